#!/usr/bin/python3
"""Checks that tests/conic_suite is what its sources make (run by ctest as conic_suite_files).

* The manifest and problems/ list the same files, each name once.
* Every problem rebuilt here from its source (netlib MPS files, transcribed data, seeded
  recipes; all but the CVXOPT book examples, whose data files are not in the project) gives the
  stored file's data exactly: the lines after the header comments, byte for byte.
Needs numpy only (no solver): the expected answers are checked when make_suite.py writes them.
"""
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from make_suite import SUITE, netlib  # noqa: E402
from problems_published import all_problems  # noqa: E402
from problems_random import all_random  # noqa: E402


def data_lines(text):
    return [line for line in text.splitlines() if not line.startswith("#")]


def main():
    errors = []
    manifest = json.load(open(os.path.join(SUITE, "manifest.json")))["problems"]
    files = [e["file"] for e in manifest]
    stored = sorted("problems/" + f for f in os.listdir(os.path.join(SUITE, "problems")) if f.endswith(".cbf"))
    if len(set(files)) != len(files):
        errors.append("the manifest names a file twice")
    if sorted(files) != stored:
        errors.append("manifest and problems/ differ: %s" % sorted(set(files) ^ set(stored)))
    rebuilt = 0
    for p in netlib() + all_problems() + all_random():
        path = os.path.join(SUITE, "problems", p.name + ".cbf")
        if not os.path.exists(path):
            errors.append("%s: no stored file" % p.name)
            continue
        if data_lines(p.cbf()) != data_lines(open(path).read()):
            errors.append("%s: the stored data differ from what its source makes" % p.name)
        rebuilt += 1
    print("%d files in the manifest, %d rebuilt from their sources, %d problems" % (len(files), rebuilt, len(errors)))
    for e in errors:
        print("ERROR " + e)
    sys.exit(1 if errors else 0)


if __name__ == "__main__":
    main()

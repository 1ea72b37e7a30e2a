#pragma once
// What a command writes, checked as a set before any work is done: every output can be
// written without replacing anything but a regular file, no two outputs are the same file
// (`--output X --log X`), and no output is one of the run's inputs (`--output` naming the
// sequence's own groundtruth.txt). Used by every subcommand that writes files.
#include <string>
#include <vector>

namespace bivo::experiments {

struct NamedPath {
  std::string role;  // the flag or argument that named it: "--output", "groundtruth", ...
  std::string path;  // empty: not given (ignored)
};

// Throws bivo::Error naming the flag and the path at fault.
void check_output_files(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs = {});

// An output folder: an existing path must be a folder; a new one must be creatable (its
// nearest existing ancestor is a folder). Throws bivo::Error naming the flag.
void check_output_folder(const NamedPath& folder);

}  // namespace bivo::experiments

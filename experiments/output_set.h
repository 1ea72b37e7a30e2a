#pragma once
// What a command writes, checked as a set before any work is done: every output can be
// written without replacing anything but a regular file, no two outputs are the same file
// (`--output X --log X`), and no output lands on one of the command's inputs (`--output`
// naming the sequence's own groundtruth.txt, an output folder inside a sequence folder).
// Paths are compared canonically and by device and inode, so symlinks, "..", hard links and
// bind mounts do not hide a collision. Used by every subcommand that writes files.
#include <string>
#include <vector>

namespace bivo::experiments {

struct NamedPath {
  std::string role;  // the flag or argument that named it: "--output", "groundtruth", ...
  std::string path;  // empty: not given (ignored)
};

// {role, path} for each path.
std::vector<NamedPath> named_paths(const std::string& role, const std::vector<std::string>& paths);

// Inputs are files or folders (a sequence): an output file is no input file and lies in no
// input folder. Throws bivo::Error naming the flag and the path at fault (both, for a collision).
void check_output_files(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs = {});

// An output folder: an existing path must be a folder; a new one must be creatable (its
// nearest existing ancestor is a folder) and writable. Against the inputs: it is no input
// folder and lies in none, and holds no input file (the command writes its files there, e.g.
// config.json). Throws bivo::Error naming the flag, and both paths for a collision.
void check_output_folder(const NamedPath& folder, const std::vector<NamedPath>& inputs = {});

}  // namespace bivo::experiments

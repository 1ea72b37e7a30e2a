#pragma once
// Outputs are written atomically: to a temporary file beside the target, then renamed,
// so a reader never sees a half-written file and a failed run leaves none behind. A rename
// replaces whatever the target path names, so the target is checked first: only a regular
// file is ever replaced, never a symlink, folder, FIFO or device node.
#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace bivo::odometry::io {

// Throws bivo::Error naming `path` unless it may receive an output: its folder exists and,
// when the path exists, it is a regular file (not a symlink, folder, FIFO, device or socket)
// and not a file this run read (see InputRegistry).
void check_output_target(const std::string& path);

// While one lives (the command line's whole run), the files read as configurations, studies,
// results and trajectories are recorded, and no output is written over one, under any name
// (`table --config out/config.json --output out` would replace its own configuration).
class InputRegistry {
 public:
  InputRegistry();
  InputRegistry(const InputRegistry&) = delete;
  InputRegistry& operator=(const InputRegistry&) = delete;
  ~InputRegistry();
};
void record_input(const std::string& path);

// Creates the output folder `dir` with its parents; bivo::Error naming it when it exists as
// something else than a folder or cannot be created.
void create_output_directory(const std::string& dir);

// Several outputs that appear together or not at all: add() checks each target and writes
// its content to a new temporary beside it; commit() renames them over their targets;
// whatever was not committed is removed when the object dies (e.g. by an exception).
class StagedOutputs {
 public:
  StagedOutputs() = default;
  StagedOutputs(const StagedOutputs&) = delete;
  StagedOutputs& operator=(const StagedOutputs&) = delete;
  ~StagedOutputs();

  void add(const std::string& path, const std::function<void(std::ostream&)>& write);
  void commit();

 private:
  std::vector<std::pair<std::string, std::string>> staged_;  // (temporary, target)
};

// One output: StagedOutputs with a single file. Throws bivo::Error naming the path when the
// target may not be replaced, the folder is missing or not writable, or a write fails.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

// Temporary path next to `path` for writers that need a file name (libpng): create it
// exclusively (fopen "wbx"), then rename with commit_temporary(), which re-checks the target.
std::string temporary_path_for(const std::string& path);
void commit_temporary(const std::string& temporary, const std::string& path);

// While one lives, every output file and folder that this process creates (not those it
// replaces) is recorded; unless keep() was called, its destructor removes them again, newest
// first, so a command that fails half-way through writing (a full disk) leaves nothing
// partial behind. One at a time; writes from any thread are recorded.
class OutputJournal {
 public:
  OutputJournal();
  OutputJournal(const OutputJournal&) = delete;
  OutputJournal& operator=(const OutputJournal&) = delete;
  ~OutputJournal();
  void keep() { keep_ = true; }

 private:
  bool keep_ = false;
};

}  // namespace bivo::odometry::io

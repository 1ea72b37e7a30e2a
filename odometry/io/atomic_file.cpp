#include "odometry/io/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <sstream>
#include <vector>

#include "odometry/io/own_temporaries.h"
#include "solvers/error.h"

namespace bivo::odometry::io {
namespace {

namespace fs = std::filesystem;

const char* kind_of(fs::file_type type) {
  switch (type) {
    case fs::file_type::symlink:
      return "a symbolic link";
    case fs::file_type::directory:
      return "a folder";
    case fs::file_type::fifo:
      return "a FIFO";
    case fs::file_type::block:
      return "a block device";
    case fs::file_type::character:
      return "a character device";
    case fs::file_type::socket:
      return "a socket";
    default:
      return "not a regular file";
  }
}

// Writes `bytes` to the new file `path` (refusing an existing one: exclusive create).
void write_new_file(const std::string& path, const std::string& target, const std::string& bytes) {
  struct Closer {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::unique_ptr<std::FILE, Closer> file(std::fopen(path.c_str(), "wbx"));
  if (!file) {
    throw Error("cannot write '" + target + "': " + std::strerror(errno));
  }
  const bool ok =
      std::fwrite(bytes.data(), 1, bytes.size(), file.get()) == bytes.size() && std::fflush(file.get()) == 0;
  const bool closed = std::fclose(file.release()) == 0;
  if (!ok || !closed) {
    const std::string why = std::strerror(errno);
    std::remove(path.c_str());
    throw Error("cannot write '" + target + "': " + why);
  }
}

// The active OutputJournal's record: paths created, oldest first, and whether each is a folder.
struct JournalState {
  std::mutex mutex;
  bool active = false;
  std::vector<std::pair<std::string, bool>> created;
};

JournalState& journal() {
  static JournalState state;
  return state;
}

struct InputState {
  std::mutex mutex;
  bool active = false;
  std::vector<std::string> paths;
};

InputState& inputs() {
  static InputState state;
  return state;
}

// The input that `path` is (the same file by identity, so a hard link counts), or "".
std::string input_at(const std::string& path) {
  InputState& in = inputs();
  std::lock_guard<std::mutex> lock(in.mutex);
  std::error_code ec;
  if (!in.active || !fs::exists(fs::symlink_status(path, ec))) return "";
  for (const std::string& input : in.paths) {
    if (fs::equivalent(path, input, ec)) return input;
  }
  return "";
}

void record_created(const std::string& path, bool folder) {
  JournalState& j = journal();
  std::lock_guard<std::mutex> lock(j.mutex);
  if (j.active) j.created.emplace_back(path, folder);
}

}  // namespace

InputRegistry::InputRegistry() {
  InputState& in = inputs();
  std::lock_guard<std::mutex> lock(in.mutex);
  in.active = true;
  in.paths.clear();
}

InputRegistry::~InputRegistry() {
  InputState& in = inputs();
  std::lock_guard<std::mutex> lock(in.mutex);
  in.active = false;
  in.paths.clear();
}

void record_input(const std::string& path) {
  InputState& in = inputs();
  std::lock_guard<std::mutex> lock(in.mutex);
  if (in.active) in.paths.push_back(path);
}

OutputJournal::OutputJournal() {
  JournalState& j = journal();
  std::lock_guard<std::mutex> lock(j.mutex);
  if (j.active) throw Error("internal: two output journals at once");
  j.active = true;
  j.created.clear();
}

OutputJournal::~OutputJournal() {
  JournalState& j = journal();
  std::lock_guard<std::mutex> lock(j.mutex);
  if (!keep_) {
    std::error_code ec;
    for (auto it = j.created.rbegin(); it != j.created.rend(); ++it) {
      // A folder goes only when empty: whatever else appeared in it meanwhile stays.
      if (it->second) {
        fs::remove(it->first, ec);
      } else if (fs::symlink_status(it->first, ec).type() == fs::file_type::regular) {
        fs::remove(it->first, ec);
      }
    }
  }
  j.created.clear();
  j.active = false;
}

void check_output_target(const std::string& path) {
  if (path.empty()) throw Error("empty output path");
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(path, ec);
  if (fs::exists(status) && status.type() != fs::file_type::regular) {
    throw Error("refusing to write '" + path + "': it is " + kind_of(status.type()) +
                ", not a regular file, and would be replaced");
  }
  if (const std::string input = input_at(path); !input.empty()) {
    throw Error("refusing to write '" + path + "': it is an input of this run ('" + input + "')");
  }
  fs::path folder = fs::path(path).parent_path();
  if (folder.empty()) folder = ".";
  if (!fs::is_directory(folder, ec)) {
    throw Error("cannot write '" + path + "': folder '" + folder.string() + "' does not exist");
  }
}

void create_output_directory(const std::string& dir) {
  if (dir.empty()) throw Error("empty output folder path");
  std::error_code ec;
  if (fs::is_directory(dir, ec)) return;
  if (fs::exists(fs::symlink_status(dir, ec))) {
    throw Error("cannot use '" + dir + "' as output folder: it exists and is not a folder");
  }
  // One level at a time, so that the journal knows which folders this run made.
  std::vector<fs::path> missing;
  for (fs::path p = fs::path(dir).lexically_normal(); !p.empty() && !fs::exists(fs::symlink_status(p, ec));
       p = p.parent_path()) {
    missing.push_back(p);
    if (p == p.root_path() || p.parent_path() == p) break;
  }
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (!fs::create_directory(*it, ec) && ec) {
      throw Error("cannot create output folder '" + dir + "': '" + it->string() + "': " + ec.message());
    }
    record_created(it->string(), true);
  }
  if (!fs::is_directory(dir, ec)) throw Error("cannot create output folder '" + dir + "'");
}

StagedOutputs::~StagedOutputs() {
  for (const auto& [temporary, target] : staged_) std::remove(temporary.c_str());
}

void StagedOutputs::add(const std::string& path, const std::function<void(std::ostream&)>& write) {
  check_output_target(path);
  remove_dead_temporaries(path);
  std::ostringstream content;
  write(content);
  if (!content) throw Error("cannot write '" + path + "': formatting failed");
  const std::string tmp = temporary_path_for(path);
  write_new_file(tmp, path, content.str());
  staged_.emplace_back(tmp, path);
}

void StagedOutputs::commit() {
  // Check every target again before the first rename: nothing is replaced unless all can be.
  for (const auto& [temporary, target] : staged_) check_output_target(target);
  while (!staged_.empty()) {
    const auto [temporary, target] = staged_.front();
    staged_.erase(staged_.begin());
    commit_temporary(temporary, target);
  }
}

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  StagedOutputs out;
  out.add(path, write);
  out.commit();
}

std::string temporary_path_for(const std::string& path) { return own_temporary_name(path); }

void commit_temporary(const std::string& temporary, const std::string& path) {
  try {
    check_output_target(path);
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
  std::error_code ec;
  const bool is_new = !fs::exists(fs::symlink_status(path, ec));
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(temporary.c_str());
    throw Error("cannot write '" + path + "': rename from temporary file failed (" + why + ")");
  }
  if (is_new) record_created(path, false);
}

}  // namespace bivo::odometry::io

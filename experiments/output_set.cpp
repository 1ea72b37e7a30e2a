#include "experiments/output_set.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <optional>

#include "odometry/io/atomic_file.h"
#include "odometry/io/own_temporaries.h"
#include "solvers/error.h"

namespace bivo::experiments {
namespace {

namespace fs = std::filesystem;

// The same file: equal canonical paths (symlinked folders, "a/../b"), or hard links.
bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  const fs::path ca = fs::weakly_canonical(fs::absolute(a, ec), ec);
  const fs::path cb = fs::weakly_canonical(fs::absolute(b, ec), ec);
  if (!ec && ca == cb) return true;
  return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec);
}

struct FileId {
  dev_t device = 0;
  ino_t inode = 0;
  bool operator==(const FileId& o) const { return device == o.device && inode == o.inode; }
};

std::optional<FileId> file_id(const fs::path& p) {
  struct stat st;
  if (::stat(p.c_str(), &st) != 0) return std::nullopt;
  return FileId{st.st_dev, st.st_ino};
}

fs::path canonical_form(const std::string& path) {
  std::error_code ec;
  const fs::path absolute = fs::absolute(path, ec);
  const fs::path canonical = fs::weakly_canonical(absolute, ec);
  return ec ? absolute.lexically_normal() : canonical;
}

// `path` is `folder` or lies below it: one of its ancestors (itself included) is the folder,
// by canonical path or, where both exist, by device and inode (a bind mount of the folder).
bool lies_in(const std::string& path, const std::string& folder) {
  const fs::path dir = canonical_form(folder);
  const std::optional<FileId> dir_id = file_id(dir);
  for (fs::path p = canonical_form(path);; p = p.parent_path()) {
    if (p == dir) return true;
    if (dir_id && file_id(p) == dir_id) return true;
    if (p.empty() || p == p.root_path() || p.parent_path() == p) return false;
  }
}

// A file of `folder` (recursively) that is `file` under another name (a hard link), or "".
std::string hard_link_in(const std::string& file, const std::string& folder) {
  struct stat st;
  if (::stat(file.c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_nlink < 2) return "";
  std::error_code ec;
  for (fs::recursive_directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code e;
    if (it->is_regular_file(e) && file_id(it->path()) == FileId{st.st_dev, st.st_ino}) return it->path().string();
  }
  return "";
}

bool is_folder(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec);
}

// Refuses an output folder that is an input folder or lies in one, or that holds an input file.
void check_folder_against_inputs(const NamedPath& out, const std::vector<NamedPath>& inputs) {
  for (const NamedPath& in : inputs) {
    std::error_code ec;
    if (in.path.empty() || !fs::exists(in.path, ec)) continue;  // nothing there to overwrite
    if (is_folder(in.path)) {
      if (lies_in(out.path, in.path)) {
        throw Error(out.role + " '" + out.path + "' " + (same_file(out.path, in.path) ? "is" : "lies in") + " " +
                    in.role + " '" + in.path + "', an input of this command; write the outputs outside the inputs");
      }
      continue;
    }
    std::string inside = lies_in(in.path, out.path) ? in.path : "";
    if (inside.empty() && is_folder(out.path)) inside = hard_link_in(in.path, out.path);
    if (!inside.empty()) {
      throw Error(in.role + " '" + in.path + "', an input of this command, " +
                  (inside == in.path ? "lies in" : "is '" + inside + "' (a hard link) in") + " " + out.role + " '" +
                  out.path + "', where the command writes its files; keep the inputs outside the output folder");
    }
  }
}

}  // namespace

std::vector<NamedPath> named_paths(const std::string& role, const std::vector<std::string>& paths) {
  std::vector<NamedPath> out;
  for (const std::string& p : paths) out.push_back({role, p});
  return out;
}

void check_output_files(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs) {
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    const NamedPath& out = outputs[k];
    if (out.path.empty()) continue;
    try {
      odometry::io::check_output_target(out.path);
    } catch (const Error& e) {
      throw Error(out.role + ": " + e.what());
    }
    for (std::size_t j = 0; j < k; ++j) {
      if (!outputs[j].path.empty() && same_file(outputs[j].path, out.path)) {
        throw Error(out.role + " '" + out.path + "' and " + outputs[j].role + " '" + outputs[j].path +
                    "' are the same file; give each output its own path");
      }
    }
    for (const NamedPath& in : inputs) {
      // A hard link to an input has a name of its own: compared by file identity too.
      if (in.path.empty()) continue;
      if (is_folder(in.path)) {
        if (lies_in(out.path, in.path)) {
          throw Error(out.role + " '" + out.path + "' lies in " + in.role + " '" + in.path +
                      "', an input of this command; write the outputs outside the inputs");
        }
        continue;
      }
      if (same_file(in.path, out.path)) {
        throw Error(out.role + " '" + out.path + "' is an input of this run (" + in.role + " '" + in.path +
                    "'); refusing to overwrite it");
      }
    }
  }
}

void check_output_folder(const NamedPath& folder, const std::vector<NamedPath>& inputs) {
  if (folder.path.empty()) throw Error(folder.role + ": empty folder path");
  check_folder_against_inputs(folder, inputs);
  std::error_code ec;
  fs::path p = fs::absolute(folder.path, ec);
  if (fs::exists(p, ec)) {
    if (!fs::is_directory(p, ec)) throw Error(folder.role + " '" + folder.path + "' exists and is not a folder");
  } else {
    // Nearest existing ancestor must be a folder, or create_directories fails half-way.
    for (p = p.parent_path(); !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
      if (p == p.root_path()) break;
    }
    if (!p.empty() && fs::exists(p, ec) && !fs::is_directory(p, ec)) {
      throw Error(folder.role + " '" + folder.path + "' cannot be created: '" + p.string() + "' is not a folder");
    }
  }
  // Whether anything can be made there (read-only filesystem, /proc, permissions) is only
  // known by trying: a probe folder, removed at once, before hours of work are spent.
  const fs::path probe = odometry::io::own_temporary_name((p / ".bivo-probe").string());
  if (::mkdir(probe.c_str(), 0700) != 0) {
    throw Error(folder.role + " '" + folder.path + "' cannot be written: '" + p.string() +
                "': " + std::strerror(errno));
  }
  ::rmdir(probe.c_str());
}

}  // namespace bivo::experiments

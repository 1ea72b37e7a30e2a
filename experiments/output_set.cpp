#include "experiments/output_set.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

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

}  // namespace

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
      if (same_file(in.path, out.path)) {
        throw Error(out.role + " '" + out.path + "' is an input of this run (" + in.role + " '" + in.path +
                    "'); refusing to overwrite it");
      }
    }
  }
}

void check_output_folder(const NamedPath& folder) {
  if (folder.path.empty()) throw Error(folder.role + ": empty folder path");
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

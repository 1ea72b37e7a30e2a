#include "odometry/io/staged_folder.h"

#include <fcntl.h>
#include <linux/fs.h>
#include <stdio.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "odometry/io/atomic_file.h"
#include "odometry/io/own_temporaries.h"
#include "solvers/error.h"

namespace bivo::odometry::io {

const char kOutputMarker[] = ".bivo-output";

namespace {

namespace fs = std::filesystem;

const char kOwnerFile[] = ".bivo-owner";

void write_small_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  if (!out) throw Error("cannot write '" + path.string() + "': " + std::strerror(errno));
}

std::string read_small_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string text(256, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  return text;
}

// rename() that never replaces an existing target (a folder made there meanwhile).
void rename_no_replace(const fs::path& from, const fs::path& to) {
  int rc = ::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE);
  if (rc != 0 && (errno == EINVAL || errno == ENOSYS)) {  // a filesystem without the flag
    std::error_code ec;
    if (fs::exists(fs::symlink_status(to, ec))) {
      errno = EEXIST;
    } else {
      rc = std::rename(from.c_str(), to.c_str());
    }
  }
  if (rc != 0) {
    throw Error("cannot move '" + from.string() + "' to '" + to.string() + "': " + std::strerror(errno));
  }
}

// Temporary folders of `target` left by runs that died: named as own temporaries, real
// folders, holding an owner record of a process of this host that is gone.
void remove_dead_temporary_folders(const fs::path& target) {
  std::error_code ec;
  const std::string prefix = target.filename().string() + ".tmp-bivo.";
  fs::directory_iterator it(target.parent_path().empty() ? fs::path(".") : target.parent_path(), ec);
  for (; !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::error_code e;
    if (name.compare(0, prefix.size(), prefix) != 0 || it->is_symlink(e) || !it->is_directory(e)) continue;
    const fs::path owner = it->path() / kOwnerFile;
    if (fs::symlink_status(owner, e).type() != fs::file_type::regular) continue;
    if (owner_is_dead(read_small_file(owner))) fs::remove_all(it->path(), e);
  }
}

}  // namespace

bool is_own_folder(const std::string& dir) {
  std::error_code ec;
  return fs::symlink_status(dir, ec).type() == fs::file_type::directory &&
         fs::symlink_status(fs::path(dir) / kOutputMarker, ec).type() == fs::file_type::regular;
}

void check_folder_target(const std::string& target, bool replace_own) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(target, ec);
  if (!fs::exists(status)) return;
  if (status.type() == fs::file_type::symlink) {
    throw Error("refusing to write '" + target + "': it is a symbolic link and would be replaced");
  }
  if (status.type() != fs::file_type::directory) {
    throw Error("refusing to write '" + target + "': it exists and is not a folder");
  }
  if (!is_own_folder(target)) {
    throw Error("refusing to replace '" + target + "': it exists and was not written by bivo (no " + kOutputMarker +
                " file); move it away or choose another name");
  }
  if (!replace_own) {
    throw Error("refusing to replace '" + target + "': it exists (written by bivo; --force replaces it)");
  }
}

StagedFolder::StagedFolder(const std::string& target, const std::string& writer, bool replace_own)
    : target_(target), writer_(writer), replace_own_(replace_own) {
  if (fs::path(target).filename().empty()) throw Error("output folder '" + target + "' has no name");
  check_folder_target(target, replace_own);
  const fs::path parent = fs::path(target).parent_path();
  create_output_directory(parent.empty() ? "." : parent.string());
  remove_dead_temporary_folders(target);
  const std::string temporary = own_temporary_name(target);
  std::error_code ec;
  if (!fs::create_directory(temporary, ec) || ec) {
    throw Error("cannot create a folder beside '" + target +
                "': " + (ec ? ec.message() : std::string("a file of that name exists")));
  }
  temporary_ = temporary;
  write_small_file(fs::path(temporary_) / kOwnerFile, owner_record());
}

StagedFolder::~StagedFolder() {
  if (committed_ || temporary_.empty()) return;
  std::error_code ec;
  fs::remove_all(temporary_, ec);
}

void StagedFolder::commit() {
  write_small_file(fs::path(temporary_) / kOutputMarker, "written by " + writer_ + "\n");
  check_folder_target(target_, replace_own_);
  std::error_code ec;
  // The owner record stays until the rename: a run killed before it leaves a removable temporary.
  if (!fs::exists(fs::symlink_status(target_, ec))) {
    rename_no_replace(temporary_, target_);
    committed_ = true;
    fs::remove(fs::path(target_) / kOwnerFile, ec);
    return;
  }
  // Replacing our own folder: it becomes an owned temporary first, so a crash between the
  // two renames leaves a folder the next run removes, never a half-replaced target.
  write_small_file(fs::path(target_) / kOwnerFile, owner_record());
  const std::string old = own_temporary_name(target_);
  rename_no_replace(target_, old);
  try {
    rename_no_replace(temporary_, target_);
  } catch (...) {
    std::rename(old.c_str(), target_.c_str());
    fs::remove(fs::path(target_) / kOwnerFile, ec);
    throw;
  }
  committed_ = true;
  fs::remove(fs::path(target_) / kOwnerFile, ec);
  fs::remove_all(old, ec);
}

}  // namespace bivo::odometry::io

#pragma once
// A folder written whole or not at all, never over one bivo did not write: the content goes
// into a fresh temporary folder beside the target (owned: see own_temporaries.h), which is
// renamed into place only when the target does not exist or, with `replace_own`, when the
// target is a real folder (not a symlink) holding the marker file a previous commit left.
#include <string>

namespace bivo::odometry::io {

// Name of the marker file in every folder a StagedFolder committed.
extern const char kOutputMarker[];

// True when `dir` is a folder (not a symlink) holding a regular-file marker.
bool is_own_folder(const std::string& dir);

// Throws bivo::Error naming `target` unless a StagedFolder may commit to it (see above).
void check_folder_target(const std::string& target, bool replace_own);

class StagedFolder {
 public:
  // Checks the target, removes the temporaries of dead runs on it, creates the temporary.
  StagedFolder(const std::string& target, const std::string& writer, bool replace_own);
  StagedFolder(const StagedFolder&) = delete;
  StagedFolder& operator=(const StagedFolder&) = delete;
  ~StagedFolder();  // removes the temporary unless committed

  const std::string& path() const { return temporary_; }  // write the content here
  void commit();

 private:
  std::string target_, temporary_, writer_;
  bool replace_own_ = false, committed_ = false;
};

}  // namespace bivo::odometry::io

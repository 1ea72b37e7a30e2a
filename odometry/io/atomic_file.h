#pragma once
// Outputs are written atomically: to a temporary file beside the target, then renamed,
// so a reader never sees a half-written file and a failed run leaves none behind.
#include <functional>
#include <ostream>
#include <string>

namespace bivo::odometry::io {

// Calls write(stream) on a temporary file next to `path`, then renames it to `path`.
// Throws bivo::Error naming the path when the directory is unwritable or a write fails.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

// Temporary path next to `path` for writers that need a file name (libpng); rename with
// commit_temporary(). Throws bivo::Error on failure.
std::string temporary_path_for(const std::string& path);
void commit_temporary(const std::string& temporary, const std::string& path);

}  // namespace bivo::odometry::io

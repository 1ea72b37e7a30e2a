#pragma once
// Temporaries that bivo can prove are its own: their name (files) or an owner file (folders)
// records the host and process that made them, so the next run on the same output removes
// those of a process that died (SIGKILL, power loss) and nothing else: a file or folder a
// user named like a temporary carries no such record and is never touched.
#include <string>

namespace bivo::odometry::io {

// "<path>.tmp-bivo.<pid>.<random>.<host>": a fresh temporary name beside `path`.
std::string own_temporary_name(const std::string& path);

// Removes the temporaries in the folder of `path` (files named by own_temporary_name) whose
// process ran on this host and is gone; each folder is looked at once per process. Never
// follows a symlink, never removes a folder.
void remove_dead_temporaries(const std::string& path);

// The owner record of a temporary folder: "<host>\n<pid>\n".
std::string owner_record();

// True when `record` names a process of this host that no longer runs.
bool owner_is_dead(const std::string& record);

}  // namespace bivo::odometry::io

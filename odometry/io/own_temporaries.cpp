#include "odometry/io/own_temporaries.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <filesystem>
#include <mutex>
#include <random>
#include <set>
#include <sstream>

namespace bivo::odometry::io {
namespace {

namespace fs = std::filesystem;

const char kTag[] = ".tmp-bivo.";

std::string host_name() {
  char buf[HOST_NAME_MAX + 1] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0) return "unknown-host";
  return buf;
}

// A pid this host no longer runs: kill(pid, 0) fails with ESRCH (EPERM means it runs).
bool process_is_gone(long pid) {
  if (pid <= 0 || pid > INT_MAX) return false;
  return ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

// Parses "<pid>.<random>.<host>"; false when it is not of that form.
bool parse_tail(const std::string& tail, long* pid, std::string* host) {
  const auto a = tail.find('.');
  if (a == std::string::npos || a == 0) return false;
  const auto b = tail.find('.', a + 1);
  if (b == std::string::npos || b == a + 1 || b + 1 >= tail.size()) return false;
  for (std::size_t k = 0; k < a; ++k) {
    if (tail[k] < '0' || tail[k] > '9') return false;
  }
  if (a > 9) return false;
  *pid = std::stol(tail.substr(0, a));
  *host = tail.substr(b + 1);
  return true;
}

}  // namespace

std::string own_temporary_name(const std::string& path) {
  std::random_device rd;
  std::ostringstream s;
  s << path << kTag << ::getpid() << '.' << std::hex << rd() << rd() << '.' << host_name();
  return s.str();
}

void remove_dead_temporaries(const std::string& path) {
  std::error_code ec;
  fs::path folder = fs::path(path).parent_path();
  if (folder.empty()) folder = ".";
  {
    // Once per folder and process: a study writes thousands of files into one folder.
    static std::mutex mutex;
    static std::set<std::string> scanned;
    std::lock_guard<std::mutex> lock(mutex);
    if (!scanned.insert(fs::absolute(folder, ec).lexically_normal().string()).second) return;
  }
  const std::string host = host_name();
  fs::directory_iterator it(folder, ec);
  for (; !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const auto at = name.rfind(kTag);
    if (at == std::string::npos || at == 0) continue;
    long pid = 0;
    std::string owner_host;
    if (!parse_tail(name.substr(at + sizeof kTag - 1), &pid, &owner_host)) continue;
    std::error_code status_ec;
    if (!it->is_regular_file(status_ec) || it->is_symlink(status_ec)) continue;
    if (owner_host == host && process_is_gone(pid)) fs::remove(it->path(), status_ec);
  }
}

std::string owner_record() { return host_name() + "\n" + std::to_string(::getpid()) + "\n"; }

bool owner_is_dead(const std::string& record) {
  std::istringstream in(record);
  std::string host, pid_text, rest;
  if (!std::getline(in, host) || !std::getline(in, pid_text) || std::getline(in, rest)) return false;
  if (host != host_name() || pid_text.empty() || pid_text.size() > 9) return false;
  for (char c : pid_text) {
    if (c < '0' || c > '9') return false;
  }
  return process_is_gone(std::stol(pid_text));
}

}  // namespace bivo::odometry::io

#include "experiments/plotting.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "odometry/io/atomic_file.h"
#include "solvers/error.h"

namespace bivo::experiments {
namespace {

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

std::string plots_dir() {
  if (const char* env = std::getenv("BIVO_PLOTS_DIR")) return env;
  // Installed: beside the executable (bin/../share/bivo/plots); a build tree has none there
  // and uses the source tree's.
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path installed = exe.parent_path() / BIVO_PLOTS_FROM_BINDIR;
    if (std::filesystem::is_regular_file(installed / "common.py", ec)) return installed.lexically_normal().string();
  }
  if (std::filesystem::is_regular_file(std::filesystem::path(BIVO_PLOTS_DIR) / "common.py", ec)) {
    return BIVO_PLOTS_DIR;
  }
  throw Error("the plot scripts are neither beside bivo (" +
              (exe.parent_path() / BIVO_PLOTS_FROM_BINDIR).lexically_normal().string() + ") nor in the source tree (" +
              BIVO_PLOTS_DIR + "); set BIVO_PLOTS_DIR to the folder of experiments/plots/*.py, or give --no-plots");
}

void plot(const std::string& script, const std::vector<std::string>& args) {
  const std::string python = "/usr/bin/python3";
  if (::access(python.c_str(), X_OK) != 0) throw Error("plotting needs " + python + " (with matplotlib)");
  const std::string log = odometry::io::temporary_path_for("/tmp/bivo_plot_stderr");
  std::string cmd = python + " " + shell_quote(plots_dir() + "/" + script);
  for (const auto& a : args) cmd += " " + shell_quote(a);
  cmd += " 2>" + shell_quote(log);
  const int raw = std::system(cmd.c_str());
  std::ifstream in(log);
  std::stringstream err;
  err << in.rdbuf();
  std::remove(log.c_str());
  if (raw != 0) {
    std::string tail = err.str();
    if (tail.size() > 800) tail = "..." + tail.substr(tail.size() - 800);
    throw Error("plot script " + script + " failed (status " + std::to_string(WIFEXITED(raw) ? WEXITSTATUS(raw) : -1) +
                "): " + tail);
  }
}

}  // namespace bivo::experiments

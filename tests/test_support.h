#pragma once
// Helpers shared by the test files.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <Eigen/Core>

#include "solvers/error.h"
#include "solvers/step_backend.h"

namespace bivo::testing {

// The file's bytes ("" when it cannot be read).
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh folder under the system temp directory, named after the test and the process,
// removed with everything in it when the test ends.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The message of the bivo::Error that f() throws, or "" when it throws none (other
// exceptions propagate and fail the test).
template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// |got - want| / max(1, |want|): relative error that stays absolute near zero.
inline double rel_err(const Eigen::VectorXd& got, const Eigen::VectorXd& want) {
  return (got - want).norm() / std::max(1.0, want.norm());
}

// The epsilon-constraint step subproblem of a linearization.
inline solvers::Subproblem eps_subproblem(const solvers::Linearization& lin, double epsilon) {
  solvers::Subproblem sp;
  sp.kind = solvers::ScalarizationKind::kEpsilonConstraint;
  sp.lin = &lin;
  sp.epsilon = epsilon;
  return sp;
}

// A PNG cut short: the signature, an IHDR (valid CRC) claiming width x height 8-bit RGB and
// the first bytes of image data (4 bytes of zlib stream, no IEND), what a hostile or
// truncated file looks like to a reader.
inline std::string png_header_only(std::uint32_t width, std::uint32_t height) {
  const auto be32 = [](std::uint32_t v) {
    return std::string{char(v >> 24), char((v >> 16) & 0xFF), char((v >> 8) & 0xFF), char(v & 0xFF)};
  };
  const auto crc32 = [](const std::string& bytes) {  // ISO 3309, as zlib's crc32
    std::uint32_t c = 0xFFFFFFFFu;
    for (unsigned char b : bytes) {
      c ^= b;
      for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return c ^ 0xFFFFFFFFu;
  };
  const auto chunk = [&](const std::string& type, const std::string& data) {
    return be32(static_cast<std::uint32_t>(data.size())) + type + data + be32(crc32(type + data));
  };
  const std::string ihdr = be32(width) + be32(height) + std::string("\x08\x02\x00\x00\x00", 5);
  return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + chunk("IDAT", std::string("\x78\x9c\x63\x00", 4));
}

// Exit status and output of one run of the built `bivo` (BIVO_BINARY).
struct BivoRun {
  int status = -1;  // exit code; -1 when killed by a signal (a crash)
  std::string out, err;
};

// Runs `bivo <args>` (args are shell words, quote paths), capturing stdout and stderr through
// files in `scratch_dir`.
inline BivoRun run_bivo_in(const std::string& args, const std::string& scratch_dir) {
  const std::string out = scratch_dir + "/bivo_stdout.txt", err = scratch_dir + "/bivo_stderr.txt";
  const std::string cmd = std::string("'") + BIVO_BINARY + "' " + args + " >'" + out + "' 2>'" + err + "'";
  const int raw = std::system(cmd.c_str());
  BivoRun r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  const auto slurp = [](const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  r.out = slurp(out);
  r.err = slurp(err);
  std::remove(out.c_str());
  std::remove(err.c_str());
  return r;
}

}  // namespace bivo::testing

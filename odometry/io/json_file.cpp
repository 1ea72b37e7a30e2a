#include "odometry/io/json_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "odometry/io/atomic_file.h"
#include "solvers/error.h"

namespace bivo::odometry::io {

nlohmann::json read_json_file(const std::string& path, const std::string& what, int max_depth) {
  using json = nlohmann::json;
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error(what + " '" + path + "' is a folder, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open " + what + " '" + path + "': " + std::strerror(errno));
  // The callback throws out of the parser, which then unwinds what it has built.
  struct TooDeep {};
  try {
    json j = json::parse(in, [max_depth](int depth, json::parse_event_t, json&) {
      if (depth > max_depth) throw TooDeep{};
      return true;
    });
    record_input(path);  // read whole: this run must not write over it
    return j;
  } catch (const TooDeep&) {
    throw Error(path + ": values nested more than " + std::to_string(max_depth) + " levels deep");
  } catch (const json::exception& e) {
    throw Error(path + ": not valid JSON (" + e.what() + ")");
  }
}

}  // namespace bivo::odometry::io

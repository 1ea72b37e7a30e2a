#pragma once
// The one way bivo reads a JSON file (configurations, studies, unit results, conic problems):
// a folder, an unreadable file, invalid JSON and values nested deeper than the format needs
// are bivo::Error naming the file. The depth is limited while parsing, so no later recursion
// (checks, messages, destruction) ever meets a document nested thousands of levels deep.
#include <string>

#include <nlohmann/json.hpp>

namespace bivo::odometry::io {

// Deep enough for every file bivo writes (a unit result nests about ten levels).
constexpr int kMaxJsonDepth = 64;

// `what` names the kind of file in errors ("study file", "tracker configuration").
nlohmann::json read_json_file(const std::string& path, const std::string& what, int max_depth = kMaxJsonDepth);

}  // namespace bivo::odometry::io

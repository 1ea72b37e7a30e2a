#include "odometry/io/tum_text.h"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>

#include "odometry/io/input_limits.h"
#include "solvers/error.h"

namespace bivo::odometry::io {

void for_each_tum_line(const std::string& path, const std::string& what,
                       const std::function<void(const TumTextLine&)>& on_line) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open " + what + " '" + path + "'");
  TumTextLine l;
  std::int64_t entries = 0;
  while (std::getline(in, l.raw)) {
    ++l.line_no;
    if (!l.raw.empty() && l.raw.back() == '\r') l.raw.pop_back();
    const auto first = l.raw.find_first_not_of(" \t");
    if (first == std::string::npos || l.raw[first] == '#') continue;
    check_list_size(++entries, what + " '" + path + "'");
    std::istringstream s(l.raw);
    l.tokens.clear();
    for (std::string t; s >> t;) l.tokens.push_back(t);
    on_line(l);
  }
  // A folder opens as a stream on Linux but fails on the first read.
  if (in.bad() || (!in.eof() && in.fail())) throw Error("cannot read " + what + " '" + path + "'");
}

std::string excerpt(const std::string& text) {
  constexpr std::size_t kMax = 80;
  return text.size() <= kMax ? text : text.substr(0, kMax) + "...";
}

std::string tum_line_error(const std::string& path, int line_no, const std::string& message) {
  return path + ":" + std::to_string(line_no) + ": " + message;
}

double parse_tum_number(const std::string& token, const std::string& path, int line_no, const std::string& what) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(token, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != token.size() || !std::isfinite(v)) {
    throw Error(tum_line_error(path, line_no, "'" + excerpt(token) + "' is not " + what));
  }
  return v;
}

}  // namespace bivo::odometry::io

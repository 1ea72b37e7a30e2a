#pragma once
// The TUM text formats (rgb.txt, depth.txt, groundtruth.txt, trajectories): whitespace-
// separated fields, '#' comments and blank lines ignored, CRLF tolerated. One reader for
// every such file, so each format only says what a data line holds.
#include <functional>
#include <string>
#include <vector>

namespace bivo::odometry::io {

struct TumTextLine {
  std::vector<std::string> tokens;
  int line_no = 0;
  std::string raw;  // the line as read, for error messages
};

// Calls on_line for every data line. Throws bivo::Error "cannot open/read <what> '<path>'",
// and when the file has more data lines than input_limits().max_list_entries.
void for_each_tum_line(const std::string& path, const std::string& what,
                       const std::function<void(const TumTextLine&)>& on_line);

// `text` cut to at most 80 characters ("..." appended): what error messages quote of a
// line or token, so that a message stays short whatever the input holds.
std::string excerpt(const std::string& text);

// "<path>:<line>: <message>", the prefix of every parse error.
std::string tum_line_error(const std::string& path, int line_no, const std::string& message);

// A finite number filling the whole token, else bivo::Error "<path>:<line>: '<token>' is not
// <what>".
double parse_tum_number(const std::string& token, const std::string& path, int line_no, const std::string& what);

}  // namespace bivo::odometry::io

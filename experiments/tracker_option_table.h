#pragma once
// The one list of tracker options: every field of odometry::TrackerOptions with its JSON key,
// command-line flag, Python keyword, type, valid range and help. The configuration reader and
// writer (tracker_config.h), the command-line flags (cli/tracker_flags.h) and the Python
// keyword arguments (python/odometry_bindings.cpp) are all built from it, and a value from
// any of them is checked by apply_tracker_option(), so a flag, a file and a Python dict accept
// and refuse the same values with the same message ("policy.phi: -1 is outside [0, inf]"),
// and whatever a run accepted writes a configuration that replays.
//
// Defaults are not repeated here: they are TrackerOptions{}'s, read through `get`.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "odometry/tracker.h"

namespace bivo::experiments {

enum class OptionType {
  kNumber,          // finite double in [lo, hi] (or (lo, hi] with lo_open)
  kInteger,         // int in [lo, hi]
  kBoolean,         // true / false
  kString,          // free text (method and backend names are checked by odometry::validate)
  kName,            // an enum by its name; `set` parses it and its error lists the valid names
  kOptionalNumber,  // a kNumber or null (absent)
  kIntrinsics,      // null or {"fx", "fy", "cx", "cy"}, all four; flag text "fx fy cx cy"
  kDistortion,      // null or {"k1", "k2", "p1", "p2", "k3"}, all five; flag text "k1 k2 p1 p2 k3" or "none"
};

struct TrackerOption {
  std::string key;   // JSON path, dots between nesting levels: "problem.weights.nu"
  std::string flag;  // "--nu"; empty: no flag (set by other flags or by the method)
  OptionType type = OptionType::kNumber;
  double lo = 0.0, hi = 0.0;         // range of numbers and integers
  bool lo_open = false;              // lo itself excluded
  std::optional<double> auto_value;  // a number accepted outside the range: "the method's own"
  std::string help;
  std::string method;  // the method the option belongs to ("" = every method); its flag is refused with another
  nlohmann::json (*get)(const odometry::TrackerOptions&) = nullptr;
  // Stores a value already checked against type and range (kName: parses, may throw).
  void (*set)(odometry::TrackerOptions&, const nlohmann::json&) = nullptr;

  // The Python keyword that names this option flat (bivo.track(path, nu=3)): the flag without
  // its dashes, '-' as '_'; the nested JSON form (problem={"weights": {"nu": 3}}) works too.
  std::string python_name() const;
  // "[0, inf]", "(0, inf]", "true/false", "a name", ...
  std::string range_text() const;
};

const std::vector<TrackerOption>& tracker_option_table();
// The entry with this JSON key / flag / Python name, or nullptr.
const TrackerOption* find_tracker_option_by_key(const std::string& key);
const TrackerOption* find_tracker_option_by_flag(const std::string& flag);
const TrackerOption* find_tracker_option_by_python_name(const std::string& name);

// The one check of every source: type and range of `value`, then the field set. Throws
// bivo::Error "<key>: <why>" (the caller prefixes its source: a file, a flag, "tracker options").
void apply_tracker_option(const TrackerOption& option, const nlohmann::json& value, odometry::TrackerOptions& o);

// The JSON value a flag's text stands for ("-2" -> -2.0, "true" -> true, "fx fy cx cy" ->
// {"fx": ..}); text that is not of the option's type becomes a value apply_tracker_option
// refuses with the same message as the file would (a string where a number belongs).
nlohmann::json tracker_flag_value(const TrackerOption& option, const std::string& text);

// A number as written in messages: the shortest text that reads back to the same double.
std::string format_option_number(double v);

}  // namespace bivo::experiments

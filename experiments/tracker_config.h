#pragma once
// The complete tracker configuration as JSON: what `bivo run --config FILE` reads, what every
// output folder gets next to its results, and the tracker part of a study file. Every field
// of odometry::TrackerOptions (with its RgbdProblemOptions, WeightOptions and
// PolicyParameters) has a key; enums are their names, absent optionals are null:
//
//   {"method": "weighted", "backend": "", "levels": 4, "finest_level": 0,
//    "initial_guess": "constant-velocity", "max_iterations": 20, ...,
//    "policy": {"lambda": 1e5, "phi": 100, ..., "eps": null},
//    "problem": {"min_depth": 0.1, ..., "weights": {"kind": "tdist", "nu": 5, ...}},
//    "intrinsics": null | {"fx": .., "fy": .., "cx": .., "cy": ..}}
//
// Reading is strict: an unknown key, a value of the wrong type or out of range is a
// bivo::Error naming the file and the key path ("cfg.json: policy.phi: ..."); keys that are
// absent keep the values of `base`. Doubles are written so that they read back bit-exactly,
// so flags -> file -> run gives identical results.
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "odometry/tracker.h"

namespace bivo::experiments {

nlohmann::json tracker_options_to_json(const odometry::TrackerOptions& options);

// `where` names the source in errors (a file path, "study.json: tracker", ...). The result is
// checked with odometry::validate().
odometry::TrackerOptions tracker_options_from_json(const nlohmann::json& j, const std::string& where,
                                                   const odometry::TrackerOptions& base = {});

odometry::TrackerOptions read_tracker_config(const std::string& path, const odometry::TrackerOptions& base = {});
// Whether the file (read by read_tracker_config without error) has a "method" key.
bool tracker_config_names_method(const std::string& path);
// Written atomically, pretty-printed.
void write_tracker_config(const std::string& path, const odometry::TrackerOptions& options);

}  // namespace bivo::experiments

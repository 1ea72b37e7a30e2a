#include "odometry/io/sensor_description.h"

#include <cmath>
#include <filesystem>

#include "odometry/io/json_file.h"
#include "solvers/error.h"

namespace bivo::odometry::io {

namespace {

// scene.json's sensor_defects.<key> when stated; bivo::Error naming the file, the key and the
// value unless it is a number in [lo, hi] (hi excluded when `open_above`).
std::optional<double> stated_defect(const std::string& directory, const char* key, double lo, double hi,
                                    bool open_above, const char* what) {
  const std::string path = sensor_description_path(directory);
  if (!std::filesystem::is_regular_file(path)) return std::nullopt;
  const nlohmann::json scene = read_json_file(path, "sequence description");
  if (!scene.is_object()) return std::nullopt;
  const auto defects = scene.find("sensor_defects");
  if (defects == scene.end() || !defects->is_object()) return std::nullopt;
  const auto value = defects->find(key);
  if (value == defects->end()) return std::nullopt;
  const double x = value->is_number() ? value->get<double>() : std::nan("");
  if (!(x >= lo && (open_above ? x < hi : x <= hi))) {
    throw Error(path + ": sensor_defects." + key + ": " + value->dump() + " is not " + what);
  }
  return x;
}

}  // namespace

std::string sensor_description_path(const std::string& directory) {
  return (std::filesystem::path(directory) / "scene.json").string();
}

std::optional<double> stated_readout_time(const std::string& directory) {
  return stated_defect(directory, "readout_s", 0.0, 1.0, false, "a readout time in [0, 1] s");
}

std::optional<double> stated_vignetting(const std::string& directory) {
  return stated_defect(directory, "vignetting", 0.0, 1.0, true, "a fall-off in [0, 1)");
}

}  // namespace bivo::odometry::io

#include "odometry/io/sensor_description.h"

#include <cmath>
#include <filesystem>

#include "odometry/io/json_file.h"
#include "solvers/error.h"

namespace bivo::odometry::io {

std::string sensor_description_path(const std::string& directory) {
  return (std::filesystem::path(directory) / "scene.json").string();
}

std::optional<double> stated_readout_time(const std::string& directory) {
  const std::string path = sensor_description_path(directory);
  if (!std::filesystem::is_regular_file(path)) return std::nullopt;
  const nlohmann::json scene = read_json_file(path, "sequence description");
  if (!scene.is_object()) return std::nullopt;
  const auto defects = scene.find("sensor_defects");
  if (defects == scene.end() || !defects->is_object()) return std::nullopt;
  const auto readout = defects->find("readout_s");
  if (readout == defects->end()) return std::nullopt;
  const double s = readout->is_number() ? readout->get<double>() : std::nan("");
  if (!(s >= 0.0 && s <= 1.0)) {
    throw Error(path + ": sensor_defects.readout_s: " + readout->dump() + " is not a readout time in [0, 1] s");
  }
  return s;
}

}  // namespace bivo::odometry::io

#pragma once
// What a sequence states about its sensor beyond the TUM lists: bivo synth writes it to
// scene.json beside them (odometry/synth/sequence.h). Real TUM sequences have none.
#include <optional>
#include <string>

namespace bivo::odometry::io {

// The file a sequence's sensor description is read from: directory/scene.json.
std::string sensor_description_path(const std::string& directory);

// The colour camera's rolling-shutter readout [s] (scene.json "sensor_defects"."readout_s"),
// when the sequence states one; none without the file or the key. Throws bivo::Error naming
// the file on invalid JSON and the key and value on anything but a number in [0, 1].
std::optional<double> stated_readout_time(const std::string& directory);
// The colour camera's fall-off k of 1 - k rho^2 (scene.json "sensor_defects"."vignetting",
// vignetting.h), when stated; the same errors, for anything but a number in [0, 1).
std::optional<double> stated_vignetting(const std::string& directory);

}  // namespace bivo::odometry::io

#pragma once
// The stress set: synthetic sequences with the real sensor defects of defects.h, crossed
// with structure x texture, so methods tuned on clean renderings can be tried on data they
// were not tuned on (`bivo synth --stress-set`, docs/synthetic.md "Sensor defects").
//
//   for (const synth::StressSequence& s : synth::stress_set()) { ... s.options ... }
//   auto dirs = synth::render_stress_set("../shared/data/trajectories", "/work/stressset");
//
// Two defect profiles x structure/nostructure x texture/notexture = 8 sequences, and three
// more textured deep views along other real motions (11 in all):
//  * deep: far background (median depth ~2.5-3 m, much beyond 3 m), biased and misregistered
//    unsynchronized depth, vignetting and auto-exposure, real fr3 motion;
//  * fast: generated shaking motion of ~6 deg and ~4 cm per frame, rolling shutter and motion
//    blur, the same depth and image defects, near scenes.
#include <string>
#include <vector>

#include "odometry/synth/sequence.h"

namespace bivo::odometry::synth {

inline constexpr int kStressFrames = 300;

struct StressSequence {
  std::string name;        // folder name, "rgbd_dataset_freiburg3_stress_<profile>_<category>"
  std::string trajectory;  // TUM ground-truth file in the trajectories folder; empty = generated
  SynthOptions options;    // everything the sequence is rendered with (frames = kStressFrames)
};

// The 11 sequences, deep first; `frames` overrides kStressFrames (short sets for tests).
std::vector<StressSequence> stress_set(int frames = kStressFrames);

// The defects both profiles share (values and sources: docs/synthetic.md).
SensorDefects stress_depth_and_image_defects();

// Sets o's defects, depth model, layout (from o.category) and generated motion to the
// stress profile "deep" or "fast" (throws bivo::Error on another name), so the profile can
// be rendered along any motion (`bivo synth --stress-profile`).
void apply_stress_profile(const std::string& profile, SynthOptions& o);

// Renders the set (or the entries whose name contains `only`) into output_dir and writes
// output_dir/stress_set.json (definition + digest of every folder). Returns the folders.
// Existing sequence folders are refused before any rendering (`replace_own_folder`: see SynthOptions).
std::vector<std::string> render_stress_set(const std::string& trajectories_dir, const std::string& output_dir,
                                           int frames = kStressFrames, const std::string& only = "", int threads = 0,
                                           bool replace_own_folder = false);

}  // namespace bivo::odometry::synth

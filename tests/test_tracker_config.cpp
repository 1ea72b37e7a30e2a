// experiments/tracker_config.h: every TrackerOptions field survives options -> JSON -> file ->
// options bit-exactly, and bad files are refused naming the file and the key path.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "experiments/tracker_config.h"
#include "experiments/tracker_option_table.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;
using bivo::experiments::read_tracker_config;
using bivo::experiments::tracker_options_from_json;
using bivo::experiments::tracker_options_to_json;
using bivo::experiments::write_tracker_config;
using bivo::odometry::TrackerOptions;
using bivo::testing::error_of;
using json = nlohmann::json;

namespace {

// Every field away from its default, doubles that need all 17 digits.
TrackerOptions unusual_options() {
  TrackerOptions o;
  o.method = "bounded";
  o.backend = "ipm-compressed";
  o.levels = 3;
  o.finest_level = 1;
  o.initial_guess = bivo::odometry::InitialGuess::kIdentity;
  o.max_iterations = 7;
  o.step_tolerance = 0.1 + 0.2;
  o.relative_decrease_tolerance = 1.0 / 3.0;
  o.pixel_motion_tolerance = 0.1 + 0.7;
  o.step_extrapolation = 1.0 + 0.9;
  o.exact_finish_iterations = 3;  // not the default
  o.retry_from_rest = 0;
  o.retime_depth = 1;
  o.readout_time = 0.0125 + 1e-9;
  o.vignetting = 0.1 + 0.2;
  o.correction_rounds = 3;
  o.evaluate_unused_objective = true;
  o.min_valid_pixels = 123;
  o.max_association_dt = 0.015;
  o.first_frame = 4;
  o.max_frames = 9;
  o.start_at_groundtruth = false;
  o.prefetch_frames = false;
  o.load_threads = 3;
  o.verbosity = 2;
  o.policy.lambda = 12345.678901234567;
  o.policy.phi = 3.0e-7;
  o.policy.delta = 0.0173;
  o.policy.eps_min = 2.5e-4;
  o.policy.eps_max = 7.0e-3;
  o.policy.eps = 1.0 / 7.0;
  o.policy.kappa = 0.3125;
  o.policy.eps_ratio = 2.0 / 3.0;
  o.policy.guard = 0.0123;
  o.policy.joint_tolerance = 2.0 / 9.0;
  o.policy.relaxed_tolerance = 3.0 / 11.0;
  o.policy.both_starts = 1;
  o.problem.min_depth = 0.25;
  o.problem.max_depth = 6.5;
  o.problem.occlusion_margin = 0.07;
  o.problem.depth_first = true;
  o.problem.joint_weights = true;
  o.problem.model_f2 = false;
  o.problem.jacobian = bivo::odometry::JacobianKind::kEsm;
  o.problem.threads = 3;
  o.problem.weights.kind = bivo::odometry::WeightKind::kHuber;
  o.problem.weights.nu = 4.5;
  o.problem.weights.huber_k = 1.5;
  o.problem.weights.max_scale_iterations = 17;
  o.problem.weights.scale_tolerance = 3e-5;
  o.intrinsics = bivo::odometry::io::Intrinsics{500.125, 501.5, 320.25, 240.75};
  o.distortion = bivo::odometry::io::Distortion{0.1 + 0.2, -1.0 / 3.0, 1e-3 / 7.0, -2e-4, 1.1633};
  return o;
}

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("bivo_test_tracker_config_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST(TrackerConfig, EveryFieldRoundTripsBitExactlyThroughAFile) {
  const TrackerOptions o = unusual_options();
  const fs::path dir = temp_dir("roundtrip");
  write_tracker_config((dir / "cfg.json").string(), o);
  const TrackerOptions back = read_tracker_config((dir / "cfg.json").string());
  // Field by field (the JSON comparison below would hide a field missing on both sides).
  EXPECT_EQ(back.method, o.method);
  EXPECT_EQ(back.backend, o.backend);
  EXPECT_EQ(back.levels, o.levels);
  EXPECT_EQ(back.finest_level, o.finest_level);
  EXPECT_EQ(back.initial_guess, o.initial_guess);
  EXPECT_EQ(back.max_iterations, o.max_iterations);
  EXPECT_EQ(back.step_tolerance, o.step_tolerance);
  EXPECT_EQ(back.relative_decrease_tolerance, o.relative_decrease_tolerance);
  EXPECT_EQ(back.pixel_motion_tolerance, o.pixel_motion_tolerance);
  EXPECT_EQ(back.step_extrapolation, o.step_extrapolation);
  EXPECT_EQ(back.exact_finish_iterations, o.exact_finish_iterations);
  EXPECT_EQ(back.retry_from_rest, o.retry_from_rest);
  EXPECT_EQ(back.retime_depth, o.retime_depth);
  EXPECT_EQ(back.readout_time, o.readout_time);
  EXPECT_EQ(back.vignetting, o.vignetting);
  EXPECT_EQ(back.correction_rounds, o.correction_rounds);
  EXPECT_EQ(back.evaluate_unused_objective, o.evaluate_unused_objective);
  EXPECT_EQ(back.min_valid_pixels, o.min_valid_pixels);
  EXPECT_EQ(back.max_association_dt, o.max_association_dt);
  EXPECT_EQ(back.first_frame, o.first_frame);
  EXPECT_EQ(back.max_frames, o.max_frames);
  EXPECT_EQ(back.start_at_groundtruth, o.start_at_groundtruth);
  EXPECT_EQ(back.prefetch_frames, o.prefetch_frames);
  EXPECT_EQ(back.load_threads, o.load_threads);
  EXPECT_EQ(back.verbosity, o.verbosity);
  EXPECT_EQ(back.policy.lambda, o.policy.lambda);
  EXPECT_EQ(back.policy.phi, o.policy.phi);
  EXPECT_EQ(back.policy.delta, o.policy.delta);
  EXPECT_EQ(back.policy.eps_min, o.policy.eps_min);
  EXPECT_EQ(back.policy.eps_max, o.policy.eps_max);
  ASSERT_TRUE(back.policy.eps.has_value());
  EXPECT_EQ(*back.policy.eps, *o.policy.eps);
  EXPECT_EQ(back.policy.kappa, o.policy.kappa);
  EXPECT_EQ(back.policy.eps_ratio, o.policy.eps_ratio);
  EXPECT_EQ(back.policy.guard, o.policy.guard);
  EXPECT_EQ(back.policy.joint_tolerance, o.policy.joint_tolerance);
  EXPECT_EQ(back.policy.relaxed_tolerance, o.policy.relaxed_tolerance);
  EXPECT_EQ(back.problem.min_depth, o.problem.min_depth);
  EXPECT_EQ(back.problem.max_depth, o.problem.max_depth);
  EXPECT_EQ(back.problem.occlusion_margin, o.problem.occlusion_margin);
  EXPECT_EQ(back.problem.depth_first, o.problem.depth_first);
  EXPECT_EQ(back.problem.joint_weights, o.problem.joint_weights);
  EXPECT_EQ(back.problem.model_f2, o.problem.model_f2);
  EXPECT_EQ(back.problem.jacobian, o.problem.jacobian);
  EXPECT_EQ(back.problem.threads, o.problem.threads);
  EXPECT_EQ(back.problem.weights.kind, o.problem.weights.kind);
  EXPECT_EQ(back.problem.weights.nu, o.problem.weights.nu);
  EXPECT_EQ(back.problem.weights.huber_k, o.problem.weights.huber_k);
  EXPECT_EQ(back.problem.weights.max_scale_iterations, o.problem.weights.max_scale_iterations);
  EXPECT_EQ(back.problem.weights.scale_tolerance, o.problem.weights.scale_tolerance);
  ASSERT_TRUE(back.intrinsics.has_value());
  EXPECT_EQ(back.intrinsics->fx, o.intrinsics->fx);
  EXPECT_EQ(back.intrinsics->fy, o.intrinsics->fy);
  EXPECT_EQ(back.intrinsics->cx, o.intrinsics->cx);
  EXPECT_EQ(back.intrinsics->cy, o.intrinsics->cy);
  ASSERT_TRUE(back.distortion.has_value());
  EXPECT_EQ(back.distortion->k1, o.distortion->k1);
  EXPECT_EQ(back.distortion->k2, o.distortion->k2);
  EXPECT_EQ(back.distortion->p1, o.distortion->p1);
  EXPECT_EQ(back.distortion->p2, o.distortion->p2);
  EXPECT_EQ(back.distortion->k3, o.distortion->k3);
  // And the second trip writes the same document.
  EXPECT_EQ(tracker_options_to_json(back).dump(), tracker_options_to_json(o).dump());
}

TEST(TrackerConfig, AbsentKeysKeepTheBaseAndNullClearsOptionals) {
  const TrackerOptions base = unusual_options();
  const TrackerOptions o = tracker_options_from_json(
      json::parse(R"({"levels": 2, "policy": {"eps": null}, "intrinsics": null, "distortion": null})"), "x", base);
  EXPECT_EQ(o.levels, 2);
  EXPECT_FALSE(o.policy.eps.has_value());
  EXPECT_FALSE(o.intrinsics.has_value());
  EXPECT_FALSE(o.distortion.has_value());
  EXPECT_EQ(o.policy.lambda, base.policy.lambda);
  EXPECT_EQ(o.method, base.method);
  // The defaults' own document reads back as the defaults.
  EXPECT_EQ(tracker_options_to_json(tracker_options_from_json(tracker_options_to_json({}), "d")).dump(),
            tracker_options_to_json({}).dump());
}

// An integer option that also takes "the method's own" (-1) accepts it from a document as a
// number option does (the check used to ignore the -1 for integers).
TEST(TrackerConfig, IntegerOptionsTakeTheirAutoValue) {
  bivo::experiments::TrackerOption option;
  option.key = "policy.photometric_start_levels";
  option.type = bivo::experiments::OptionType::kInteger;
  option.lo = 0.0;
  option.hi = 8.0;
  option.auto_value = -1.0;
  option.set = [](TrackerOptions& o, const json& v) { v.get_to(o.policy.photometric_start_levels); };
  TrackerOptions o;
  o.policy.photometric_start_levels = 3;
  const auto apply = [&](int v) { return error_of([&] { bivo::experiments::apply_tracker_option(option, v, o); }); };
  EXPECT_EQ(apply(-1), "");
  EXPECT_EQ(o.policy.photometric_start_levels, -1);
  EXPECT_NE(apply(-2).find("policy.photometric_start_levels: -2 is outside -1 or [0, 8]"), std::string::npos);
  EXPECT_NE(apply(9).find("is outside -1 or [0, 8]"), std::string::npos);
}

TEST(TrackerConfig, BadDocumentsNameTheFileAndTheKey) {
  auto err = [](const char* text) {
    return error_of([&] { tracker_options_from_json(json::parse(text), "cfg.json"); });
  };
  EXPECT_NE(err(R"({"levls": 3})").find("cfg.json: unknown key 'levls'"), std::string::npos);
  EXPECT_NE(err(R"({"policy": {"phii": 3}})").find("cfg.json: unknown key 'policy.phii'"), std::string::npos);
  EXPECT_NE(err(R"({"levels": "four"})").find("cfg.json: levels: must be an integer"), std::string::npos);
  EXPECT_NE(err(R"({"levels": 2.5})").find("cfg.json: levels: must be an integer, got 2.5"), std::string::npos);
  EXPECT_NE(err(R"({"levels": 0})").find("cfg.json: levels: 0 is outside [1, 8]"), std::string::npos);
  EXPECT_NE(err(R"({"max_frames": 4294967296})").find("cfg.json: max_frames: 4294967296 is outside [-1, 2147483647]"),
            std::string::npos);
  EXPECT_NE(err(R"({"step_extrapolation": 0.9})").find("cfg.json: step_extrapolation: 0.9 is outside -1 or [1, 100]"),
            std::string::npos);
  EXPECT_NE(err(R"({"step_extrapolation": -2})").find("cfg.json: step_extrapolation: -2 is outside -1 or [1, 100]"),
            std::string::npos);
  EXPECT_EQ(err(R"({"step_extrapolation": -1})"), "");  // the method's own
  EXPECT_NE(err(R"({"policy": {"both_starts": 2}})").find("cfg.json: policy.both_starts: 2 is outside [0, 1]"),
            std::string::npos);
  EXPECT_NE(err(R"({"policy": {"phi": -1}})").find("cfg.json: policy.phi: -1 is outside (0, inf]"), std::string::npos);
  EXPECT_NE(err(R"({"problem": {"weights": {"kind": "cauchy"}}})").find("cfg.json: problem.weights.kind: "),
            std::string::npos);
  EXPECT_NE(err(R"({"initial_guess": "zero"})").find("cfg.json: initial_guess: "), std::string::npos);
  EXPECT_NE(err(R"({"method": "nonsense"})").find("cfg.json: "), std::string::npos);
  EXPECT_NE(err(R"({"intrinsics": {"fx": 0, "fy": 1, "cx": 0, "cy": 0}})")
                .find("cfg.json: intrinsics.fx: 0 is outside (0, inf)"),
            std::string::npos);
  EXPECT_NE(err(R"([1, 2])").find("cfg.json: must be a JSON object"), std::string::npos);
  EXPECT_NE(err(R"({"policy": 3})").find("cfg.json: policy: must be a JSON object, got number"), std::string::npos);
  // Intrinsics need all four numbers (a missing cy used to keep the default silently).
  EXPECT_NE(err(R"({"intrinsics": {"fx": 500, "fy": 500, "cx": 320}})").find("cfg.json: intrinsics.cy: missing"),
            std::string::npos);
  // A method's backend that cannot solve its scalarization is caught by validate().
  EXPECT_NE(err(R"({"method": "bounded", "backend": "gn"})"), "");

  const fs::path dir = temp_dir("bad");
  std::ofstream(dir / "broken.json") << "{\"levels\": 3,";
  EXPECT_NE(error_of([&] { read_tracker_config((dir / "broken.json").string()); }).find("not valid JSON"),
            std::string::npos);
  EXPECT_NE(error_of([&] { read_tracker_config((dir / "missing.json").string()); }).find("cannot open"),
            std::string::npos);
}

// TUM data handling: file lists, association, frame loading and its errors, intrinsics,
// pyramids and image statistics, each against hand-computed values.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>

#include <time.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "odometry/image_statistics.h"
#include "odometry/io/camera_intrinsics.h"
#include "odometry/io/frame_stream.h"
#include "odometry/io/lens_distortion.h"
#include "odometry/io/png_io.h"
#include "odometry/io/tum_dataset.h"
#include "odometry/rgbd_pyramid.h"
#include "solvers/error.h"
#include "tests/test_support.h"

using namespace bivo;
using namespace bivo::odometry;
using namespace bivo::odometry::io;
namespace fs = std::filesystem;

namespace {

using bivo::testing::error_of;

// The process's scratch folder, removed with everything in it when the process ends.
const fs::path& scratch_root() {
  static const bivo::testing::TempDir root("bivo_odometry_data");
  return root.path;
}

std::string fresh_dir(const std::string& name) {
  const fs::path dir = scratch_root() / name;
  fs::remove_all(dir);
  fs::create_directories(dir / "rgb");
  fs::create_directories(dir / "depth");
  return dir.string();
}

void write_text(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// A tiny valid sequence: n frames of w x h, rgb at t = 1 + 0.1 k, depth 5 ms later.
std::string make_sequence(const std::string& name, int n, int w = 16, int h = 12) {
  const std::string dir = fresh_dir(name);
  std::string rgb = "# color images\r\n# timestamp filename\r\n\r\n", depth = "# depth\n";
  for (int k = 0; k < n; ++k) {
    char t_rgb[32], t_depth[32];
    std::snprintf(t_rgb, sizeof t_rgb, "%.6f", 1.0 + 0.1 * k);
    std::snprintf(t_depth, sizeof t_depth, "%.6f", 1.005 + 0.1 * k);
    Png8 c{w, h, 3, std::vector<std::uint8_t>(static_cast<std::size_t>(w * h * 3), 0)};
    for (int i = 0; i < w * h; ++i) {
      c.data[3 * i] = static_cast<std::uint8_t>(10 * k);
      c.data[3 * i + 1] = 100;
      c.data[3 * i + 2] = 200;
    }
    Png16 d{w, h, std::vector<std::uint16_t>(static_cast<std::size_t>(w * h), 5000)};
    d.data[0] = 0;  // one missing measurement
    write_png8(dir + "/rgb/" + t_rgb + ".png", c);
    write_png16(dir + "/depth/" + t_depth + ".png", d);
    rgb += std::string(t_rgb) + " rgb/" + t_rgb + ".png\r\n";
    depth += std::string(t_depth) + " depth/" + t_depth + ".png\n";
  }
  write_text(dir + "/rgb.txt", rgb);
  write_text(dir + "/depth.txt", depth);
  return dir;
}

}  // namespace

TEST(TumLists, CommentsBlankLinesAndCrlfAreTolerated) {
  const std::string dir = make_sequence("lists", 3);
  const auto rgb = read_file_list(dir + "/rgb.txt");
  ASSERT_EQ(rgb.size(), 3u);
  EXPECT_DOUBLE_EQ(rgb[1].timestamp, 1.1);
  EXPECT_EQ(rgb[1].file, "rgb/1.100000.png");  // no trailing '\r'
  EXPECT_EQ(rgb[0].line, 4);
}

TEST(TumLists, UnsortedEmptyAndMalformedListsNameFileAndLine) {
  const std::string dir = fresh_dir("bad_lists");
  write_text(dir + "/unsorted.txt", "# x\n2.0 a.png\n1.0 b.png\n");
  std::string msg = error_of([&] { read_file_list(dir + "/unsorted.txt"); });
  EXPECT_NE(msg.find("unsorted.txt:3"), std::string::npos) << msg;
  write_text(dir + "/empty.txt", "# only comments\n\n");
  msg = error_of([&] { read_file_list(dir + "/empty.txt"); });
  EXPECT_NE(msg.find("empty.txt"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no entries"), std::string::npos) << msg;
  write_text(dir + "/bad.txt", "1.0 a.png\nabc b.png\n");
  msg = error_of([&] { read_file_list(dir + "/bad.txt"); });
  EXPECT_NE(msg.find("bad.txt:2"), std::string::npos) << msg;
  write_text(dir + "/extra.txt", "1.0 a.png b.png\n");
  msg = error_of([&] { read_file_list(dir + "/extra.txt"); });
  EXPECT_NE(msg.find("extra.txt:1"), std::string::npos) << msg;
  EXPECT_THROW(read_file_list(dir + "/missing.txt"), Error);
}

TEST(TumLists, AssociationTakesNearestWithinDtOneToOne) {
  const std::vector<ListedFile> rgb = {{1.00, "r0", 1}, {1.03, "r1", 2}, {1.06, "r2", 3}, {2.00, "r3", 4}};
  const std::vector<ListedFile> depth = {{1.005, "d0", 1}, {1.028, "d1", 2}, {1.031, "d2", 3}, {1.07, "d3", 4}};
  const auto a = associate_lists(rgb, depth, "/seq", 0.02);
  ASSERT_EQ(a.size(), 3u);  // r3 has no depth within 0.02 s
  EXPECT_EQ(a[0].depth_path, "/seq/d0");
  EXPECT_EQ(a[1].depth_path, "/seq/d2");  // |1.03 - 1.031| < |1.03 - 1.028|
  EXPECT_EQ(a[2].depth_path, "/seq/d3");
  EXPECT_EQ(a[1].origin, "rgb.txt:2 + depth.txt:3");
  // Tighter dt: only exact-ish pairs remain.
  EXPECT_EQ(associate_lists(rgb, depth, "/seq", 0.002).size(), 1u);
  EXPECT_THROW(associate_lists(rgb, depth, "/seq", 0.0), Error);
}

TEST(TumSequenceTest, NoAssociationNamesBothLists) {
  const std::string dir = make_sequence("no_assoc", 2);
  write_text(dir + "/depth.txt", "5.0 depth/x.png\n");
  const std::string msg = error_of([&] { open_tum_sequence(dir); });
  EXPECT_NE(msg.find("rgb.txt"), std::string::npos) << msg;
  EXPECT_NE(msg.find("depth.txt"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no rgb/depth association"), std::string::npos) << msg;
}

TEST(TumSequenceTest, AssociationsFileIsPreferredAndChecked) {
  const std::string dir = make_sequence("assoc", 2);
  write_text(dir + "/associations.txt", "1.100000 rgb/1.100000.png 1.105000 depth/1.105000.png\n");
  TumSequence seq = open_tum_sequence(dir);
  ASSERT_EQ(seq.frames.size(), 1u);
  EXPECT_DOUBLE_EQ(seq.frames[0].rgb_time, 1.1);
  write_text(dir + "/associations.txt", "1.1 rgb/a.png 1.2 depth/b.png\n");
  const std::string msg = error_of([&] { open_tum_sequence(dir); });
  EXPECT_NE(msg.find("associations.txt:1"), std::string::npos) << msg;
}

TEST(TumSequenceTest, FramesLoadWithLuminanceAndMetres) {
  const std::string dir = make_sequence("load", 2);
  SequenceOptions o;
  o.intrinsics = parse_intrinsics("500 501 7.5 5.5");
  const TumSequence seq = open_tum_sequence(dir, o);
  ASSERT_EQ(seq.frames.size(), 2u);
  EXPECT_EQ(seq.intrinsics.fy, 501.0);
  EXPECT_FALSE(seq.groundtruth);
  const RgbdImage im = load_rgbd_image(seq.frames[1], 16, 12);
  EXPECT_NEAR(im.intensity[5], 0.299 * 10 + 0.587 * 100 + 0.114 * 200, 1e-4);
  EXPECT_FLOAT_EQ(im.depth[5], 1.0f);
  EXPECT_FLOAT_EQ(im.depth[0], 0.0f);
  EXPECT_DOUBLE_EQ(im.timestamp, 1.1);
}

TEST(TumSequenceTest, BadFramesNameTheFileAndItsListLine) {
  const std::string dir = make_sequence("bad_frames", 3);
  TumSequence seq = open_tum_sequence(dir);
  // Missing image.
  fs::remove(seq.frames[1].rgb_path);
  std::string msg = error_of([&] { load_rgbd_image(seq.frames[1]); });
  EXPECT_NE(msg.find(seq.frames[1].rgb_path), std::string::npos) << msg;
  EXPECT_NE(msg.find("rgb.txt:5"), std::string::npos) << msg;
  // 8-bit depth.
  write_png8(seq.frames[2].depth_path, Png8{16, 12, 1, std::vector<std::uint8_t>(16 * 12, 7)});
  msg = error_of([&] { load_rgbd_image(seq.frames[2]); });
  EXPECT_NE(msg.find(seq.frames[2].depth_path), std::string::npos) << msg;
  EXPECT_NE(msg.find("8-bit"), std::string::npos) << msg;
  // Wrong size against the sequence's first frame.
  write_png8(seq.frames[0].rgb_path, Png8{8, 12, 3, std::vector<std::uint8_t>(8 * 12 * 3, 7)});
  msg = error_of([&] { load_rgbd_image(seq.frames[0]); });
  EXPECT_NE(msg.find("size mismatch"), std::string::npos) << msg;
  Png16 d{8, 12, std::vector<std::uint16_t>(8 * 12, 1)};
  write_png16(seq.frames[0].depth_path, d);
  msg = error_of([&] { load_rgbd_image(seq.frames[0], 16, 12); });
  EXPECT_NE(msg.find("wrong image size"), std::string::npos) << msg;
  EXPECT_NE(msg.find(seq.frames[0].rgb_path), std::string::npos) << msg;
}

TEST(Intrinsics, PresetsByNameAndOverrideParsing) {
  EXPECT_EQ(intrinsics_for_sequence("/x/rgbd_dataset_freiburg1_rpy").fx, 517.3);
  EXPECT_EQ(intrinsics_for_sequence("rgbd_dataset_freiburg2_desk").cy, 249.7);
  EXPECT_EQ(intrinsics_for_sequence("rgbd_dataset_freiburg3_nostructure").fy, 539.2);
  EXPECT_EQ(intrinsics_for_sequence("my_synthetic").cx, 319.5);
  EXPECT_THROW(parse_intrinsics("500 500 320"), Error);
  EXPECT_THROW(parse_intrinsics("-1 500 320 240"), Error);
  EXPECT_THROW(parse_intrinsics("500 500 320 240 1"), Error);
}

TEST(LensDistortion, ClosedFormPresetsAndParsing) {
  // Hand-computed: radial only, r^2 = 0.25, g = 1 + 0.1 * 0.25; tangential only, r^2 = 0.13.
  const auto radial = Distortion{0.1, 0, 0, 0, 0}.distort(0.5, 0.0);
  EXPECT_NEAR(radial[0], 0.5125, 1e-15);
  EXPECT_NEAR(radial[1], 0.0, 1e-15);
  const auto tangential = Distortion{0, 0, 0.01, 0.02, 0}.distort(0.2, 0.3);
  EXPECT_NEAR(tangential[0], 0.2 + 2 * 0.01 * 0.06 + 0.02 * (0.13 + 0.08), 1e-15);
  EXPECT_NEAR(tangential[1], 0.3 + 0.01 * (0.13 + 0.18) + 2 * 0.02 * 0.06, 1e-15);
  const auto k3 = Distortion{0, 0, 0, 0, 2.0}.distort(0.0, 0.5);  // g = 1 + 2 * 0.25^3
  EXPECT_NEAR(k3[1], 0.5 * (1 + 2 * 0.015625), 1e-15);

  EXPECT_EQ(distortion_for_sequence("/x/rgbd_dataset_freiburg1_rpy").k1, 0.2624);
  EXPECT_EQ(distortion_for_sequence("rgbd_dataset_freiburg2_desk").k3, 0.9172);
  EXPECT_TRUE(distortion_for_sequence("rgbd_dataset_freiburg3_structure_texture_near").is_identity());
  EXPECT_TRUE(distortion_for_sequence("rgbd_dataset_freiburg3_synth_structure_texture_far").is_identity());
  EXPECT_TRUE(distortion_for_sequence("my_synthetic").is_identity());
  EXPECT_TRUE(parse_distortion("none").is_identity());
  EXPECT_EQ(parse_distortion("0.1 -0.2 0.003 0.004 0.5").p2, 0.004);
  for (const char* bad : {"0.1 0.2 0.3 0.4", "0.1 0.2 0.3 0.4 0.5 0.6", "none 1", "nan 0 0 0 0", ""}) {
    const std::string msg = error_of([&] { parse_distortion(bad); });
    EXPECT_NE(msg.find(std::string("'") + bad + "'"), std::string::npos) << msg;
  }
}

TEST(LensDistortion, UndistortionResamplesAtTheDistortedPositions) {
  // Input images whose intensity is linear in the input pixel position (bilinear
  // interpolation reproduces it exactly) and whose depth names its pixel: every output pixel
  // must hold the value at K distort(K^-1 [u v 1]) (intensity; clamped to the image outside
  // it) or at the nearest input pixel (depth; missing outside).
  const int W = 64, H = 48;
  const Intrinsics K{52.0, 51.0, 31.7, 24.2};
  const Distortion d{0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
  RgbdImage im;
  im.width = W;
  im.height = H;
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      im.intensity.push_back(3.0f * u + 2.0f * v + 10.0f);
      im.depth.push_back(1.0f + u + 100.0f * v);
    }
  }
  const Undistortion map(K, d, W, H);
  ASSERT_FALSE(map.is_identity());
  RgbdImage out = im;
  map.apply(out);
  int outside = 0;
  double largest_shift = 0.0;
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const auto [xd, yd] = d.distort((u - K.cx) / K.fx, (v - K.cy) / K.fy);
      const double su = K.fx * xd + K.cx, sv = K.fy * yd + K.cy;
      const std::size_t i = static_cast<std::size_t>(v) * W + u;
      const double cu = std::clamp(su, 0.0, W - 1.0), cv = std::clamp(sv, 0.0, H - 1.0);
      EXPECT_NEAR(out.intensity[i], 3.0 * cu + 2.0 * cv + 10.0, 2e-4 * (3.0 * cu + 2.0 * cv + 10.0)) << u << "," << v;
      if (su >= 0 && su <= W - 1 && sv >= 0 && sv <= H - 1) {
        EXPECT_EQ(out.depth[i], 1.0f + std::lround(su) + 100.0f * std::lround(sv)) << u << "," << v;
        largest_shift = std::max(largest_shift, std::hypot(su - u, sv - v));
      } else {
        EXPECT_EQ(out.depth[i], 0.0f) << u << "," << v;
        ++outside;
      }
    }
  }
  EXPECT_GT(outside, 0);          // the corners of this lens fall outside the stored image
  EXPECT_GT(largest_shift, 1.5);  // inside the image: ~1.9 pixels here, ten times that at 640x480

  // No distortion: the frame is left bit for bit; a frame of another size is an error.
  RgbdImage same = im;
  Undistortion(K, Distortion{}, W, H).apply(same);
  EXPECT_EQ(same.intensity, im.intensity);
  EXPECT_EQ(same.depth, im.depth);
  // A lens model whose positions overflow to inf - inf = NaN (921 of these pixels) is still a
  // defined resampling: no NaN out, depth missing there (a NaN cast to int read far outside).
  RgbdImage wild = im;
  Undistortion(Intrinsics{20.0, 20.0, 31.7, 24.2}, Distortion{1e308, 1e308, 0, 1e308, 1e308}, W, H).apply(wild);
  for (std::size_t i = 0; i < wild.intensity.size(); ++i) ASSERT_TRUE(std::isfinite(wild.intensity[i])) << i;
  EXPECT_EQ(wild.depth.front(), 0.0f);
  RgbdImage small = im;
  small.width = W / 2;
  const std::string msg = error_of([&] { map.apply(small); });
  EXPECT_NE(msg.find("32x48"), std::string::npos) << msg;
}

// The frame stream (loading one frame ahead on a thread of its own, or inline) delivers what
// loading each frame and undistorting it gives, bit for bit, in order; a bad frame's error
// comes when its turn comes, after the good frames before it.
TEST(FrameStreamTest, DeliversWhatLoadingAndUndistortingEachFrameGives) {
  const std::string dir = make_sequence("stream", 5);
  const TumSequence seq = open_tum_sequence(dir);
  for (int k = 0; k < 5; ++k) {  // content that varies over the image, so undistortion moves it
    Png8 c{16, 12, 3, std::vector<std::uint8_t>(16 * 12 * 3)};
    for (std::size_t i = 0; i < c.data.size(); ++i) c.data[i] = static_cast<std::uint8_t>((i * 7 + 31 * k) % 251);
    write_png8(seq.frames[static_cast<std::size_t>(k)].rgb_path, c);
  }
  const Intrinsics K{14.0, 13.0, 7.6, 5.4};
  const Distortion lens{0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
  const Undistortion map(K, lens, 16, 12);
  for (const int loaders : {0, 1, 2, 3}) {
    const bool background = loaders > 0;
    const double fall_off = loaders == 2 ? 0.2 : 0.0;  // divided out before the lens is
    FrameStream frames(seq.frames, 1, 5, K, lens, loaders, fall_off);
    for (int k = 1; k < 5; ++k) {
      RgbdImage expected = load_rgbd_image(seq.frames[static_cast<std::size_t>(k)]);
      const RgbdImage raw = expected;
      for (int v = 0; v < 12; ++v) {
        for (int u = 0; u < 16; ++u) {
          expected.intensity[static_cast<std::size_t>(v * 16 + u)] /=
              static_cast<float>(1.0 - fall_off * ((u - 7.6) * (u - 7.6) + (v - 5.4) * (v - 5.4)) /
                                           (7.6 * 7.6 + 5.6 * 5.6));  // to the farthest corner, (0, 11)
        }
      }
      map.apply(expected);
      // Time for the loader to run ahead, if it would: it must wait for this frame to be taken.
      if (background) std::this_thread::sleep_for(std::chrono::milliseconds(5));
      const RgbdImage got = frames.next();
      ASSERT_EQ(got.intensity.size(), expected.intensity.size());
      for (std::size_t i = 0; i < got.intensity.size(); ++i) {
        ASSERT_NEAR(got.intensity[i], expected.intensity[i], 1e-4f) << k << " " << loaders << " " << i;
      }
      EXPECT_EQ(got.depth, expected.depth) << k << " " << loaders;
      EXPECT_NE(got.intensity, raw.intensity) << k;  // the lens was applied
      EXPECT_DOUBLE_EQ(got.timestamp, seq.frames[static_cast<std::size_t>(k)].rgb_time);
      EXPECT_GE(frames.last_wait_seconds(), 0.0);
    }
    const std::string msg = error_of([&] { frames.next(); });
    EXPECT_NE(msg.find("all 4 frames"), std::string::npos) << msg;
  }
  for (const double bad : {-0.1, 1.0}) {
    const std::string msg = error_of([&] { FrameStream(seq.frames, 1, 5, K, lens, 0, bad); });
    EXPECT_NE(msg.find("vignetting fall-off"), std::string::npos) << msg;
  }
  // A stream left with frames unread stops at once (the loader waits to hand over the next).
  { FrameStream(seq.frames, 0, 5, K, lens, 1).next(); }
  { FrameStream(seq.frames, 0, 5, K, lens, 3).next(); }
  EXPECT_NE(error_of([&] { FrameStream(seq.frames, 3, 3, K, lens, 1); }).find("[3, 3)"), std::string::npos);
  EXPECT_NE(error_of([&] { FrameStream(seq.frames, 0, 3, K, lens, -1); }).find("-1 loader"), std::string::npos);
}

TEST(FrameStreamTest, ABadFrameFailsWhenItsTurnComes) {
  const std::string dir = make_sequence("stream_bad", 5);
  const TumSequence seq = open_tum_sequence(dir);
  fs::remove(seq.frames[2].rgb_path);  // missing
  Png16 small{8, 12, std::vector<std::uint16_t>(8 * 12, 5000)};
  write_png16(seq.frames[4].depth_path, small);  // the wrong size
  write_png8(seq.frames[4].rgb_path, Png8{8, 12, 3, std::vector<std::uint8_t>(8 * 12 * 3, 9)});
  for (const int loaders : {0, 1, 2, 3}) {
    FrameStream frames(seq.frames, 0, 5, Intrinsics{14.0, 13.0, 7.6, 5.4}, Distortion{}, loaders);
    EXPECT_DOUBLE_EQ(frames.next().timestamp, seq.frames[0].rgb_time);
    EXPECT_DOUBLE_EQ(frames.next().timestamp, seq.frames[1].rgb_time);
    for (int again = 0; again < 2; ++again) {  // the error stays; nothing after it is delivered
      const std::string msg = error_of([&] { frames.next(); });
      EXPECT_NE(msg.find(seq.frames[2].rgb_path), std::string::npos) << msg;
      EXPECT_NE(msg.find("rgb.txt:6"), std::string::npos) << msg;
    }
    FrameStream from3(seq.frames, 3, 5, Intrinsics{14.0, 13.0, 7.6, 5.4}, Distortion{}, loaders);
    EXPECT_EQ(from3.next().width, 16);
    const std::string msg = error_of([&] { from3.next(); });
    EXPECT_NE(msg.find("wrong image size"), std::string::npos) << msg;  // against the stream's first frame
    EXPECT_NE(msg.find(seq.frames[4].rgb_path), std::string::npos) << msg;
  }
}

// The loader's CPU clock, read from the caller's thread, is the rest of the process's CPU
// time: what track_sequence subtracts from the process's to time a pair's own work. It still
// reads after the last frame (the loader waits for the stream's end).
TEST(FrameStreamTest, LoaderCpuClockIsTheProcessLessTheCaller) {
  const std::string dir = make_sequence("stream_cpu", 4, 640, 480);
  const TumSequence seq = open_tum_sequence(dir);
  std::mt19937 rng(7);
  for (const auto& frame : seq.frames) {  // noise: inflating it is real work
    Png8 c{640, 480, 3, std::vector<std::uint8_t>(640 * 480 * 3)};
    for (auto& v : c.data) v = static_cast<std::uint8_t>(rng());
    write_png8(frame.rgb_path, c);
  }
  const Intrinsics K{517.3, 516.5, 318.6, 255.3};
  const Distortion lens{0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
  const auto cpu = [](clockid_t id) {
    timespec ts{};
    clock_gettime(id, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
  };
  {
    FrameStream inline_frames(seq.frames, 0, 4, K, lens, 0);
    inline_frames.next();
    EXPECT_EQ(inline_frames.loader_cpu_seconds(), 0.0);
  }
  for (const int loaders : {1, 2}) {  // two: the sum of both threads' clocks
    const double process0 = cpu(CLOCK_PROCESS_CPUTIME_ID), own0 = cpu(CLOCK_THREAD_CPUTIME_ID);
    FrameStream frames(seq.frames, 0, 4, K, lens, loaders);
    for (int k = 0; k < 4; ++k) frames.next();
    const double loader = frames.loader_cpu_seconds();
    const double process = cpu(CLOCK_PROCESS_CPUTIME_ID) - process0, own = cpu(CLOCK_THREAD_CPUTIME_ID) - own0;
    EXPECT_GT(loader, 0.004);  // four noisy 640x480 frames decoded and undistorted
    EXPECT_NEAR(process - own, loader, 0.002 + 0.05 * loader)
        << loaders << " loaders: process " << process << " s, own " << own << " s";
  }
}

TEST(Intrinsics, LevelScalingMatchesTheAveragedPixelGrid) {
  // A point projects at level 0 to (u, v); the coarse pixel grid of 2x2 averaging puts it
  // at ((u - 0.5) / 2, (v - 0.5) / 2) per level.
  const Intrinsics K{517.3, 516.5, 318.6, 255.3};
  const Eigen::Vector3d p(0.3, -0.2, 1.7);
  double u = K.fx * p.x() / p.z() + K.cx, v = K.fy * p.y() / p.z() + K.cy;
  for (int level = 1; level <= 3; ++level) {
    u = (u - 0.5) / 2;
    v = (v - 0.5) / 2;
    const Intrinsics Kl = K.at_level(level);
    EXPECT_NEAR(Kl.fx * p.x() / p.z() + Kl.cx, u, 1e-12);
    EXPECT_NEAR(Kl.fy * p.y() / p.z() + Kl.cy, v, 1e-12);
  }
}

TEST(Pyramid, IntensityAveragesAndDepthIgnoresMissing) {
  ImageF I{4, 2, {0, 4, 8, 8, 2, 6, 8, 8}};
  const ImageF Ic = downsample_intensity(I);
  ASSERT_EQ(Ic.width, 2);
  ASSERT_EQ(Ic.height, 1);
  EXPECT_FLOAT_EQ(Ic.data[0], 3.0f);
  EXPECT_FLOAT_EQ(Ic.data[1], 8.0f);
  ImageF D{4, 2, {1.0f, 0.0f, 0, 0, 2.0f, 0.0f, 0, 0}};
  const ImageF Dc = downsample_depth(D);
  EXPECT_FLOAT_EQ(Dc.data[0], 1.5f);  // mean of the two valid values, not of four
  EXPECT_FLOAT_EQ(Dc.data[1], 0.0f);  // nothing valid stays missing
  // A coarse width of 19: two groups of eight lanes and a remainder of three, every pixel
  // against the per-pixel formula, bit for bit (the lanes promise the same operations in the
  // same order), with missing depths scattered over the blocks.
  const int W = 38, H = 6;
  ImageF In{W, H, std::vector<float>(W * H)}, Dn{W, H, std::vector<float>(W * H)};
  for (int i = 0; i < W * H; ++i) {
    In.data[i] = static_cast<float>(std::sin(0.37 * i) * 100.0 + 0.1 * i);
    Dn.data[i] = i % 3 == 0 || i % 7 == 0 ? 0.0f : static_cast<float>(1.0 + 0.013 * i);
  }
  const ImageF In2 = downsample_intensity(In), Dn2 = downsample_depth(Dn);
  ASSERT_EQ(In2.width, 19);
  for (int y = 0; y < H / 2; ++y) {
    for (int x = 0; x < W / 2; ++x) {
      const auto at = [&](const ImageF& f, int dx, int dy) { return f.data[(2 * y + dy) * W + 2 * x + dx]; };
      EXPECT_EQ(In2.data[y * 19 + x], 0.25f * (at(In, 0, 0) + at(In, 1, 0) + at(In, 0, 1) + at(In, 1, 1)));
      float sum = 0.0f, count = 0.0f;
      for (const float d : {at(Dn, 0, 0), at(Dn, 1, 0), at(Dn, 0, 1), at(Dn, 1, 1)}) {
        sum += d > 0.0f ? d : 0.0f;
        count += d > 0.0f ? 1.0f : 0.0f;
      }
      EXPECT_EQ(Dn2.data[y * 19 + x], count > 0.0f ? sum / count : 0.0f) << x << "," << y;
    }
  }
  RgbdImage im;
  im.width = 64;
  im.height = 48;
  im.intensity.assign(64 * 48, 1.0f);
  im.depth.assign(64 * 48, 1.0f);
  const RgbdPyramid p = build_pyramid(im, Intrinsics{}, 3);
  ASSERT_EQ(p.levels.size(), 3u);
  EXPECT_EQ(p.levels[2].intensity.width, 16);
  EXPECT_EQ(p.levels[2].depth.height, 12);
  EXPECT_DOUBLE_EQ(p.levels[2].K.fx, 525.0 / 4);
  EXPECT_THROW(build_pyramid(im, Intrinsics{}, 4), Error);  // 8x6 coarsest level
  EXPECT_THROW(build_pyramid(im, Intrinsics{}, 0), Error);
}

TEST(ImageStatisticsTest, ComplexityOfARampIsTwiceTheSlopes) {
  // I(x, y) = 3x - 2y: every central difference over two pixels is 6 or 4.
  ImageF I{20, 15, {}};
  ImageF D{20, 15, {}};
  for (int y = 0; y < 15; ++y) {
    for (int x = 0; x < 20; ++x) {
      I.data.push_back(3.0f * x - 2.0f * y + 100.0f);
      D.data.push_back(1.0f + 0.01f * x);
    }
  }
  EXPECT_NEAR(complexity_metric(I, false), 10.0, 1e-9);
  EXPECT_NEAR(complexity_metric(D, true), 0.02, 1e-6);
  // Holes do not change the depth metric: differences touching them are skipped.
  for (int k : {25, 60, 61, 130, 200}) D.data[static_cast<std::size_t>(k)] = 0.0f;
  EXPECT_NEAR(complexity_metric(D, true), 0.02, 1e-6);
  // Variance and median of 1..5 (with a missing 0 skipped).
  ImageF v{6, 1, {0, 1, 2, 3, 4, 5}};
  EXPECT_DOUBLE_EQ(variance(v, true), 2.0);
  EXPECT_DOUBLE_EQ(median(v, true), 3.0);
  EXPECT_DOUBLE_EQ(median(v, false), 2.5);
}

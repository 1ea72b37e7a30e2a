// PNG I/O: round trips (the oracle is the data written), format rejections, corrupt and
// missing files, and a real TUM frame's known layout.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "odometry/io/png_io.h"
#include "solvers/error.h"
#include "tests/test_support.h"

using namespace bivo;
using namespace bivo::odometry;
using namespace bivo::odometry::io;
namespace fs = std::filesystem;

namespace {

using bivo::testing::error_of;

// The process's scratch folder, removed with everything in it when the process ends.
std::string temp_dir() {
  static const bivo::testing::TempDir dir("bivo_png_test");
  return dir.path.string();
}

}  // namespace

TEST(PngIo, Gray8RoundTripIsExact) {
  Png8 img;
  img.width = 7;
  img.height = 5;
  img.channels = 1;
  for (int i = 0; i < 35; ++i) img.data.push_back(static_cast<std::uint8_t>(i * 7 + 3));
  const std::string path = temp_dir() + "/gray.png";
  write_png8(path, img);
  const Png8 back = read_png8(path);
  EXPECT_EQ(back.width, 7);
  EXPECT_EQ(back.height, 5);
  EXPECT_EQ(back.channels, 1);
  EXPECT_EQ(back.data, img.data);
}

TEST(PngIo, Rgb8RoundTripIsExact) {
  Png8 img;
  img.width = 4;
  img.height = 3;
  img.channels = 3;
  for (int i = 0; i < 36; ++i) img.data.push_back(static_cast<std::uint8_t>(255 - i * 5));
  const std::string path = temp_dir() + "/rgb.png";
  write_png8(path, img);
  const Png8 back = read_png8(path);
  EXPECT_EQ(back.channels, 3);
  EXPECT_EQ(back.data, img.data);
}

TEST(PngIo, Depth16RoundTripKeepsFullRangeAndByteOrder) {
  Png16 img;
  img.width = 3;
  img.height = 2;
  // 0x0102 distinguishes byte orders; 65535 and 0 are the extremes.
  img.data = {0, 1, 0x0102, 5000, 65535, 32768};
  const std::string path = temp_dir() + "/depth.png";
  write_png16(path, img);
  const Png16 back = read_png16(path);
  EXPECT_EQ(back.width, 3);
  EXPECT_EQ(back.height, 2);
  EXPECT_EQ(back.data, img.data);
  // No temporary files remain beside the output.
  int entries = 0;
  for (const auto& e : fs::directory_iterator(fs::path(path).parent_path())) {
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
    ++entries;
  }
  EXPECT_GE(entries, 1);
}

TEST(PngIo, EightBitFileGivenAsDepthIsRejectedNamingFileAndFormat) {
  Png8 img;
  img.width = 2;
  img.height = 2;
  img.channels = 1;
  img.data = {1, 2, 3, 4};
  const std::string path = temp_dir() + "/eight_bit_depth.png";
  write_png8(path, img);
  const std::string msg = error_of([&] { read_png16(path); });
  EXPECT_NE(msg.find("eight_bit_depth.png"), std::string::npos) << msg;
  EXPECT_NE(msg.find("8-bit gray"), std::string::npos) << msg;
}

TEST(PngIo, SixteenBitFileGivenAsColourIsRejected) {
  Png16 img;
  img.width = 2;
  img.height = 1;
  img.data = {1, 2};
  const std::string path = temp_dir() + "/sixteen.png";
  write_png16(path, img);
  const std::string msg = error_of([&] { read_png8(path); });
  EXPECT_NE(msg.find("sixteen.png"), std::string::npos) << msg;
  EXPECT_NE(msg.find("16-bit"), std::string::npos) << msg;
}

TEST(PngIo, TruncatedFileIsReportedAsCorrupt) {
  Png8 img;
  img.width = 64;
  img.height = 64;
  img.channels = 3;
  for (int i = 0; i < 64 * 64 * 3; ++i) img.data.push_back(static_cast<std::uint8_t>((i * 131) % 251));
  const std::string path = temp_dir() + "/truncated.png";
  write_png8(path, img);
  const auto size = fs::file_size(path);
  fs::resize_file(path, size / 2);
  const std::string msg = error_of([&] { read_png8(path); });
  EXPECT_NE(msg.find("truncated.png"), std::string::npos) << msg;
  EXPECT_NE(msg.find("corrupt"), std::string::npos) << msg;
}

TEST(PngIo, NonPngAndMissingFilesAreRejected) {
  const std::string path = temp_dir() + "/not_a_png.png";
  std::ofstream(path) << "hello, this is text";
  std::string msg = error_of([&] { read_png8(path); });
  EXPECT_NE(msg.find("not_a_png.png"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not a PNG"), std::string::npos) << msg;
  msg = error_of([&] { read_png16(temp_dir() + "/does_not_exist.png"); });
  EXPECT_NE(msg.find("does_not_exist.png"), std::string::npos) << msg;
}

TEST(PngIo, InconsistentImageIsNotWritten) {
  Png8 img;
  img.width = 3;
  img.height = 3;
  img.channels = 1;
  img.data = {1, 2, 3};
  const std::string path = temp_dir() + "/inconsistent.png";
  EXPECT_THROW(write_png8(path, img), Error);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_THROW(write_png8(temp_dir() + "/no/such/dir/x.png", Png8{1, 1, 1, {0}}), Error);
}

TEST(PngIo, RealTumFramesHaveTheDocumentedLayout) {
  const std::string dir = std::string(BIVO_SHARED_DIR) + "/data/tum/rgbd_dataset_freiburg1_rpy";
  if (!fs::exists(dir)) GTEST_SKIP() << "shared data absent: " << dir;
  const Png8 rgb = read_png8(dir + "/rgb/1305031229.528748.png");
  EXPECT_EQ(rgb.width, 640);
  EXPECT_EQ(rgb.height, 480);
  EXPECT_EQ(rgb.channels, 3);
  const Png16 depth = read_png16(dir + "/depth/1305031229.528784.png");
  EXPECT_EQ(depth.width, 640);
  EXPECT_EQ(depth.height, 480);
  // A desk scene at 0.5..5 m: most valid depths (units 1/5000 m) fall in that band.
  std::size_t valid = 0, in_band = 0;
  for (std::uint16_t v : depth.data) {
    if (v == 0) continue;
    ++valid;
    if (v >= 2500 && v <= 25000) ++in_band;
  }
  EXPECT_GT(valid, depth.data.size() / 2);
  EXPECT_GT(in_band, valid * 9 / 10);
  // Real 16-bit depth given as colour is rejected.
  EXPECT_THROW(read_png8(dir + "/depth/1305031229.528784.png"), Error);
}

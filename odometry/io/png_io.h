#pragma once
// PNG reading and writing through libpng (8-bit RGB/gray images, 16-bit depth images).
#include <cstdint>
#include <string>
#include <vector>

namespace bivo::odometry::io {

struct Png8 {
  int width = 0, height = 0, channels = 0;  // channels: 1 (gray) or 3 (RGB; alpha dropped)
  std::vector<std::uint8_t> data;           // row-major, interleaved
};

struct Png16 {
  int width = 0, height = 0;  // single channel
  std::vector<std::uint16_t> data;
};

// Throw bivo::Error naming the file when it is missing, not a PNG, corrupt, or of the
// wrong bit depth / colour type (e.g. an 8-bit file given as depth).
Png8 read_png8(const std::string& path);
Png16 read_png16(const std::string& path);

// Atomic writes (temporary file + rename).
void write_png8(const std::string& path, const Png8& image);
void write_png16(const std::string& path, const Png16& image);

}  // namespace bivo::odometry::io

#pragma once
// Limits on what one input file may ask the program to allocate. A file's own header or
// line count never decides an allocation alone: a 41-byte PNG claiming 100000 x 100000
// pixels or a list of ten million lines is refused with an error naming the file, the
// value and the flag that raises the limit (`bivo --max-image-pixels N --max-list-entries N`).
#include <cstdint>
#include <string>

namespace bivo::odometry::io {

struct InputLimits {
  // Pixels of one image (width x height). Default 8192 x 8192, 100x a TUM frame's 640 x 480.
  std::int64_t max_image_pixels = std::int64_t{1} << 26;
  // Data lines of one TUM list or trajectory (and frames of a rendered sequence). Default
  // 10^6: 2.8 hours of 100 Hz motion capture, 9 hours of 30 Hz frames.
  std::int64_t max_list_entries = 1'000'000;
};

// The process-wide limits (set once by `bivo`'s global flags, or by a test).
InputLimits& input_limits();

// Throws bivo::Error "<what> ... limit L (raise with <flag>)" when width x height exceeds
// max_image_pixels or either side is < 1.
void check_image_size(std::int64_t width, std::int64_t height, const std::string& what);

// Throws bivo::Error when `entries` exceeds max_list_entries, naming `what`.
void check_list_size(std::int64_t entries, const std::string& what);

}  // namespace bivo::odometry::io

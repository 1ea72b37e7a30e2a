#include "odometry/io/input_limits.h"

#include "solvers/error.h"

namespace bivo::odometry::io {

InputLimits& input_limits() {
  static InputLimits limits;
  return limits;
}

void check_image_size(std::int64_t width, std::int64_t height, const std::string& what) {
  if (width < 1 || height < 1) {
    throw Error(what + ": image size " + std::to_string(width) + " x " + std::to_string(height) +
                " (both sides must be >= 1)");
  }
  const std::int64_t limit = input_limits().max_image_pixels;
  // width, height < 2^32 (PNG) and the comparison is done without forming an overflowing product.
  if (width > limit || height > limit / width) {
    throw Error(what + ": image size " + std::to_string(width) + " x " + std::to_string(height) +
                " exceeds the limit of " + std::to_string(limit) + " pixels (raise with --max-image-pixels)");
  }
}

void check_list_size(std::int64_t entries, const std::string& what) {
  const std::int64_t limit = input_limits().max_list_entries;
  if (entries > limit) {
    throw Error(what + ": more than " + std::to_string(limit) + " entries (the limit; raise with --max-list-entries)");
  }
}

}  // namespace bivo::odometry::io

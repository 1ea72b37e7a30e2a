// PNG reading/writing with libpng's classic API. libpng reports errors by longjmp to the
// setjmp point; the error callback records libpng's message first so the bivo::Error we
// throw afterwards (outside any libpng frame) names both the file and the cause.
#include "odometry/io/png_io.h"

#include <png.h>

#include <algorithm>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include "odometry/io/atomic_file.h"
#include "odometry/io/input_limits.h"
#include "solvers/error.h"

namespace bivo::odometry::io {
namespace {

struct ErrorSink {
  std::string message;
};

void on_png_error(png_structp png, png_const_charp message) {
  auto* sink = static_cast<ErrorSink*>(png_get_error_ptr(png));
  if (sink) sink->message = message ? message : "unknown libpng error";
  png_longjmp(png, 1);
}

void on_png_warning(png_structp, png_const_charp) {}  // warnings (e.g. iCCP) are harmless here

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

std::string colour_type_name(int colour_type) {
  switch (colour_type) {
    case PNG_COLOR_TYPE_GRAY:
      return "gray";
    case PNG_COLOR_TYPE_GRAY_ALPHA:
      return "gray+alpha";
    case PNG_COLOR_TYPE_RGB:
      return "RGB";
    case PNG_COLOR_TYPE_RGB_ALPHA:
      return "RGBA";
    case PNG_COLOR_TYPE_PALETTE:
      return "palette";
    default:
      return "colour type " + std::to_string(colour_type);
  }
}

// Raw decoded image in the file's own layout after the requested transforms.
struct Decoded {
  int width = 0, height = 0, channels = 0, bit_depth = 0;
  std::vector<std::uint8_t> bytes;  // rows back to back, rowbytes each
  std::size_t rowbytes = 0;
};

enum class Want { k8, k16 };

// Decodes `path`. For k8, palette/low-bit gray are expanded to 8 bits, alpha stripped,
// 16-bit is rejected; for k16 only 16-bit single-channel gray is accepted.
Decoded decode(const std::string& path, Want want) {
  FilePtr file(std::fopen(path.c_str(), "rb"));
  if (!file) throw Error("cannot open PNG '" + path + "': file missing or unreadable");

  png_byte signature[8] = {0};
  if (std::fread(signature, 1, 8, file.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0) {
    throw Error("'" + path + "' is not a PNG file (bad signature)");
  }

  ErrorSink sink;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &sink, on_png_error, on_png_warning);
  if (!png) throw Error("libpng could not allocate a read struct for '" + path + "'");
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    throw Error("libpng could not allocate an info struct for '" + path + "'");
  }

  // Everything that may be modified between setjmp and longjmp lives in `out` (declared
  // before setjmp, only touched through a pointer) so it is well defined after the jump.
  Decoded out;
  Decoded* result = &out;
  std::string refusal;  // set when the image is valid PNG but the wrong kind or too large
  std::string* refused = &refusal;
  std::vector<png_bytep> rows;
  std::string found;  // declared before setjmp: a longjmp must not skip a destructor

  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error("corrupt PNG '" + path + "': " + sink.message);
  }

  png_init_io(png, file.get());
  png_set_sig_bytes(png, 8);
  // Only the pixels are wanted: every ancillary chunk but tRNS is skipped unread. libpng
  // allocates a known ancillary chunk's whole length before it checks the data (a 60-byte
  // file whose sPLT chunk claims 1.9 GB asked for 1.9 GB); a skipped chunk is read in
  // small pieces and costs nothing.
  png_set_keep_unknown_chunks(png, PNG_HANDLE_CHUNK_NEVER, nullptr, -1);
  png_read_info(png, info);

  const int bit_depth = png_get_bit_depth(png, info);
  const int colour_type = png_get_color_type(png, info);
  found = std::to_string(bit_depth) + "-bit " + colour_type_name(colour_type);
  try {  // our own exception, thrown and caught here: no libpng frame in between
    check_image_size(png_get_image_width(png, info), png_get_image_height(png, info), "PNG '" + path + "'");
  } catch (const Error& e) {
    *refused = e.what();
  }

  if (!refused->empty()) {
    // too large: nothing is decoded
  } else if (want == Want::k16) {
    if (bit_depth != 16 || colour_type != PNG_COLOR_TYPE_GRAY) {
      *refused =
          "wrong PNG format in '" + path + "': expected a 16-bit single-channel (gray) depth PNG, found " + found;
    } else {
      // PNG stores 16-bit samples big-endian; swap to host order on little-endian machines.
      const std::uint16_t probe = 1;
      if (*reinterpret_cast<const std::uint8_t*>(&probe) == 1) png_set_swap(png);
    }
  } else {
    if (bit_depth == 16) {
      *refused = "wrong PNG format in '" + path + "': expected an 8-bit gray/RGB/RGBA/palette PNG, found " + found;
    } else {
      if (colour_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
      if (colour_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
      // A palette's tRNS chunk becomes an alpha channel on expansion: dropped like any alpha.
      if ((colour_type & PNG_COLOR_MASK_ALPHA) || png_get_valid(png, info, PNG_INFO_tRNS)) {
        png_set_strip_alpha(png);
      }
    }
  }

  if (refused->empty()) {
    const int passes = png_set_interlace_handling(png);
    png_read_update_info(png, info);
    result->width = static_cast<int>(png_get_image_width(png, info));
    result->height = static_cast<int>(png_get_image_height(png, info));
    result->channels = png_get_channels(png, info);
    result->bit_depth = png_get_bit_depth(png, info);
    result->rowbytes = png_get_rowbytes(png, info);
    const auto height = static_cast<std::size_t>(result->height);
    if (passes > 1) {  // Adam7 fills every row in each pass: the whole image at once
      result->bytes.resize(result->rowbytes * height);
      rows.resize(height);
      for (std::size_t y = 0; y < height; ++y) rows[y] = result->bytes.data() + result->rowbytes * y;
      png_read_image(png, rows.data());
    } else {
      // Row by row, the buffer growing with the rows actually decoded: a truncated file
      // claiming a huge image fails before the memory its header asks for is taken.
      for (std::size_t y = 0; y < height; ++y) {
        result->bytes.resize(result->rowbytes * (y + 1));
        png_read_row(png, result->bytes.data() + result->rowbytes * y, nullptr);
      }
    }
    png_read_end(png, nullptr);
  }
  png_destroy_read_struct(&png, &info, nullptr);
  if (!refusal.empty()) throw Error(refusal);
  return out;
}

// Encodes rows of `bit_depth` samples. `row_at(y)` returns a pointer to row y in PNG
// byte order. Writes to a temporary file and renames it over `path`.
template <typename RowAt>
void encode(const std::string& path, int width, int height, int colour_type, int bit_depth, bool swap16, RowAt row_at) {
  if (width <= 0 || height <= 0) {
    throw Error("cannot write PNG '" + path + "': empty image " + std::to_string(width) + "x" + std::to_string(height));
  }
  check_output_target(path);
  const std::string tmp = temporary_path_for(path);
  FilePtr file(std::fopen(tmp.c_str(), "wbx"));
  if (!file) throw Error("cannot write PNG '" + path + "': folder missing or not writable");

  ErrorSink sink;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, on_png_error, on_png_warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    if (png) png_destroy_write_struct(&png, nullptr);
    file.reset();
    std::remove(tmp.c_str());
    throw Error("libpng could not allocate a write struct for '" + path + "'");
  }
  errno = 0;
  if (setjmp(png_jmpbuf(png))) {
    // libpng says "Write Error"; the system's cause (disk full, file too large) is in errno.
    const std::string cause = errno != 0 ? std::string(" (") + std::strerror(errno) + ")" : "";
    png_destroy_write_struct(&png, &info);
    file.reset();
    std::remove(tmp.c_str());
    throw Error("cannot write PNG '" + path + "': " + sink.message + cause);
  }
  png_init_io(png, file.get());
  // Fast deflate: rendering sequences is dominated by compression at the default level,
  // and file size matters little for generated data (decoding is unaffected).
  png_set_compression_level(png, 1);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), bit_depth, colour_type,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (swap16) png_set_swap(png);
  for (int y = 0; y < height; ++y) png_write_row(png, row_at(y));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);

  const bool flushed = std::fflush(file.get()) == 0 && !std::ferror(file.get());
  file.reset();
  if (!flushed) {
    const std::string cause = std::strerror(errno);
    std::remove(tmp.c_str());
    throw Error("cannot write PNG '" + path + "': " + cause);
  }
  commit_temporary(tmp, path);
}

bool host_is_little_endian() {
  const std::uint16_t probe = 1;
  return *reinterpret_cast<const std::uint8_t*>(&probe) == 1;
}

}  // namespace

Png8 read_png8(const std::string& path) {
  Decoded d = decode(path, Want::k8);
  if (d.bit_depth != 8 || (d.channels != 1 && d.channels != 3)) {
    throw Error("wrong PNG format in '" + path + "': decoded to " + std::to_string(d.channels) + " channels of " +
                std::to_string(d.bit_depth) + " bits, expected 8-bit gray or RGB");
  }
  Png8 img;
  img.width = d.width;
  img.height = d.height;
  img.channels = d.channels;
  const std::size_t row = static_cast<std::size_t>(d.width) * d.channels;
  img.data.resize(row * d.height);
  for (int y = 0; y < d.height; ++y) {
    std::copy_n(d.bytes.data() + d.rowbytes * y, row, img.data.data() + row * y);
  }
  return img;
}

Png16 read_png16(const std::string& path) {
  Decoded d = decode(path, Want::k16);
  Png16 img;
  img.width = d.width;
  img.height = d.height;
  img.data.resize(static_cast<std::size_t>(d.width) * d.height);
  for (int y = 0; y < d.height; ++y) {
    std::memcpy(img.data.data() + static_cast<std::size_t>(d.width) * y, d.bytes.data() + d.rowbytes * y,
                sizeof(std::uint16_t) * d.width);
  }
  return img;
}

void write_png8(const std::string& path, const Png8& image) {
  if (image.channels != 1 && image.channels != 3) {
    throw Error("cannot write PNG '" + path + "': " + std::to_string(image.channels) + " channels (expected 1 or 3)");
  }
  const std::size_t row = static_cast<std::size_t>(image.width) * image.channels;
  if (image.data.size() != row * static_cast<std::size_t>(image.height)) {
    throw Error("cannot write PNG '" + path + "': data size " + std::to_string(image.data.size()) + " does not match " +
                std::to_string(image.width) + "x" + std::to_string(image.height) + "x" +
                std::to_string(image.channels));
  }
  const int colour = image.channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB;
  encode(path, image.width, image.height, colour, 8, false,
         [&](int y) { return const_cast<png_bytep>(image.data.data() + row * y); });
}

void write_png16(const std::string& path, const Png16& image) {
  if (image.data.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height)) {
    throw Error("cannot write PNG '" + path + "': data size " + std::to_string(image.data.size()) + " does not match " +
                std::to_string(image.width) + "x" + std::to_string(image.height));
  }
  encode(path, image.width, image.height, PNG_COLOR_TYPE_GRAY, 16, host_is_little_endian(), [&](int y) {
    return reinterpret_cast<png_bytep>(const_cast<std::uint16_t*>(image.data.data()) +
                                       static_cast<std::size_t>(image.width) * y);
  });
}

}  // namespace bivo::odometry::io

#include "odometry/io/tum_dataset.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "odometry/io/png_io.h"
#include "odometry/io/sensor_description.h"
#include "odometry/io/timestamp_matching.h"
#include "odometry/io/tum_text.h"
#include "solvers/error.h"

namespace bivo::odometry::io {
namespace {

namespace fs = std::filesystem;

std::string join(const std::string& directory, const std::string& file) {
  if (fs::path(file).is_absolute()) return file;
  return (fs::path(directory) / file).string();
}

std::string basename_of(const std::string& path) { return fs::path(path).filename().string(); }

}  // namespace

std::vector<ListedFile> read_file_list(const std::string& path) {
  std::vector<ListedFile> out;
  for_each_tum_line(path, "list", [&](const TumTextLine& l) {
    const auto& tokens = l.tokens;
    const int line_no = l.line_no;
    if (tokens.size() != 2) {
      throw Error(tum_line_error(path, line_no, "expected 'timestamp filename', got '" + excerpt(l.raw) + "'"));
    }
    ListedFile f;
    f.timestamp = parse_tum_number(tokens[0], path, line_no, "a timestamp");
    f.file = tokens[1];
    f.line = line_no;
    if (!out.empty() && f.timestamp <= out.back().timestamp) {
      const std::string relation = f.timestamp == out.back().timestamp ? " repeats" : " is earlier than";
      throw Error(tum_line_error(path, line_no,
                                 "timestamp " + excerpt(tokens[0]) + relation + " line " +
                                     std::to_string(out.back().line) + "'s (list must be strictly increasing)"));
    }
    out.push_back(f);
  });
  if (out.empty()) throw Error("list '" + path + "' has no entries");
  return out;
}

std::vector<AssociatedFrame> associate_lists(const std::vector<ListedFile>& rgb, const std::vector<ListedFile>& depth,
                                             const std::string& directory, double max_dt) {
  if (!(max_dt > 0.0)) throw Error("association max dt must be positive, got " + std::to_string(max_dt));
  std::vector<double> rgb_stamps, depth_stamps;
  for (const auto& f : rgb) rgb_stamps.push_back(f.timestamp);
  for (const auto& f : depth) depth_stamps.push_back(f.timestamp);
  const auto matches = associate_timestamps(rgb_stamps, depth_stamps, max_dt);
  std::vector<AssociatedFrame> out;
  out.reserve(matches.size());
  for (const auto& [i, j] : matches) {
    AssociatedFrame f;
    f.rgb_time = rgb[i].timestamp;
    f.depth_time = depth[j].timestamp;
    f.rgb_path = join(directory, rgb[i].file);
    f.depth_path = join(directory, depth[j].file);
    f.origin = "rgb.txt:" + std::to_string(rgb[i].line) + " + depth.txt:" + std::to_string(depth[j].line);
    out.push_back(f);
  }
  return out;
}

std::vector<AssociatedFrame> read_associations(const std::string& path, const std::string& directory, double max_dt) {
  std::vector<AssociatedFrame> out;
  for_each_tum_line(path, "list", [&](const TumTextLine& l) {
    const auto& tokens = l.tokens;
    const int line_no = l.line_no;
    const std::string where = path + ":" + std::to_string(line_no);
    if (tokens.size() != 4) {
      throw Error(where + ": expected 't_rgb rgb_file t_depth depth_file', got '" + excerpt(l.raw) + "'");
    }
    AssociatedFrame f;
    f.rgb_time = parse_tum_number(tokens[0], path, line_no, "a timestamp");
    f.rgb_path = join(directory, tokens[1]);
    f.depth_time = parse_tum_number(tokens[2], path, line_no, "a timestamp");
    f.depth_path = join(directory, tokens[3]);
    f.origin = basename_of(path) + ":" + std::to_string(line_no);
    if (!(std::abs(f.rgb_time - f.depth_time) < max_dt)) {
      throw Error(where + ": rgb and depth timestamps differ by " +
                  std::to_string(std::abs(f.rgb_time - f.depth_time)) + " s (limit " + std::to_string(max_dt) + " s)");
    }
    if (!out.empty() && f.rgb_time <= out.back().rgb_time) {
      throw Error(where + ": rgb timestamp " + excerpt(tokens[0]) +
                  (f.rgb_time == out.back().rgb_time ? " repeats" : " is earlier than") +
                  " the previous line's (list must be strictly increasing)");
    }
    out.push_back(f);
  });
  if (out.empty()) throw Error("list '" + path + "' has no entries");
  return out;
}

TumSequence open_tum_sequence(const std::string& directory, const SequenceOptions& options) {
  if (!fs::is_directory(directory)) throw Error("sequence directory '" + directory + "' does not exist");
  TumSequence seq;
  seq.directory = directory;
  seq.name = fs::path(directory).lexically_normal().filename().string();
  if (seq.name.empty()) seq.name = fs::path(directory).lexically_normal().parent_path().filename().string();
  seq.intrinsics = options.intrinsics ? *options.intrinsics : intrinsics_for_sequence(seq.name);
  seq.distortion = options.distortion ? *options.distortion : distortion_for_sequence(seq.name);

  const std::string associations = join(directory, "associations.txt");
  if (fs::exists(associations)) {
    seq.frames = read_associations(associations, directory, options.max_association_dt);
    seq.list_files = {associations};
  } else {
    const std::string rgb_list = join(directory, "rgb.txt");
    const std::string depth_list = join(directory, "depth.txt");
    const auto rgb = read_file_list(rgb_list);
    const auto depth = read_file_list(depth_list);
    seq.frames = associate_lists(rgb, depth, directory, options.max_association_dt);
    seq.list_files = {rgb_list, depth_list};
    if (seq.frames.empty()) {
      throw Error("no rgb/depth association within " + std::to_string(options.max_association_dt) + " s between '" +
                  rgb_list + "' (" + std::to_string(rgb.size()) + " entries) and '" + depth_list + "' (" +
                  std::to_string(depth.size()) + " entries)");
    }
  }
  if (options.max_frames >= 0 && int(seq.frames.size()) > options.max_frames) {
    seq.frames.resize(static_cast<std::size_t>(options.max_frames));
  }
  const std::string gt = join(directory, "groundtruth.txt");
  if (fs::exists(gt)) {
    seq.groundtruth = read_tum_trajectory(gt);
    seq.list_files.push_back(gt);
  }
  seq.readout_time = stated_readout_time(directory);
  seq.vignetting = stated_vignetting(directory);
  if (seq.readout_time || seq.vignetting) seq.list_files.push_back(sensor_description_path(directory));
  return seq;
}

RgbdImage load_rgbd_image(const AssociatedFrame& frame, int expected_width, int expected_height) {
  const std::string from = " (listed at " + frame.origin + ")";
  Png8 colour;
  Png16 depth;
  try {
    colour = read_png8(frame.rgb_path);
  } catch (const Error& e) {
    throw Error(std::string(e.what()) + from);
  }
  try {
    depth = read_png16(frame.depth_path);
  } catch (const Error& e) {
    throw Error(std::string(e.what()) + from);
  }
  if (colour.width != depth.width || colour.height != depth.height) {
    throw Error("image size mismatch: '" + frame.rgb_path + "' is " + std::to_string(colour.width) + "x" +
                std::to_string(colour.height) + " but '" + frame.depth_path + "' is " + std::to_string(depth.width) +
                "x" + std::to_string(depth.height) + from);
  }
  if (expected_width > 0 && (colour.width != expected_width || colour.height != expected_height)) {
    throw Error("wrong image size: '" + frame.rgb_path + "' is " + std::to_string(colour.width) + "x" +
                std::to_string(colour.height) + ", the sequence's frames are " + std::to_string(expected_width) + "x" +
                std::to_string(expected_height) + from);
  }
  RgbdImage im;
  im.width = colour.width;
  im.height = colour.height;
  im.timestamp = frame.rgb_time;
  im.depth_delay = frame.depth_time - frame.rgb_time;
  const std::size_t n = static_cast<std::size_t>(im.width) * im.height;
  im.intensity.resize(n);
  im.depth.resize(n);
  if (colour.channels == 3) {
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint8_t* p = colour.data.data() + 3 * i;
      im.intensity[i] = 0.299f * p[0] + 0.587f * p[1] + 0.114f * p[2];
    }
  } else {
    for (std::size_t i = 0; i < n; ++i) im.intensity[i] = colour.data[i];
  }
  const float scale = static_cast<float>(1.0 / kTumDepthUnitsPerMetre);
  for (std::size_t i = 0; i < n; ++i) im.depth[i] = depth.data[i] * scale;
  return im;
}

}  // namespace bivo::odometry::io

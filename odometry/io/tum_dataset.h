#pragma once
// TUM RGB-D sequences on disk: the file lists (rgb.txt, depth.txt, associations.txt,
// groundtruth.txt), rgb/depth association by nearest timestamp, and loading ONE frame at a
// time (a run holds the pair it works on, never the whole sequence).
//
//   TumSequence seq = open_tum_sequence("/data/tum/rgbd_dataset_freiburg1_rpy");
//   for (const AssociatedFrame& f : seq.frames) { RgbdImage im = load_rgbd_image(f); ... }
#include <optional>
#include <string>
#include <vector>

#include "odometry/io/camera_intrinsics.h"
#include "odometry/io/lens_distortion.h"
#include "odometry/io/trajectory.h"

namespace bivo::odometry::io {

// One line "timestamp filename" of rgb.txt / depth.txt.
struct ListedFile {
  double timestamp = 0.0;
  std::string file;  // as written (relative to the sequence directory)
  int line = 0;      // line number in the list, for error messages
};

// Reads a TUM file list; '#' comments, blank lines and CRLF are tolerated. Throws
// bivo::Error naming file and line on a malformed line, a non-finite, repeated or
// decreasing timestamp, an empty list, and more lines than input_limits() allow.
std::vector<ListedFile> read_file_list(const std::string& path);

struct AssociatedFrame {
  double rgb_time = 0.0, depth_time = 0.0;
  std::string rgb_path, depth_path;  // full paths
  std::string origin;                // "rgb.txt:12 + depth.txt:13" or "associations.txt:5"
};

// Pairs each rgb entry with the depth entry of nearest timestamp, one to one, greedily in
// order of increasing |dt| (as TUM's associate.py, associate_timestamps), keeping pairs with
// |dt| < max_dt; the result is sorted by rgb time. Paths are joined to `directory`.
std::vector<AssociatedFrame> associate_lists(const std::vector<ListedFile>& rgb, const std::vector<ListedFile>& depth,
                                             const std::string& directory, double max_dt);

// Reads associations.txt lines "t_rgb rgb_file t_depth depth_file" (associate.py output).
// Throws on malformed lines, |t_rgb - t_depth| >= max_dt, rgb times not strictly increasing
// or empty lists.
std::vector<AssociatedFrame> read_associations(const std::string& path, const std::string& directory, double max_dt);

struct SequenceOptions {
  double max_association_dt = 0.02;      // seconds
  std::optional<Intrinsics> intrinsics;  // override of the preset chosen by name
  std::optional<Distortion> distortion;  // override of the preset chosen by name
  int max_frames = -1;                   // keep only the first N associated frames (-1: all)
};

struct TumSequence {
  std::string directory;
  std::string name;  // last path component, e.g. rgbd_dataset_freiburg1_rpy
  Intrinsics intrinsics;
  Distortion distortion;                  // of the images as stored (lens_distortion.h)
  std::vector<AssociatedFrame> frames;    // sorted by rgb time
  std::optional<Trajectory> groundtruth;  // when groundtruth.txt exists
  // The colour camera's rolling-shutter readout [s] as the sequence states it (scene.json of
  // a bivo synth rendering, sensor_description.h); none for real TUM sequences.
  std::optional<double> readout_time;
  // The colour camera's fall-off 1 - k rho^2 as the sequence states it (vignetting.h); none
  // for real TUM sequences.
  std::optional<double> vignetting;
  std::vector<std::string> list_files;  // the text files read (lists, groundtruth.txt, scene.json)
};

// associations.txt when present, otherwise rgb.txt + depth.txt associated by timestamp.
// Throws bivo::Error when the directory or a list is missing, a list is empty or unsorted,
// or no rgb/depth pair lies within max_association_dt (naming both lists).
TumSequence open_tum_sequence(const std::string& directory, const SequenceOptions& options = {});

// One frame's raw data at full resolution: intensity 0..255 (0.299 R + 0.587 G + 0.114 B,
// gray PNGs taken as is) and depth in metres (PNG value / 5000, 0 = missing).
struct RgbdImage {
  int width = 0, height = 0;
  double timestamp = 0.0;    // rgb time
  double depth_delay = 0.0;  // depth time - rgb time [s] (unsynchronized sensors)
  std::vector<float> intensity;
  std::vector<float> depth;
};

// Loads and checks one frame: 8-bit RGB/gray colour, 16-bit depth, equal sizes, and (when
// expected_width/height > 0) the sequence's size. Errors name the file and its list line.
RgbdImage load_rgbd_image(const AssociatedFrame& frame, int expected_width = 0, int expected_height = 0);

inline constexpr double kTumDepthUnitsPerMetre = 5000.0;

}  // namespace bivo::odometry::io

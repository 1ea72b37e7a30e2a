#pragma once
// Textures of the synthetic scenes: RGB reflectance images (albedo in [0, 1]) with a mip
// pyramid, sampled trilinearly at the camera pixel's footprint so distant or grazing
// surfaces are prefiltered instead of aliased. Generated procedurally and deterministically
// from a seed: colourful "posters" (texture) and near-uniform "white foil" (no texture).
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace bivo::odometry::synth {

class MipTexture {
 public:
  // `level0` is row-major RGB, width*height texels; width and height are powers of two.
  MipTexture(int width, int height, std::vector<Eigen::Vector3f> level0);

  int width() const { return widths_[0]; }
  int height() const { return heights_[0]; }
  int levels() const { return static_cast<int>(levels_.size()); }

  // Albedo at texture coordinates (s, t) in [0, 1]^2 (clamped), prefiltered for a sample
  // footprint of `footprint` level-0 texels (trilinear: bilinear in the two nearest levels).
  Eigen::Vector3f sample(float s, float t, float footprint) const;

  // Mean albedo over the whole texture (the 1x1 level).
  Eigen::Vector3f mean() const { return levels_.back()[0]; }

 private:
  Eigen::Vector3f bilinear(int level, float s, float t) const;
  std::vector<int> widths_, heights_;
  std::vector<std::vector<Eigen::Vector3f>> levels_;
};

// A poster: white margin, colour-gradient background, random discs, rectangles and rings,
// and lines of dark glyph-like blocks, like the printed posters on the TUM panels.
// Each texel is the average of 2x2 analytic sub-samples (anti-aliased shape edges).
MipTexture make_poster_texture(std::uint64_t seed, int width = 512, int height = 512);

// Near-uniform matte material (white foil, painted wall, floor): constant `albedo` times a
// smooth variation of relative amplitude `variation` (e.g. 0.01) on a scale of ~1/4 of
// the texture, so intensity gradients are tiny but not exactly zero.
MipTexture make_uniform_texture(std::uint64_t seed, const Eigen::Vector3f& albedo, float variation, int size = 64);

}  // namespace bivo::odometry::synth

#include "odometry/synth/texture.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "odometry/synth/random.h"
#include "solvers/error.h"

namespace bivo::odometry::synth {

namespace {

bool is_power_of_two(int n) { return n > 0 && (n & (n - 1)) == 0; }

Eigen::Vector3f random_saturated_colour(HashRng& rng) {
  // A random hue at high saturation, as printed poster inks; HSV -> RGB with V in [0.5, 1].
  const float h = static_cast<float>(rng.uniform(0.0, 6.0));
  const float s = static_cast<float>(rng.uniform(0.55, 1.0));
  const float v = static_cast<float>(rng.uniform(0.5, 1.0));
  const float c = v * s, x = c * (1.0f - std::fabs(std::fmod(h, 2.0f) - 1.0f)), m = v - c;
  Eigen::Vector3f rgb;
  switch (static_cast<int>(h)) {
    case 0:
      rgb = {c, x, 0};
      break;
    case 1:
      rgb = {x, c, 0};
      break;
    case 2:
      rgb = {0, c, x};
      break;
    case 3:
      rgb = {0, x, c};
      break;
    case 4:
      rgb = {x, 0, c};
      break;
    default:
      rgb = {c, 0, x};
      break;
  }
  return rgb + Eigen::Vector3f::Constant(m);
}

struct Shape {
  enum Kind { kDisc, kRing, kRect } kind;
  float cx, cy, a, b, angle;  // centre; radius/half-size a, b (ring: outer, inner)
  Eigen::Vector3f colour;
  bool contains(float x, float y) const {
    const float dx = x - cx, dy = y - cy;
    if (kind == kDisc) return dx * dx + dy * dy <= a * a;
    if (kind == kRing) {
      const float r2 = dx * dx + dy * dy;
      return r2 <= a * a && r2 >= b * b;
    }
    const float c = std::cos(angle), s = std::sin(angle);
    return std::fabs(c * dx + s * dy) <= a && std::fabs(-s * dx + c * dy) <= b;
  }
};

// A paragraph of "text": lines of glyph cells, each glyph a random 3x5 bitmap, with word
// gaps; evaluated in O(1) per sample from hashes of the cell index.
struct Paragraph {
  float x0, y0, x1, y1, line_height, glyph_width;
  std::uint64_t seed;
  Eigen::Vector3f colour;
  bool ink(float x, float y) const {
    if (x < x0 || x >= x1 || y < y0 || y >= y1) return false;
    const int line = static_cast<int>((y - y0) / line_height);
    const float ly = (y - y0) / line_height - line;  // 0..1 within the line
    if (ly > 0.7f) return false;                     // interline spacing
    const int cell = static_cast<int>((x - x0) / glyph_width);
    const float lx = (x - x0) / glyph_width - cell;
    if (lx > 0.8f) return false;  // letter spacing
    const std::uint64_t h = hash3(seed, static_cast<std::uint64_t>(line), static_cast<std::uint64_t>(cell));
    if ((h & 7u) == 0) return false;  // word gap
    const int gx = std::min(2, static_cast<int>(lx / 0.8f * 3.0f));
    const int gy = std::min(4, static_cast<int>(ly / 0.7f * 5.0f));
    return (h >> (8 + gy * 3 + gx)) & 1u;
  }
};

}  // namespace

MipTexture::MipTexture(int width, int height, std::vector<Eigen::Vector3f> level0) {
  if (!is_power_of_two(width) || !is_power_of_two(height)) {
    throw Error("texture size " + std::to_string(width) + "x" + std::to_string(height) + " is not a power of two");
  }
  if (level0.size() != static_cast<std::size_t>(width) * height) {
    throw Error("texture data has " + std::to_string(level0.size()) + " texels, expected " +
                std::to_string(width * height));
  }
  widths_.push_back(width);
  heights_.push_back(height);
  levels_.push_back(std::move(level0));
  // Box-filter pyramid down to 1x1 (a non-square texture keeps halving its long side).
  while (widths_.back() > 1 || heights_.back() > 1) {
    const int w = widths_.back(), h = heights_.back();
    const int nw = std::max(1, w / 2), nh = std::max(1, h / 2);
    const auto& src = levels_.back();
    std::vector<Eigen::Vector3f> dst(static_cast<std::size_t>(nw) * nh);
    for (int y = 0; y < nh; ++y) {
      for (int x = 0; x < nw; ++x) {
        const int x0 = std::min(2 * x, w - 1), x1 = std::min(2 * x + 1, w - 1);
        const int y0 = std::min(2 * y, h - 1), y1 = std::min(2 * y + 1, h - 1);
        dst[y * nw + x] = 0.25f * (src[y0 * w + x0] + src[y0 * w + x1] + src[y1 * w + x0] + src[y1 * w + x1]);
      }
    }
    widths_.push_back(nw);
    heights_.push_back(nh);
    levels_.push_back(std::move(dst));
  }
}

Eigen::Vector3f MipTexture::bilinear(int level, float s, float t) const {
  const int w = widths_[level], h = heights_[level];
  const auto& d = levels_[level];
  const float x = std::clamp(s, 0.0f, 1.0f) * w - 0.5f;
  const float y = std::clamp(t, 0.0f, 1.0f) * h - 0.5f;
  const float fx0 = std::floor(x), fy0 = std::floor(y);
  const float ax = x - fx0, ay = y - fy0;
  const int x0 = std::clamp(static_cast<int>(fx0), 0, w - 1), x1 = std::clamp(static_cast<int>(fx0) + 1, 0, w - 1);
  const int y0 = std::clamp(static_cast<int>(fy0), 0, h - 1), y1 = std::clamp(static_cast<int>(fy0) + 1, 0, h - 1);
  return (1 - ay) * ((1 - ax) * d[y0 * w + x0] + ax * d[y0 * w + x1]) +
         ay * ((1 - ax) * d[y1 * w + x0] + ax * d[y1 * w + x1]);
}

Eigen::Vector3f MipTexture::sample(float s, float t, float footprint) const {
  const float lod = std::clamp(std::log2(std::max(footprint, 1e-6f)), 0.0f, static_cast<float>(levels() - 1));
  const int l0 = static_cast<int>(lod);
  const float a = lod - l0;
  if (a == 0.0f || l0 + 1 >= levels()) return bilinear(l0, s, t);
  return (1 - a) * bilinear(l0, s, t) + a * bilinear(l0 + 1, s, t);
}

MipTexture make_poster_texture(std::uint64_t seed, int width, int height) {
  HashRng rng(seed, 0x706f73746572ull);  // "poster"
  const Eigen::Vector3f paper(0.92f, 0.92f, 0.90f);
  const Eigen::Vector3f c0 = random_saturated_colour(rng), c1 = random_saturated_colour(rng);
  const float gdir = static_cast<float>(rng.uniform(0.0, 6.283185307179586));
  const float gx = std::cos(gdir), gy = std::sin(gdir);
  const float margin = static_cast<float>(rng.uniform(0.02, 0.05));

  std::vector<Shape> shapes;
  const int n_shapes = rng.integer(10, 18);
  for (int i = 0; i < n_shapes; ++i) {
    Shape s;
    const double k = rng.uniform();
    s.kind = k < 0.4 ? Shape::kDisc : (k < 0.6 ? Shape::kRing : Shape::kRect);
    s.cx = static_cast<float>(rng.uniform(0.05, 0.95));
    s.cy = static_cast<float>(rng.uniform(0.05, 0.95));
    s.a = static_cast<float>(rng.uniform(0.03, 0.22));
    s.b = s.kind == Shape::kRing ? s.a * static_cast<float>(rng.uniform(0.5, 0.85))
                                 : static_cast<float>(rng.uniform(0.03, 0.22));
    s.angle = static_cast<float>(rng.uniform(0.0, 3.14159265));
    s.colour = rng.uniform() < 0.2 ? Eigen::Vector3f(0.95f, 0.95f, 0.95f) : random_saturated_colour(rng);
    shapes.push_back(s);
  }
  std::vector<Paragraph> text;
  const int n_text = rng.integer(2, 4);
  for (int i = 0; i < n_text; ++i) {
    Paragraph p;
    p.glyph_width = static_cast<float>(rng.uniform(0.012, 0.035));
    p.line_height = p.glyph_width * 1.9f;
    p.x0 = static_cast<float>(rng.uniform(0.06, 0.5));
    p.x1 = std::min(0.94f, p.x0 + static_cast<float>(rng.uniform(0.2, 0.6)));
    p.y0 = static_cast<float>(rng.uniform(0.06, 0.8));
    p.y1 = std::min(0.94f, p.y0 + p.line_height * rng.integer(1, 6));
    p.seed = hash3(seed, 0x74657874ull, static_cast<std::uint64_t>(i));
    p.colour = rng.uniform() < 0.6 ? Eigen::Vector3f(0.08f, 0.08f, 0.1f) : Eigen::Vector3f(0.97f, 0.97f, 0.97f);
    text.push_back(p);
  }

  const auto paint = [&](float x, float y) -> Eigen::Vector3f {
    if (x < margin || x > 1 - margin || y < margin || y > 1 - margin) return paper;
    for (auto it = text.rbegin(); it != text.rend(); ++it) {
      if (it->ink(x, y)) return it->colour;
    }
    for (auto it = shapes.rbegin(); it != shapes.rend(); ++it) {
      if (it->contains(x, y)) return it->colour;
    }
    const float g = std::clamp(0.5f + 0.7f * (gx * (x - 0.5f) + gy * (y - 0.5f)), 0.0f, 1.0f);
    return (1 - g) * c0 + g * c1;
  };

  std::vector<Eigen::Vector3f> texels(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      Eigen::Vector3f acc = Eigen::Vector3f::Zero();
      for (int sy = 0; sy < 2; ++sy) {
        for (int sx = 0; sx < 2; ++sx) {
          acc += paint((x + 0.25f + 0.5f * sx) / width, (y + 0.25f + 0.5f * sy) / height);
        }
      }
      texels[static_cast<std::size_t>(y) * width + x] = 0.25f * acc;
    }
  }
  return MipTexture(width, height, std::move(texels));
}

MipTexture make_uniform_texture(std::uint64_t seed, const Eigen::Vector3f& albedo, float variation, int size) {
  HashRng rng(seed, 0x756e69666f726dull);  // "uniform"
  // Two smooth sinusoidal undulations of random phase: variation is low-frequency only.
  const float p1 = static_cast<float>(rng.uniform(0, 6.2832)), p2 = static_cast<float>(rng.uniform(0, 6.2832));
  std::vector<Eigen::Vector3f> texels(static_cast<std::size_t>(size) * size);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const float u = (x + 0.5f) / size, v = (y + 0.5f) / size;
      const float m = 1.0f + variation * 0.5f * (std::sin(6.2832f * 2 * u + p1) + std::sin(6.2832f * 2 * v + p2));
      texels[static_cast<std::size_t>(y) * size + x] = m * albedo;
    }
  }
  return MipTexture(size, size, std::move(texels));
}

}  // namespace bivo::odometry::synth

#pragma once
// Procedural grey-level textures for the simulator (deterministic in the seed) and their mip
// pyramids. Every texture tiles seamlessly (power-of-two size, patterns periodic in it), so a
// surface can repeat it with wrap-around addressing.
#include <cmath>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace adugs::data {

class SimRng;

// A square power-of-two texture with box-filtered mip levels (level 0 = full size).
class SimTexture {
 public:
  explicit SimTexture(const cv::Mat& level0_u8);  // CV_8UC1, square power of two

  int size() const { return size_; }
  int levels() const { return static_cast<int>(mips_.size()); }
  const cv::Mat& level(int i) const { return mips_[static_cast<size_t>(i)]; }  // CV_8UC1

  // Bilinear sample at texel coordinates (s, t) >= 0 of level 0 (texel i covers [i, i+1)), wrapped,
  // blended between the two mip levels around `lod` (trilinear, narrowed: see sample()). lod <= 0
  // means full resolution.
  float sample(float s, float t, float lod) const;

 private:
  float sampleLevel(int level, float s, float t) const;

  // 8-bit levels keep the whole pyramid small enough to stay in cache while a frame is shaded.
  struct Level {
    const uint8_t* data;
    int size;
    int mask;
    float scale;  // 2^-level
  };
  int size_;
  std::vector<cv::Mat> mips_;
  std::vector<Level> levels_;
};

// Inline: called for every pixel of every frame.
inline float SimTexture::sampleLevel(int lvl, float s, float t) const {
  const Level& m = levels_[static_cast<size_t>(lvl)];
  // Texel centres sit at i + 0.5.
  const float x = s * m.scale - 0.5f, y = t * m.scale - 0.5f;
  // s, t >= 0 so x, y >= -0.5: truncation of x + 1 is floor(x) + 1 (cheaper than std::floor).
  const int ix = static_cast<int>(x + 1.0f) - 1, iy = static_cast<int>(y + 1.0f) - 1;
  const float ax = x - static_cast<float>(ix), ay = y - static_cast<float>(iy);
  const int x0 = ix & m.mask, y0 = iy & m.mask;
  const int x1 = (x0 + 1) & m.mask, y1 = (y0 + 1) & m.mask;
  const uint8_t* r0 = m.data + y0 * m.size;
  const uint8_t* r1 = m.data + y1 * m.size;
  const float top = r0[x0] + ax * (float(r0[x1]) - float(r0[x0]));
  const float bottom = r1[x0] + ax * (float(r1[x1]) - float(r1[x0]));
  return top + ay * (bottom - top);
}

inline float SimTexture::sample(float s, float t, float lod) const {
  if (lod <= 0.0f) return sampleLevel(0, s, t);
  const int last = levels() - 1;
  if (lod >= static_cast<float>(last)) return sampleLevel(last, s, t);
  const int l0 = static_cast<int>(lod);
  // "Brilinear": blend the two levels only in the middle half of each level interval (weight still
  // continuous in lod, so no seams), one bilinear lookup elsewhere - half the cost of trilinear.
  const float w = 2.0f * (lod - static_cast<float>(l0)) - 0.5f;
  if (w <= 0.0f) return sampleLevel(l0, s, t);
  if (w >= 1.0f) return sampleLevel(l0 + 1, s, t);
  const float a = sampleLevel(l0, s, t);
  return a + w * (sampleLevel(l0 + 1, s, t) - a);
}

enum class SimTextureKind {
  kNoise,    // multi-octave value noise (plaster, concrete)
  kBricks,   // brick wall
  kTiles,    // floor tiles with stains
  kPosters,  // random blobs, rectangles and lines: dense corners for features
  kFacade,   // building front: wall noise with a grid of windows
  kRoad,     // asphalt with lane marks
  kPerson,   // clothing-like: coloured bands and folds
  kVehicle,  // car/bus side: body panel with a window band
  kChecker,  // 2x2 checker (validation marker): corner at the texture centre
};

// Builds one texture; `size` must be a power of two >= 8.
cv::Mat makeTexture(SimTextureKind kind, int size, SimRng& rng);

}  // namespace adugs::data

#pragma once
// Cut-out images of real walking people for the simulator (tracking needs movers a detector
// recognises, which textured boxes are not): a walk cycle is a few consecutive video frames of one
// person, each a grey image with an exact binary alpha mask. scripts/extract_walker_sprites.py
// cuts them from OpenCV's pedestrian video at build time (walkers.yaml + walker_NN/frame_MM.png,
// BGRA). The renderer draws a walker as an upright billboard turned toward the camera, alpha-tested
// so that the object mask is the person's silhouette.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace adugs::data {

// One cut-out: grey levels (where transparent: filled from the nearest opaque texels, so bilinear
// filtering at the silhouette never blends in the video's background) and the alpha mask, with
// 2x box-filtered mip levels of the grey image.
class SimSprite {
 public:
  // bgra: CV_8UC4 as cv::imread(..., IMREAD_UNCHANGED) gives a PNG with alpha.
  explicit SimSprite(const cv::Mat& bgra);

  int width() const { return mips_[0].cols; }
  int height() const { return mips_[0].rows; }
  // (a, b) in [0, 1) across and down the sprite: the alpha mask interpolated bilinearly, >= 0.5
  // (a magnified cut-out then has smooth, not blocky, outlines).
  bool opaque(float a, float b) const;
  // Grey level at texel coordinates (s, t) of level 0 (bilinear, clamped), mip level from lod.
  float sample(float s, float t, float lod) const;

 private:
  cv::Mat alpha_;              // CV_32FC1, 0 or 1
  std::vector<cv::Mat> mips_;  // CV_32FC1
};

struct SimWalkCycle {
  std::string name;
  std::vector<int> frames;  // indices into SimScene::sprites, in walking order
  // Image-space direction the person walks in the video: "left", "right", "towards", "away".
  std::string direction;
};

struct SimWalkerSet {
  std::vector<SimSprite> sprites;
  std::vector<SimWalkCycle> cycles;  // frames index `sprites`
};

// Reads DIR/walkers.yaml and its PNGs. Throws InputError naming the file and field when the index
// or a sprite is missing, unreadable, without alpha or empty.
SimWalkerSet loadWalkerSet(const std::string& dir);

// Where the build put the walkers cut from vtest.avi ("" when it could not: no opencv-doc);
// $ADUGS_WALKERS_DIR overrides it.
std::string defaultWalkersDir();

}  // namespace adugs::data

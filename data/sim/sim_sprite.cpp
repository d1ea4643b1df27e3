#include "data/sim/sim_sprite.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include <opencv2/imgproc.hpp>

#include "data/formats/image_file.h"
#include "data/input_error.h"

namespace adugs::data {

SimSprite::SimSprite(const cv::Mat& bgra) {
  if (bgra.type() != CV_8UC4 || bgra.empty()) throw std::invalid_argument("SimSprite: need a CV_8UC4 image");
  cv::Mat grey;
  cv::cvtColor(bgra, grey, cv::COLOR_BGRA2GRAY);
  cv::Mat alpha;
  cv::extractChannel(bgra, alpha, 3);
  cv::threshold(alpha, alpha, 127, 255, cv::THRESH_BINARY);
  alpha.convertTo(alpha_, CV_32F, 1.0 / 255);
  // Grow the opaque colours outward over the transparent texels (a few rings are enough for the
  // bilinear footprint of the coarse mip levels too).
  cv::Mat filled = grey.clone(), known = alpha.clone();
  for (int ring = 0; ring < 8 && cv::countNonZero(known) < static_cast<int>(known.total()); ++ring) {
    cv::Mat sum, count, grown;
    cv::Mat known_f, values;
    known.convertTo(known_f, CV_32F, 1.0 / 255);
    filled.convertTo(values, CV_32F);
    cv::boxFilter(values.mul(known_f), sum, CV_32F, {3, 3}, {-1, -1}, false);
    cv::boxFilter(known_f, count, CV_32F, {3, 3}, {-1, -1}, false);
    cv::dilate(known, grown, cv::Mat());
    for (int y = 0; y < filled.rows; ++y)
      for (int x = 0; x < filled.cols; ++x)
        if (!known.at<uint8_t>(y, x) && grown.at<uint8_t>(y, x))
          filled.at<uint8_t>(y, x) = cv::saturate_cast<uint8_t>(sum.at<float>(y, x) / count.at<float>(y, x));
    known = grown;
  }
  cv::Mat level;
  filled.convertTo(level, CV_32F);
  mips_.push_back(level);
  while (level.cols > 2 && level.rows > 2) {
    cv::Mat next;
    cv::resize(level, next, {(level.cols + 1) / 2, (level.rows + 1) / 2}, 0, 0, cv::INTER_AREA);
    mips_.push_back(next);
    level = next;
  }
}

namespace {

// Bilinear lookup of a CV_32FC1 image at texel coordinates (x, y) (centres at integers), clamped
// to the border texels.
float bilinearClamped(const cv::Mat& m, float x, float y) {
  x = std::clamp(x, 0.0f, static_cast<float>(m.cols - 1));
  y = std::clamp(y, 0.0f, static_cast<float>(m.rows - 1));
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, m.cols - 1), y1 = std::min(y0 + 1, m.rows - 1);
  const float ax = x - static_cast<float>(x0), ay = y - static_cast<float>(y0);
  const float* r0 = m.ptr<float>(y0);
  const float* r1 = m.ptr<float>(y1);
  const float top = r0[x0] + ax * (r0[x1] - r0[x0]);
  const float bottom = r1[x0] + ax * (r1[x1] - r1[x0]);
  return top + ay * (bottom - top);
}

}  // namespace

bool SimSprite::opaque(float a, float b) const {
  // Texel centres at i + 0.5.
  return bilinearClamped(alpha_, a * static_cast<float>(alpha_.cols) - 0.5f, b * static_cast<float>(alpha_.rows) - 0.5f) >=
         0.5f;
}

float SimSprite::sample(float s, float t, float lod) const {
  const int lvl = std::clamp(static_cast<int>(lod + 0.5f), 0, static_cast<int>(mips_.size()) - 1);
  const cv::Mat& m = mips_[static_cast<size_t>(lvl)];
  const float scale = static_cast<float>(m.cols) / static_cast<float>(mips_[0].cols);
  return bilinearClamped(m, s * scale - 0.5f, t * scale - 0.5f);
}

SimWalkerSet loadWalkerSet(const std::string& dir) {
  namespace fs = std::filesystem;
  const std::string index = (fs::path(dir) / "walkers.yaml").string();
  if (!fs::is_regular_file(index))
    throw InputError(index, 0, "", "walker sprite index not found (cut from vtest.avi at build time by "
                                   "scripts/extract_walker_sprites.py; needs Debian's opencv-doc)");
  YAML::Node root;
  try {
    root = YAML::LoadFile(index);
  } catch (const YAML::Exception& e) {
    throw InputError(index, e.mark.line + 1, "", std::string("not YAML: ") + e.what());
  }
  if (!root["walkers"] || !root["walkers"].IsSequence() || root["walkers"].size() == 0)
    throw InputError(index, 0, "walkers", "no list of walkers");
  SimWalkerSet set;
  for (const YAML::Node& w : root["walkers"]) {
    SimWalkCycle cycle;
    int frames = 0;
    try {
      cycle.name = w["name"].as<std::string>();
      frames = w["frames"].as<int>();
      cycle.direction = w["direction"].as<std::string>("");
    } catch (const YAML::Exception& e) {
      throw InputError(index, e.mark.line + 1, "walkers", std::string("each walker needs name and frames: ") + e.what());
    }
    if (frames < 1) throw InputError(index, 0, "walkers." + cycle.name + ".frames", "must be at least 1");
    for (int k = 0; k < frames; ++k) {
      char file[32];
      std::snprintf(file, sizeof file, "frame_%02d.png", k);
      const std::string path = (fs::path(dir) / cycle.name / file).string();
      const cv::Mat bgra = readImageFile(path, ImageRead::kUnchanged);
      if (bgra.type() != CV_8UC4) throw InputError(path, 0, "", "the sprite has no alpha channel (BGRA PNG expected)");
      cycle.frames.push_back(static_cast<int>(set.sprites.size()));
      set.sprites.emplace_back(bgra);
    }
    set.cycles.push_back(std::move(cycle));
  }
  return set;
}

std::string defaultWalkersDir() {
  if (const char* env = std::getenv("ADUGS_WALKERS_DIR")) return env;
#ifdef ADUGS_WALKERS_DIR
  return ADUGS_WALKERS_DIR;
#else
  return "";
#endif
}

}  // namespace adugs::data

#include "data/sim/sim_texture.h"

#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "data/sim/sim_random.h"

namespace adugs::data {

SimTexture::SimTexture(const cv::Mat& level0_u8) : size_(level0_u8.cols) {
  if (level0_u8.type() != CV_8UC1 || level0_u8.rows != level0_u8.cols || size_ < 1 ||
      (size_ & (size_ - 1)) != 0)
    throw std::invalid_argument("SimTexture: need a square power-of-two CV_8UC1 image");
  cv::Mat level;
  level0_u8.convertTo(level, CV_32F);
  mips_.push_back(level0_u8.clone());
  // 2x2 box filtering keeps the pyramid tileable (no border handling needed).
  while (level.cols > 1) {
    cv::Mat next(level.rows / 2, level.cols / 2, CV_32F);
    for (int y = 0; y < next.rows; ++y) {
      const float* a = level.ptr<float>(2 * y);
      const float* b = level.ptr<float>(2 * y + 1);
      float* o = next.ptr<float>(y);
      for (int x = 0; x < next.cols; ++x)
        o[x] = 0.25f * (a[2 * x] + a[2 * x + 1] + b[2 * x] + b[2 * x + 1]);
    }
    cv::Mat u8;
    next.convertTo(u8, CV_8U);
    mips_.push_back(u8);
    level = next;
  }
  for (size_t i = 0; i < mips_.size(); ++i)
    levels_.push_back({mips_[i].ptr<uint8_t>(), mips_[i].cols, mips_[i].cols - 1,
                       1.0f / static_cast<float>(1 << i)});
}

namespace {

// Tileable value noise: a random grid of `cells` x `cells` upsampled with wrap-around cubic
// interpolation, summed over octaves with halving amplitude. Output CV_32F roughly in [-1, 1].
cv::Mat tileableNoise(int size, int base_cells, int octaves, SimRng& rng) {
  cv::Mat acc = cv::Mat::zeros(size, size, CV_32F);
  float amp = 1.0f, total = 0.0f;
  for (int o = 0, cells = base_cells; o < octaves && cells <= size; ++o, cells *= 2) {
    cv::Mat grid(cells, cells, CV_32F);
    for (int y = 0; y < cells; ++y)
      for (int x = 0; x < cells; ++x) grid.at<float>(y, x) = static_cast<float>(rng.uniform(-1, 1));
    cv::Mat padded, up;
    cv::copyMakeBorder(grid, padded, 2, 2, 2, 2, cv::BORDER_WRAP);
    const double f = static_cast<double>(size) / cells;
    cv::resize(padded, up, cv::Size(), f, f, cv::INTER_CUBIC);
    const int off = static_cast<int>(std::lround(2 * f));
    acc += amp * up(cv::Rect(off, off, size, size));
    total += amp;
    amp *= 0.55f;
  }
  return acc / total;
}

// Draws with wrap-around: the shape is drawn at the 9 periodic copies that can touch the tile.
template <typename Draw>
void drawWrapped(int size, Draw draw) {
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) draw(cv::Point(dx * size, dy * size));
}

cv::Mat toU8(const cv::Mat& f) {
  cv::Mat out;
  f.convertTo(out, CV_8U);  // saturating, rounded
  return out;
}

cv::Mat noiseTexture(int size, SimRng& rng) {
  const double mean = rng.uniform(90, 170), contrast = rng.uniform(35, 60);
  return toU8(mean + contrast * tileableNoise(size, 4, 6, rng));
}

cv::Mat bricksTexture(int size, SimRng& rng) {
  const int rows = 16, cols = 8;  // bricks per tile: periodic by construction
  const int bh = size / rows, bw = size / cols, mortar = std::max(1, size / 128);
  cv::Mat img(size, size, CV_32F, cv::Scalar(200));
  const double base = rng.uniform(90, 140);
  for (int r = 0; r < rows; ++r) {
    const int shift = (r % 2) * bw / 2;
    for (int c = 0; c <= cols; ++c) {
      const float shade = static_cast<float>(base + rng.uniform(-35, 35));
      cv::Rect rc(c * bw - shift + mortar, r * bh + mortar, bw - 2 * mortar, bh - 2 * mortar);
      drawWrapped(size, [&](cv::Point o) {
        cv::rectangle(img, rc + o, cv::Scalar(shade), cv::FILLED, cv::LINE_AA);
      });
    }
  }
  img += 25.0 * tileableNoise(size, 16, 4, rng);
  return toU8(img);
}

cv::Mat tilesTexture(int size, SimRng& rng) {
  const int n = 8, t = size / n;
  cv::Mat img(size, size, CV_32F, cv::Scalar(60));
  const double a = rng.uniform(110, 170), b = rng.uniform(60, 110);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double shade = ((x + y) % 2 ? a : b) + rng.uniform(-15, 15);
      cv::rectangle(img, cv::Rect(x * t + 1, y * t + 1, t - 2, t - 2), cv::Scalar(shade), cv::FILLED);
    }
  for (int i = 0; i < 12; ++i) {  // stains
    const cv::Point c(rng.uniformInt(0, size - 1), rng.uniformInt(0, size - 1));
    const int r = rng.uniformInt(size / 40, size / 10);
    const double shade = rng.uniform(30, 220);
    drawWrapped(size, [&](cv::Point o) {
      cv::circle(img, c + o, r, cv::Scalar(shade), cv::FILLED, cv::LINE_AA);
    });
  }
  img += 18.0 * tileableNoise(size, 8, 5, rng);
  return toU8(img);
}

cv::Mat postersTexture(int size, SimRng& rng) {
  cv::Mat img = rng.uniform(100, 150) + 30.0 * tileableNoise(size, 4, 5, rng);
  const int count = 40 + rng.uniformInt(0, 30);
  for (int i = 0; i < count; ++i) {
    const cv::Point c(rng.uniformInt(0, size - 1), rng.uniformInt(0, size - 1));
    const double shade = rng.uniform(0, 1) < 0.5 ? rng.uniform(10, 70) : rng.uniform(180, 250);
    const int kind = rng.uniformInt(0, 2);
    const int r = rng.uniformInt(size / 64, size / 12);
    drawWrapped(size, [&](cv::Point o) {
      if (kind == 0) {
        cv::circle(img, c + o, r, cv::Scalar(shade), cv::FILLED, cv::LINE_AA);
      } else if (kind == 1) {
        cv::rectangle(img, cv::Rect(c + o, cv::Size(r * 2, r + 3)), cv::Scalar(shade), cv::FILLED,
                      cv::LINE_AA);
      } else {
        cv::line(img, c + o, c + o + cv::Point(r * 3, r), cv::Scalar(shade), 2 + r / 6, cv::LINE_AA);
      }
    });
  }
  return toU8(img);
}

cv::Mat facadeTexture(int size, SimRng& rng) {
  cv::Mat img = rng.uniform(110, 180) + 25.0 * tileableNoise(size, 8, 5, rng);
  const int n = 4, cell = size / n;  // 4 x 4 windows per tile
  const int w = static_cast<int>(cell * rng.uniform(0.4, 0.6));
  const int h = static_cast<int>(cell * rng.uniform(0.5, 0.7));
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const cv::Rect win(x * cell + (cell - w) / 2, y * cell + (cell - h) / 3, w, h);
      cv::rectangle(img, win + cv::Point(-3, -3) + cv::Size(6, 6), cv::Scalar(230), cv::FILLED);
      const double glass = rng.uniform(0, 1) < 0.2 ? rng.uniform(170, 220) : rng.uniform(20, 60);
      cv::rectangle(img, win, cv::Scalar(glass), cv::FILLED);
      cv::line(img, cv::Point(win.x + w / 2, win.y), cv::Point(win.x + w / 2, win.y + h),
               cv::Scalar(200), 2);
    }
  return toU8(img);
}

cv::Mat roadTexture(int size, SimRng& rng) {
  cv::Mat img = 75.0 + 20.0 * tileableNoise(size, 32, 4, rng);
  for (int i = 0; i < 400; ++i) {  // gravel speckle
    const cv::Point c(rng.uniformInt(0, size - 1), rng.uniformInt(0, size - 1));
    cv::circle(img, c, 1, cv::Scalar(rng.uniform(30, 160)), cv::FILLED, cv::LINE_AA);
  }
  // Dashed centre line along s (the tile's x axis), at the tile centre row.
  for (int x = 0; x < size; x += size / 4)
    cv::rectangle(img, cv::Rect(x, size / 2 - size / 64, size / 8, size / 32), cv::Scalar(220),
                  cv::FILLED, cv::LINE_AA);
  return toU8(img);
}

cv::Mat personTexture(int size, SimRng& rng) {
  // Texture v runs up the body: bottom half trousers, top half shirt, a head band at the top.
  cv::Mat img(size, size, CV_32F);
  const double legs = rng.uniform(20, 120), shirt = rng.uniform(40, 230), skin = rng.uniform(120, 200);
  img.rowRange(0, size / 8).setTo(skin);
  img.rowRange(size / 8, size / 2).setTo(shirt);
  img.rowRange(size / 2, size).setTo(legs);
  if (rng.uniform(0, 1) < 0.5)  // stripes
    for (int y = size / 8; y < size / 2; y += size / 16)
      cv::rectangle(img, cv::Rect(0, y, size, size / 40 + 1), cv::Scalar(255 - shirt), cv::FILLED);
  img += 22.0 * tileableNoise(size, 8, 5, rng);
  return toU8(img);
}

cv::Mat vehicleTexture(int size, SimRng& rng) {
  const double body = rng.uniform(30, 230);
  cv::Mat img = body + 12.0 * tileableNoise(size, 4, 5, rng);
  // Window band in the upper part, wheel-arch dark band at the bottom, door lines.
  img.rowRange(size / 8, size * 3 / 8).setTo(rng.uniform(15, 50));
  img.rowRange(size * 7 / 8, size).setTo(20);
  for (int x = size / 8; x < size; x += size / 4)
    cv::line(img, cv::Point(x, size / 8), cv::Point(x, size * 7 / 8), cv::Scalar(body * 0.5), 2,
             cv::LINE_AA);
  cv::Mat band = img.rowRange(size / 8, size * 3 / 8);  // a view: adds in place
  band += 25.0 * tileableNoise(size, 16, 3, rng).rowRange(0, size / 4);
  return toU8(img);
}

cv::Mat checkerTexture(int size) {
  cv::Mat img(size, size, CV_8U, cv::Scalar(230));
  img(cv::Rect(0, 0, size / 2, size / 2)).setTo(25);
  img(cv::Rect(size / 2, size / 2, size / 2, size / 2)).setTo(25);
  return img;
}

}  // namespace

cv::Mat makeTexture(SimTextureKind kind, int size, SimRng& rng) {
  if (size < 8 || (size & (size - 1)) != 0)
    throw std::invalid_argument("makeTexture: size must be a power of two >= 8");
  switch (kind) {
    case SimTextureKind::kNoise: return noiseTexture(size, rng);
    case SimTextureKind::kBricks: return bricksTexture(size, rng);
    case SimTextureKind::kTiles: return tilesTexture(size, rng);
    case SimTextureKind::kPosters: return postersTexture(size, rng);
    case SimTextureKind::kFacade: return facadeTexture(size, rng);
    case SimTextureKind::kRoad: return roadTexture(size, rng);
    case SimTextureKind::kPerson: return personTexture(size, rng);
    case SimTextureKind::kVehicle: return vehicleTexture(size, rng);
    case SimTextureKind::kChecker: return checkerTexture(size);
  }
  throw std::invalid_argument("makeTexture: unknown kind");
}

}  // namespace adugs::data

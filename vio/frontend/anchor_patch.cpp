#include "vio/frontend/anchor_patch.h"

#include <Eigen/Dense>
#include <cmath>

namespace adugs::vio {
namespace {

// Bilinear grey value at (x, y); false outside the image (a full 2x2 neighbourhood is needed).
bool sample(const cv::Mat& image, double x, double y, float* value) {
  if (!(x >= 0 && y >= 0 && x < image.cols - 1 && y < image.rows - 1)) return false;
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const float a = static_cast<float>(x - x0), b = static_cast<float>(y - y0);
  const uchar* r0 = image.ptr<uchar>(y0) + x0;
  const uchar* r1 = image.ptr<uchar>(y0 + 1) + x0;
  *value = (1 - b) * ((1 - a) * r0[0] + a * r0[1]) + b * ((1 - a) * r1[0] + a * r1[1]);
  return true;
}

// d(warped offset)/d(parameters) at the identity, parameters (a11, a12, a21, a22, tx, ty) of
// x' = (I + D) x + d, contracted with the template gradient.
Eigen::Matrix<double, 6, 1> steepestDescent(double gx, double gy, double x, double y) {
  Eigen::Matrix<double, 6, 1> J;
  J << gx * x, gx * y, gy * x, gy * y, gx, gy;
  return J;
}

// Subtracts the mean (sum / size) from every value; returns their standard deviation.
double removeMean(std::vector<float>* values, double sum) {
  const double n = static_cast<double>(values->size());
  const float mean = static_cast<float>(sum / n);
  double var = 0;
  for (float& v : *values) {
    v -= mean;
    var += v * v;
  }
  return std::sqrt(var / n);
}

}  // namespace

AnchorPatch::AnchorPatch(const cv::Mat& image, const Eigen::Vector2d& center, int half)
    : half_(half) {
  // Samples on a grid one pixel wider than the patch, for central-difference gradients.
  const int w = 2 * half + 3;
  std::vector<float> grid(static_cast<size_t>(w * w));
  for (int r = 0; r < w; ++r)
    for (int c = 0; c < w; ++c)
      if (!sample(image, center.x() + c - half - 1, center.y() + r - half - 1, &grid[r * w + c]))
        return;
  const int n = (2 * half + 1) * (2 * half + 1);
  values_.resize(n), steepest_.resize(n);
  double sum = 0;
  for (int r = 0, i = 0; r <= 2 * half; ++r)
    for (int c = 0; c <= 2 * half; ++c, ++i) {
      const int g = (r + 1) * w + (c + 1);
      values_[i] = grid[g];
      const double gx = 0.5 * (grid[g + 1] - grid[g - 1]), gy = 0.5 * (grid[g + w] - grid[g - w]);
      steepest_[i] = steepestDescent(gx, gy, c - half, r - half).cast<float>();
      sum += grid[g];
    }
  sigma_ = removeMean(&values_, sum);
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  for (const auto& J : steepest_) H.selfadjointView<Eigen::Lower>().rankUpdate(J.cast<double>());
  H = H.selfadjointView<Eigen::Lower>();
  // A corner constrains all six parameters; an edge or a flat patch leaves some free.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(H, Eigen::EigenvaluesOnly);
  if (sigma_ < 2.0 || !(eig.eigenvalues()(0) > 1e-6 * eig.eigenvalues()(5))) return;
  H_inv_ = H.inverse();
  valid_ = true;
}

AnchorPatch::Result AnchorPatch::align(const cv::Mat& image, const Eigen::Matrix2d& A0,
                                       const Eigen::Vector2d& position, int max_iterations) const {
  Result res;
  res.A = A0;
  res.position = position;
  if (!valid_) return res;
  const int n = static_cast<int>(values_.size());
  std::vector<float> warped(n);
  for (int it = 0; it < max_iterations; ++it) {
    res.iterations = it + 1;
    // The warp is affine: the patch lies inside the image iff its four corners do. Then sample
    // without per-pixel checks (this loop is most of the anchor cost).
    for (const double cx : {-half_, half_})
      for (const double cy : {-half_, half_}) {
        const Eigen::Vector2d corner = res.position + res.A * Eigen::Vector2d(cx, cy);
        // A 0.01 px margin: the loop below steps in float, the corners are checked in double.
        if (!(corner.x() >= 0.01 && corner.y() >= 0.01 && corner.x() < image.cols - 1.01 &&
              corner.y() < image.rows - 1.01))
          return res;
      }
    const float ax = static_cast<float>(res.A(0, 0)), ay = static_cast<float>(res.A(1, 0));
    double sum = 0;
    for (int r = 0, i = 0; r <= 2 * half_; ++r) {
      const Eigen::Vector2d start = res.position + res.A * Eigen::Vector2d(-half_, r - half_);
      float x = static_cast<float>(start.x()), y = static_cast<float>(start.y());
      for (int c = 0; c <= 2 * half_; ++c, ++i, x += ax, y += ay) {
        const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
        const float a = x - x0, b = y - y0;
        const uchar* r0 = image.ptr<uchar>(y0) + x0;
        const uchar* r1 = r0 + image.step[0];
        warped[i] = (1 - b) * ((1 - a) * r0[0] + a * r0[1]) + b * ((1 - a) * r1[0] + a * r1[1]);
        sum += warped[i];
      }
    }
    const double sigma = removeMean(&warped, sum);
    if (sigma < 1e-3) return res;
    const double gain = sigma_ / sigma;
    Eigen::Matrix<float, 6, 1> b = Eigen::Matrix<float, 6, 1>::Zero();
    double cross = 0;
    const float g = static_cast<float>(gain);
    for (int i = 0; i < n; ++i) {
      b += steepest_[i] * (g * warped[i] - values_[i]);
      cross += static_cast<double>(warped[i]) * values_[i];
    }
    res.zncc = cross / (n * sigma * sigma_);
    // Inverse composition: W <- W o W(dp)^-1, W(dp)(x) = (I + D) x + d.
    const Eigen::Matrix<double, 6, 1> dp = H_inv_ * b.cast<double>();
    Eigen::Matrix2d M;
    M << 1 + dp(0), dp(1), dp(2), 1 + dp(3);
    const Eigen::Vector2d d(dp(4), dp(5));
    if (std::abs(M.determinant()) < 1e-3) return res;
    res.A = res.A * M.inverse();
    const Eigen::Vector2d step = res.A * d;
    res.position -= step;
    if (step.norm() < 0.03 && dp.head<4>().norm() * half_ < 0.03) {
      res.converged = res.A.allFinite() && res.position.allFinite();
      return res;
    }
  }
  return res;
}

}  // namespace adugs::vio

#include "vio/frontend/anms.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace adugs::vio {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

float dist2(const cv::Point2f& a, const cv::Point2f& b) {
  const float dx = a.x - b.x, dy = a.y - b.y;
  return dx * dx + dy * dy;
}

// Indices sorted by decreasing response (stable, so equal responses keep input order).
std::vector<int> byResponse(const std::vector<cv::KeyPoint>& kps) {
  std::vector<int> order(kps.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return kps[a].response > kps[b].response; });
  return order;
}

// Uniform grid over a bounding box holding point indices as singly linked lists (no per-cell
// allocation): head_[cell] -> next_[point] -> ... -> -1.
class PointGrid {
 public:
  PointGrid(float x0, float y0, float x1, float y1, float cell, size_t n_points)
      : x0_(x0), y0_(y0), cell_(cell) {
    cols_ = std::max(1, static_cast<int>((x1 - x0) / cell) + 1);
    rows_ = std::max(1, static_cast<int>((y1 - y0) / cell) + 1);
    head_.assign(static_cast<size_t>(cols_) * rows_, -1);
    next_.assign(n_points, -1);
  }
  int cols() const { return cols_; }
  int rows() const { return rows_; }
  float cell() const { return cell_; }
  int col(float x) const { return std::clamp(static_cast<int>((x - x0_) / cell_), 0, cols_ - 1); }
  int row(float y) const { return std::clamp(static_cast<int>((y - y0_) / cell_), 0, rows_ - 1); }
  void insert(int index, const cv::Point2f& p) {
    int& h = head_[static_cast<size_t>(row(p.y)) * cols_ + col(p.x)];
    next_[index] = h;
    h = index;
  }
  // Calls f(index) for every point in cell (c, r); the cell must be inside the grid.
  template <typename F>
  void forCell(int c, int r, F&& f) const {
    for (int i = head_[static_cast<size_t>(r) * cols_ + c]; i >= 0; i = next_[i]) f(i);
  }
  // Every in-grid cell at Chebyshev distance exactly k from (c, r).
  template <typename F>
  void forRing(int c, int r, int k, F&& f) const {
    if (k == 0) {
      forCell(c, r, f);
      return;
    }
    const int c0 = std::max(0, c - k), c1 = std::min(cols_ - 1, c + k);
    for (int rr : {r - k, r + k}) {
      if (rr < 0 || rr >= rows_) continue;
      for (int cc = c0; cc <= c1; ++cc) forCell(cc, rr, f);
    }
    const int r0 = std::max(0, r - k + 1), r1 = std::min(rows_ - 1, r + k - 1);
    for (int cc : {c - k, c + k}) {
      if (cc < 0 || cc >= cols_) continue;
      for (int rr = r0; rr <= r1; ++rr) forCell(cc, rr, f);
    }
  }

 private:
  float x0_, y0_, cell_;
  int cols_ = 1, rows_ = 1;
  std::vector<int> head_, next_;
};

}  // namespace

std::vector<float> suppressionRadiiBruteForce(const std::vector<cv::KeyPoint>& kps) {
  std::vector<float> radii(kps.size(), kInf);
  for (size_t i = 0; i < kps.size(); ++i) {
    float best = kInf;
    for (size_t j = 0; j < kps.size(); ++j)
      if (kps[j].response > kps[i].response) best = std::min(best, dist2(kps[i].pt, kps[j].pt));
    radii[i] = std::sqrt(best);
  }
  return radii;
}

std::vector<float> suppressionRadii(const std::vector<cv::KeyPoint>& kps) {
  const size_t n = kps.size();
  std::vector<float> radii(n, kInf);
  if (n < 2) return radii;
  float x0 = kps[0].pt.x, x1 = x0, y0 = kps[0].pt.y, y1 = y0;
  for (const auto& k : kps) {
    x0 = std::min(x0, k.pt.x), x1 = std::max(x1, k.pt.x);
    y0 = std::min(y0, k.pt.y), y1 = std::max(y1, k.pt.y);
  }
  // About four points per cell once all are inserted.
  const float area = std::max(1.0f, (x1 - x0) * (y1 - y0));
  const float cell = std::max(1.0f, 2.0f * std::sqrt(area / static_cast<float>(n)));
  PointGrid grid(x0, y0, x1, y1, cell, n);
  const int max_ring = std::max(grid.cols(), grid.rows());

  const std::vector<int> order = byResponse(kps);
  // Walk groups of equal response: a group is searched against the strictly stronger points
  // already in the grid, then inserted, so equal responses never suppress each other.
  for (size_t g = 0; g < n;) {
    size_t g_end = g + 1;
    while (g_end < n && kps[order[g_end]].response == kps[order[g]].response) ++g_end;
    if (g > 0) {
      for (size_t t = g; t < g_end; ++t) {
        const cv::Point2f p = kps[order[t]].pt;
        const int c = grid.col(p.x), r = grid.row(p.y);
        float best = kInf;
        for (int k = 0; k <= max_ring; ++k) {
          grid.forRing(c, r, k, [&](int j) { best = std::min(best, dist2(p, kps[j].pt)); });
          // Cells of ring k+1 and beyond are at least k cells away along x or y.
          const float reach = static_cast<float>(k) * grid.cell();
          if (best <= reach * reach) break;
        }
        radii[order[t]] = std::sqrt(best);
      }
    }
    for (size_t t = g; t < g_end; ++t) grid.insert(order[t], kps[order[t]].pt);
    g = g_end;
  }
  return radii;
}

std::vector<int> selectAnms(const std::vector<cv::KeyPoint>& kps, int n_keep, double min_distance,
                            const std::vector<cv::Point2f>& existing,
                            const std::vector<float>* radii_in) {
  std::vector<int> kept;
  if (n_keep <= 0 || kps.empty()) return kept;
  std::vector<float> computed;
  if (!radii_in) computed = suppressionRadii(kps);
  const std::vector<float>& radii = radii_in ? *radii_in : computed;
  if (radii.size() != kps.size())
    throw std::invalid_argument("selectAnms: radii and keypoints differ in size");

  std::vector<int> order(kps.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    if (radii[a] != radii[b]) return radii[a] > radii[b];
    if (kps[a].response != kps[b].response) return kps[a].response > kps[b].response;
    return a < b;
  });

  const size_t max_kept = std::min<size_t>(static_cast<size_t>(n_keep), kps.size());
  kept.reserve(max_kept);
  if (min_distance <= 0) {
    for (int i : order) {
      if (static_cast<int>(kept.size()) >= n_keep) break;
      kept.push_back(i);
    }
    return kept;
  }

  // Occupancy grid with cell = D_min: a conflict can only sit in the 3x3 neighbouring cells.
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool first = true;
  auto grow = [&](const cv::Point2f& p) {
    if (first) x0 = x1 = p.x, y0 = y1 = p.y, first = false;
    x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  };
  for (const auto& k : kps) grow(k.pt);
  for (const auto& p : existing) grow(p);
  // A cell larger than D_min is still correct (conflicts stay within the 3x3 block); the floor
  // only bounds the grid size for tiny D_min.
  const float cell =
      std::max(static_cast<float>(min_distance), std::max(x1 - x0, y1 - y0) / 1024.0f);
  std::vector<cv::Point2f> points;  // existing then kept, indexed by the grid
  points.reserve(existing.size() + max_kept);
  PointGrid grid(x0, y0, x1, y1, cell, existing.size() + max_kept);
  for (const auto& p : existing) {
    grid.insert(static_cast<int>(points.size()), p);
    points.push_back(p);
  }
  const float d2_min = static_cast<float>(min_distance * min_distance);
  for (int i : order) {
    if (static_cast<int>(kept.size()) >= n_keep) break;
    const cv::Point2f p = kps[i].pt;
    const int c = grid.col(p.x), r = grid.row(p.y);
    bool free = true;
    for (int rr = std::max(0, r - 1); free && rr <= std::min(grid.rows() - 1, r + 1); ++rr)
      for (int cc = std::max(0, c - 1); free && cc <= std::min(grid.cols() - 1, c + 1); ++cc)
        grid.forCell(cc, rr, [&](int j) { free = free && dist2(p, points[j]) >= d2_min; });
    if (!free) continue;
    grid.insert(static_cast<int>(points.size()), p);
    points.push_back(p);
    kept.push_back(i);
  }
  return kept;
}

}  // namespace adugs::vio

#include "calib/target/chessboard.h"

#include <cmath>
#include <cstdio>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace adugs::calib {

bool parseChessboardSpec(const std::string& spec, Chessboard& out) {
  const std::string prefix = "chessboard:";
  if (spec.rfind(prefix, 0) != 0) return false;
  int cols = 0, rows = 0, used = 0;
  double square = 0;
  const std::string rest = spec.substr(prefix.size());
  if (std::sscanf(rest.c_str(), "%dx%d:%lf%n", &cols, &rows, &square, &used) != 3 ||
      used != static_cast<int>(rest.size()) || cols < 2 || rows < 2 || cols > 1000 ||
      rows > 1000 || !(square > 0) || !std::isfinite(square))
    return false;
  out = {cols, rows, square};
  return true;
}

TargetObservation detectChessboard(const Chessboard& board, const cv::Mat& gray, int64_t t_ns) {
  TargetObservation obs;
  obs.t_ns = t_ns;
  std::vector<cv::Point2f> corners;
  const cv::Size size(board.cols, board.rows);
  if (!cv::findChessboardCorners(gray, size, corners,
                                 cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE))
    return obs;
  // Window: a third of the smallest square side in pixels, 2..11.
  double side = 1e9;
  for (int r = 0; r < board.rows; ++r)
    for (int c = 0; c + 1 < board.cols; ++c)
      side = std::min<double>(side, cv::norm(corners[r * board.cols + c + 1] - corners[r * board.cols + c]));
  const int half = std::clamp(static_cast<int>(side / 3), 2, 11);
  cv::cornerSubPix(gray, corners, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 40, 0.005));
  for (int k = 0; k < static_cast<int>(corners.size()); ++k)
    obs.corners.push_back({k, 0, Eigen::Vector2d(corners[k].x, corners[k].y),
                           Eigen::Vector3d((k % board.cols) * board.square_m,
                                           (k / board.cols) * board.square_m, 0)});
  return obs;
}

}  // namespace adugs::calib

#pragma once
// Chessboard targets (OpenCV's findChessboardCorners), for intrinsics only. Given on the command
// line as "chessboard:COLSxROWS:SQUARE" (inner corners, square edge in metres), e.g.
// "chessboard:9x6:0.025". Corner k (row-major as OpenCV returns them) gets tag_id k, corner 0,
// and the target point (k % cols, k / cols) * square. A chessboard's labelling may come out
// rotated by 180 degrees between views; for intrinsics that is harmless (the flipped grid is
// the same point set under another pose).
#include <string>

#include <opencv2/core.hpp>

#include "calib/target/target_observation.h"

namespace adugs::calib {

struct Chessboard {
  int cols = 9;  // inner corners per row
  int rows = 6;
  double square_m = 0.025;
};

// False unless spec is "chessboard:CxR:S" with C, R >= 2 and S > 0.
bool parseChessboardSpec(const std::string& spec, Chessboard& out);

// Empty observation when the full board is not found.
TargetObservation detectChessboard(const Chessboard& board, const cv::Mat& gray, int64_t t_ns);

}  // namespace adugs::calib

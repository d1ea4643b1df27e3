#include "calib/target/aprilgrid.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace adugs::calib {

Eigen::Vector3d AprilGrid::corner(int tag_id, int corner_index) const {
  if (tag_id < 0 || tag_id >= numTags())
    throw std::out_of_range("AprilGrid tag id " + std::to_string(tag_id) + " outside 0.." +
                            std::to_string(numTags() - 1));
  if (corner_index < 0 || corner_index > 3)
    throw std::out_of_range("AprilGrid corner index " + std::to_string(corner_index));
  const int row = tag_id / tag_cols;
  const int col = tag_id % tag_cols;
  // Offsets of corners 0..3 (counter-clockwise from bottom-left) within a tag, in tag sizes.
  static constexpr int kCornerDx[4] = {0, 1, 1, 0};
  static constexpr int kCornerDy[4] = {0, 0, 1, 1};
  return {col * pitch() + kCornerDx[corner_index] * tag_size_m,
          row * pitch() + kCornerDy[corner_index] * tag_size_m, 0.0};
}

void AprilGrid::validate() const {
  if (tag_rows < 1) throw std::invalid_argument("tagRows must be >= 1");
  if (tag_cols < 1) throw std::invalid_argument("tagCols must be >= 1");
  if (!(tag_size_m > 0.0) || !std::isfinite(tag_size_m))
    throw std::invalid_argument("tagSize must be a positive number of metres");
  if (!(tag_spacing >= 0.0) || !std::isfinite(tag_spacing))
    throw std::invalid_argument("tagSpacing must be a non-negative ratio");
  if (border_bits != 1 && border_bits != 2)
    throw std::invalid_argument("borderBits must be 1 (standard tag36h11) or 2 (Kalibr)");
  if (numTags() > kTag36h11Count)
    throw std::invalid_argument("tagRows * tagCols = " + std::to_string(numTags()) +
                                " exceeds the " + std::to_string(kTag36h11Count) +
                                " codes of tag36h11");
}

}  // namespace adugs::calib

#pragma once
// Kalibr's AprilGrid target: tagRows x tagCols tag36h11 tags of side tagSize (the black square),
// separated by tagSpacing * tagSize. Tag ids run row-major from the bottom-left tag; the target
// frame has its origin at the bottom-left corner of tag 0, x along a row, y up the columns, z out
// of the board. Corners of a tag are numbered counter-clockwise from its bottom-left corner.
#include <Eigen/Core>

namespace adugs::calib {

// Number of distinct codes in the tag36h11 family.
constexpr int kTag36h11Count = 587;

struct AprilGrid {
  int tag_rows = 6;
  int tag_cols = 6;
  double tag_size_m = 0.088;  // edge of the black square
  double tag_spacing = 0.3;   // gap between tags as a fraction of tag_size_m
  // Width of the black border in code bits. Kalibr prints 2 (its ethz_apriltag2 detector's
  // blackBorder); standard tag36h11 (ViSP, apriltag3) has 1.
  int border_bits = 2;

  int numTags() const { return tag_rows * tag_cols; }
  // Distance between the same corner of two neighbouring tags.
  double pitch() const { return tag_size_m * (1.0 + tag_spacing); }
  // Row and column of a tag (row 0 at the bottom).
  int tagRow(int tag_id) const { return tag_id / tag_cols; }
  int tagCol(int tag_id) const { return tag_id % tag_cols; }
  // 3-D point (target frame, metres) of corner 0..3 of a tag; throws std::out_of_range.
  Eigen::Vector3d corner(int tag_id, int corner_index) const;
  // Throws std::invalid_argument naming the bad field.
  void validate() const;
};

}  // namespace adugs::calib

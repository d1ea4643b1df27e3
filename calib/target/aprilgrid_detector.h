#pragma once
// AprilGrid detection: tag36h11 quads -> ids and corners -> sub-pixel corners -> consistency
// checks -> corners with their 3-D target points.
//
// Quads: the system apriltag library, with the tag36h11 family as it is for standard tags (1-bit
// border; the same corners as ViSP's vpDetectorAprilTag, checked in the tests on ViSP's AprilTag
// photo) and with its bit grid widened by one cell on each side for a Kalibr board (2-bit border,
// the default; ViSP cannot decode those). Corners come in Kalibr's corner numbering (checked in
// the tests on a real EuRoC image and on rendered boards). Kalibr's corner squares touch the tag corners, which can
// merge the white gaps into the black blobs and hide quads; a second pass on a slightly dilated
// image (white grown by one pixel) recovers those tags. Corners are then refined with
// cv::cornerSubPix on the original image.
//
// Rejected: ids outside the grid, ids seen twice, tags whose corners moved too far during the
// sub-pixel refinement, tags whose corners do not fit a homography with their neighbours on the
// grid (wrong id or corner order), and tags with no neighbours to check against.
#include <array>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "calib/target/aprilgrid.h"
#include "calib/target/target_observation.h"

namespace adugs::calib {

struct TagDetection {
  int id = 0;
  std::array<Eigen::Vector2d, 4> corners;  // Kalibr corner order
};

struct DetectorOptions {
  float quad_decimate = 1.0f;      // >1 speeds up detection of large tags
  int threads = 1;
  bool subpix = true;
  double max_subpix_shift_px = 2.0;  // per corner (at least 6% of the tag side is allowed)
  double consistency_tol = 0.15;     // local-homography error / tag side
  bool dilated_pass = true;          // more passes on dilated images when tags are missing
};

struct DetectionStats {
  int raw_tags = 0;
  int rejected_id = 0;
  int rejected_duplicate = 0;
  int rejected_subpix = 0;
  int rejected_inconsistent = 0;
  int kept_tags = 0;
};

class AprilGridDetector {
 public:
  AprilGridDetector(const AprilGrid& grid, const DetectorOptions& options = {});
  ~AprilGridDetector();
  AprilGridDetector(const AprilGridDetector&) = delete;
  AprilGridDetector& operator=(const AprilGridDetector&) = delete;

  // All tag36h11 tags in an 8-bit gray image with the configured border, no grid logic.
  std::vector<TagDetection> detectTags(const cv::Mat& gray) const;
  // The grid corners seen in the image (empty when nothing usable was found).
  TargetObservation detect(const cv::Mat& gray, int64_t t_ns = 0,
                           DetectionStats* stats = nullptr) const;

  const AprilGrid& grid() const { return grid_; }

 private:
  struct Impl;
  AprilGrid grid_;
  DetectorOptions options_;
  std::unique_ptr<Impl> impl_;
};

// The consistency check on its own: removes (worst first) tags whose corners are off by more
// than tol * tag side from a homography fitted to the tags within two grid steps, and tags with
// fewer than two such neighbours. Returns the number removed.
int rejectInconsistentTags(const AprilGrid& grid, std::vector<TagDetection>& tags, double tol);

}  // namespace adugs::calib

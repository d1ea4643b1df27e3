#include "calib/target/aprilgrid_detector.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

extern "C" {
#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>
}

namespace adugs::calib {
namespace {

double tagSide(const TagDetection& t) {
  double sum = 0;
  for (int k = 0; k < 4; ++k) sum += (t.corners[k] - t.corners[(k + 1) % 4]).norm();
  return sum / 4;
}

// Ids that appear more than once (a second board, or a misread) are dropped entirely.
int dropDuplicates(std::vector<TagDetection>& tags) {
  std::map<int, int> count;
  for (const auto& t : tags) ++count[t.id];
  const size_t before = tags.size();
  tags.erase(std::remove_if(tags.begin(), tags.end(),
                            [&](const TagDetection& t) { return count[t.id] > 1; }),
             tags.end());
  return static_cast<int>(before - tags.size());
}

}  // namespace

// The system AprilTag library for both borders: the standard 1-bit tags and Kalibr's 2-bit ones,
// whose family is the standard one with the black border one cell wider. Called directly rather
// than through ViSP's vpDetectorAprilTag, whose module loads OpenCV's image codecs and video I/O
// (~50 MB) into every adugs process; the tests check both give the same corners.
struct AprilGridDetector::Impl {
  apriltag_family_t* family = nullptr;
  apriltag_detector_t* detector = nullptr;

  Impl(int border_bits, const DetectorOptions& o) {
    family = tag36h11_create();
    // The code bits keep their pattern; the black border around them is wider.
    const int extra = border_bits - 1;
    family->width_at_border += 2 * extra;
    family->total_width += 2 * extra;
    for (uint32_t i = 0; i < family->nbits; ++i) {
      family->bit_x[i] += extra;
      family->bit_y[i] += extra;
    }
    detector = apriltag_detector_create();
    apriltag_detector_add_family(detector, family);
    detector->quad_decimate = o.quad_decimate;
    detector->nthreads = std::max(1, o.threads);
    detector->quad_sigma = 0.0f;
    detector->refine_edges = true;
  }
  ~Impl() {
    if (detector) apriltag_detector_destroy(detector);
    if (family) tag36h11_destroy(family);
  }

  std::vector<TagDetection> run(const cv::Mat& gray) const {
    std::vector<TagDetection> out;
    image_u8_t image{gray.cols, gray.rows, static_cast<int32_t>(gray.step),
                     const_cast<uint8_t*>(gray.ptr<uint8_t>())};
    zarray_t* detections = apriltag_detector_detect(detector, &image);
    for (int i = 0; i < zarray_size(detections); ++i) {
      apriltag_detection_t* d = nullptr;
      zarray_get(detections, i, &d);
      if (d->hamming > 1) continue;  // 36h11 corrects more, but a calibration wants clean codes
      TagDetection t;
      t.id = d->id;
      for (int k = 0; k < 4; ++k) t.corners[k] = {d->p[k][0], d->p[k][1]};
      out.push_back(t);
    }
    apriltag_detections_destroy(detections);
    return out;
  }
};

AprilGridDetector::AprilGridDetector(const AprilGrid& grid, const DetectorOptions& options)
    : grid_(grid), options_(options) {
  grid_.validate();
  impl_ = std::make_unique<Impl>(grid_.border_bits, options_);
}

AprilGridDetector::~AprilGridDetector() = default;

std::vector<TagDetection> AprilGridDetector::detectTags(const cv::Mat& gray) const {
  if (gray.empty() || gray.type() != CV_8UC1)
    throw std::invalid_argument("AprilGridDetector wants a non-empty 8-bit gray image");
  return impl_->run(gray.isContinuous() ? gray : gray.clone());
}

TargetObservation AprilGridDetector::detect(const cv::Mat& gray, int64_t t_ns,
                                            DetectionStats* stats_out) const {
  DetectionStats stats;
  std::vector<TagDetection> tags = detectTags(gray);
  stats.raw_tags = static_cast<int>(tags.size());
  stats.rejected_duplicate += dropDuplicates(tags);

  auto dropOutsideGrid = [&](std::vector<TagDetection>& v) {
    const size_t before = v.size();
    v.erase(std::remove_if(v.begin(), v.end(),
                           [&](const TagDetection& t) { return t.id >= grid_.numTags(); }),
            v.end());
    return static_cast<int>(before - v.size());
  };
  stats.rejected_id += dropOutsideGrid(tags);
  std::set<int> from_dilated;  // their quads are shrunk by the dilation: allow a larger shift

  // Grow white by 1, then 1.5 pixels: separates the corner squares from the tags (see header).
  for (int kernel = 2; options_.dilated_pass && kernel <= 3 &&
                       static_cast<int>(tags.size()) < grid_.numTags();
       ++kernel) {
    cv::Mat dilated;
    cv::dilate(gray, dilated, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(kernel, kernel)));
    std::vector<TagDetection> more = impl_->run(dilated);
    dropDuplicates(more);
    dropOutsideGrid(more);
    for (const auto& t : more) {
      const bool known = std::any_of(tags.begin(), tags.end(),
                                     [&](const TagDetection& o) { return o.id == t.id; });
      if (!known) {
        tags.push_back(t);
        from_dilated.insert(t.id);
      }
    }
  }

  if (options_.subpix && !tags.empty()) {
    std::vector<TagDetection> kept;
    const int cells = 6 + 2 * grid_.border_bits;
    for (TagDetection t : tags) {
      const double side = tagSide(t);
      // The X-junction is clean within the border width and within the corner square.
      double clean = side * grid_.border_bits / cells;
      if (grid_.tag_spacing > 0) clean = std::min(clean, side * grid_.tag_spacing);
      const int half = std::clamp(static_cast<int>(0.8 * clean), 2, 12);
      std::vector<cv::Point2f> pts;
      for (const auto& c : t.corners) pts.emplace_back(float(c.x()), float(c.y()));
      const cv::Rect inside(half + 1, half + 1, gray.cols - 2 * half - 2, gray.rows - 2 * half - 2);
      bool ok = std::all_of(pts.begin(), pts.end(), [&](const cv::Point2f& p) {
        return inside.contains(cv::Point(int(p.x), int(p.y)));
      });
      if (ok) {
        cv::cornerSubPix(gray, pts, cv::Size(half, half), cv::Size(-1, -1),
                         cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 40,
                                          0.005));
        const double max_shift = std::max(options_.max_subpix_shift_px, 0.06 * side) +
                                 (from_dilated.count(t.id) ? 1.5 : 0.0);
        for (int k = 0; k < 4 && ok; ++k) {
          const Eigen::Vector2d refined(pts[k].x, pts[k].y);
          ok = (refined - t.corners[k]).norm() <= max_shift;
          t.corners[k] = refined;
        }
      }
      if (ok)
        kept.push_back(t);
      else
        ++stats.rejected_subpix;
    }
    tags = std::move(kept);
  }

  if (grid_.numTags() >= 3)
    stats.rejected_inconsistent += rejectInconsistentTags(grid_, tags, options_.consistency_tol);

  std::sort(tags.begin(), tags.end(),
            [](const TagDetection& a, const TagDetection& b) { return a.id < b.id; });
  TargetObservation obs;
  obs.t_ns = t_ns;
  for (const auto& t : tags)
    for (int k = 0; k < 4; ++k) obs.corners.push_back({t.id, k, t.corners[k], grid_.corner(t.id, k)});
  stats.kept_tags = static_cast<int>(tags.size());
  if (stats_out) *stats_out = stats;
  return obs;
}

int rejectInconsistentTags(const AprilGrid& grid, std::vector<TagDetection>& tags, double tol) {
  int removed = 0;
  while (!tags.empty()) {
    double worst_ratio = 0;
    size_t worst = tags.size();
    for (size_t i = 0; i < tags.size(); ++i) {
      const TagDetection& t = tags[i];
      std::vector<cv::Point2d> src, dst;
      int neighbours = 0;
      for (size_t j = 0; j < tags.size(); ++j) {
        if (j == i) continue;
        const TagDetection& u = tags[j];
        if (std::abs(grid.tagRow(u.id) - grid.tagRow(t.id)) > 2 ||
            std::abs(grid.tagCol(u.id) - grid.tagCol(t.id)) > 2)
          continue;
        ++neighbours;
        for (int k = 0; k < 4; ++k) {
          const Eigen::Vector3d p = grid.corner(u.id, k);
          src.emplace_back(p.x(), p.y());
          dst.emplace_back(u.corners[k].x(), u.corners[k].y());
        }
      }
      double ratio = 1e9;  // no neighbours: cannot be verified
      if (neighbours >= 2) {
        const cv::Mat H = cv::findHomography(src, dst, 0);
        if (!H.empty()) {
          double err = 0;
          for (int k = 0; k < 4; ++k) {
            const Eigen::Vector3d p = grid.corner(t.id, k);
            const cv::Mat q = H * (cv::Mat_<double>(3, 1) << p.x(), p.y(), 1.0);
            const Eigen::Vector2d uv(q.at<double>(0) / q.at<double>(2),
                                     q.at<double>(1) / q.at<double>(2));
            err = std::max(err, (uv - t.corners[k]).norm());
          }
          ratio = err / (tol * std::max(tagSide(t), 1.0));
        }
      }
      if (ratio > worst_ratio) {
        worst_ratio = ratio;
        worst = i;
      }
    }
    if (worst_ratio <= 1.0 || worst == tags.size()) break;
    tags.erase(tags.begin() + static_cast<long>(worst));
    ++removed;
  }
  return removed;
}

}  // namespace adugs::calib

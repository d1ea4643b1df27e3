#pragma once
// The features of the sliding window as landmarks (VINS-Mono's FeatureManager): for each feature
// id, its observations in the window's frames (window index, undistorted normalised point,
// image velocity) and, once triangulated, its inverse depth along z of the host camera = the
// first frame that observes it.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <set>
#include <vector>

#include "vio/frontend/frame_features.h"

namespace adugs::vio {

struct Observation {
  int frame = 0;  // window index
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();
};

struct Landmark {
  int64_t id = 0;
  std::vector<Observation> observations;  // increasing frame index; front() is the host
  double inverse_depth = 0;               // valid when has_depth
  bool has_depth = false;
  int hostFrame() const { return observations.front().frame; }
};

class LandmarkMap {
 public:
  // Records the features of the frame at window index `frame`, except rejected ones.
  void addFrame(int frame, const FrameFeatures& features);

  // Erases an outlier landmark and ignores its feature id in later frames for as long as the
  // tracker keeps reporting it (the set forgets an id at the first frame without it, so it stays
  // no larger than one frame's features).
  void reject(int64_t id);
  bool isRejected(int64_t id) const { return rejected_.count(id) > 0; }

  // Mean displacement (normalised units) of the features seen in both frames, and how many.
  double meanParallax(int frame_a, int frame_b, int* common = nullptr) const;

  // Removes every observation in `frame` and shifts later window indices down by one. A
  // landmark hosted there moves to its next observing frame; its depth is carried over with the
  // camera poses T_W_C (indexed by window index, BEFORE the removal), or lost if the poses are
  // not given. Landmarks left with no observation are erased.
  void removeFrame(int frame, const std::vector<Eigen::Isometry3d>* T_W_C = nullptr);

  // Triangulates landmarks without depth that have at least two observations (linear least
  // squares over all observations with the given camera poses T_W_C). Accepts points seen in
  // front of every camera, at a host depth in [min_depth, max_depth], whose rays meet at an angle
  // of at least min_angle_rad. Returns how many got a depth.
  int triangulate(const std::vector<Eigen::Isometry3d>& T_W_C, double min_depth = 0.1,
                  double max_depth = 80.0, double min_angle_rad = 0.0175);

  // Sets the depth from a world point (e.g. after initialisation).
  void setWorldPoint(int64_t id, const Eigen::Vector3d& p_W,
                     const std::vector<Eigen::Isometry3d>& T_W_C);
  // The world point of a landmark with depth.
  Eigen::Vector3d worldPoint(const Landmark& l, const std::vector<Eigen::Isometry3d>& T_W_C) const;

  void erase(int64_t id) { landmarks_.erase(id); }
  void clear() {
    landmarks_.clear();
    rejected_.clear();
  }
  std::map<int64_t, Landmark>& landmarks() { return landmarks_; }
  const std::map<int64_t, Landmark>& landmarks() const { return landmarks_; }
  int size() const { return static_cast<int>(landmarks_.size()); }

 private:
  std::map<int64_t, Landmark> landmarks_;
  std::set<int64_t> rejected_;
};

// Linear (DLT) triangulation of one point from normalised observations and camera poses T_W_C:
// the world point minimising the algebraic error. False if the system is degenerate.
bool triangulatePoint(const std::vector<Eigen::Vector2d>& points,
                      const std::vector<Eigen::Isometry3d>& T_W_C, Eigen::Vector3d* p_W);

}  // namespace adugs::vio

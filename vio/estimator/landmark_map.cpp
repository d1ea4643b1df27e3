#include "vio/estimator/landmark_map.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace adugs::vio {

void LandmarkMap::addFrame(int frame, const FrameFeatures& f) {
  std::set<int64_t> still_rejected;
  for (size_t k = 0; k < f.size(); ++k) {
    if (rejected_.count(f.ids[k])) {
      still_rejected.insert(f.ids[k]);
      continue;
    }
    Landmark& l = landmarks_[f.ids[k]];
    l.id = f.ids[k];
    l.observations.push_back({frame, f.normalized[k], f.velocities[k]});
  }
  rejected_.swap(still_rejected);
}

void LandmarkMap::reject(int64_t id) {
  landmarks_.erase(id);
  rejected_.insert(id);
}

double LandmarkMap::meanParallax(int frame_a, int frame_b, int* common) const {
  double sum = 0;
  int n = 0;
  for (const auto& [id, l] : landmarks_) {
    const Observation *a = nullptr, *b = nullptr;
    for (const Observation& o : l.observations) {
      if (o.frame == frame_a) a = &o;
      if (o.frame == frame_b) b = &o;
    }
    if (a && b) {
      sum += (a->point - b->point).norm();
      ++n;
    }
  }
  if (common) *common = n;
  return n > 0 ? sum / n : 0.0;
}

Eigen::Vector3d LandmarkMap::worldPoint(const Landmark& l,
                                        const std::vector<Eigen::Isometry3d>& T_W_C) const {
  const Eigen::Vector3d p_C = l.observations.front().point.homogeneous() / l.inverse_depth;
  return T_W_C.at(l.hostFrame()) * p_C;
}

void LandmarkMap::setWorldPoint(int64_t id, const Eigen::Vector3d& p_W,
                                const std::vector<Eigen::Isometry3d>& T_W_C) {
  auto it = landmarks_.find(id);
  if (it == landmarks_.end()) return;
  const Eigen::Vector3d p_C = T_W_C.at(it->second.hostFrame()).inverse() * p_W;
  if (p_C.z() <= 1e-3) return;
  it->second.inverse_depth = 1.0 / p_C.z();
  it->second.has_depth = true;
}

void LandmarkMap::removeFrame(int frame, const std::vector<Eigen::Isometry3d>* T_W_C) {
  for (auto it = landmarks_.begin(); it != landmarks_.end();) {
    Landmark& l = it->second;
    const bool was_host = l.hostFrame() == frame;
    Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
    const bool keep_depth = was_host && l.has_depth && T_W_C != nullptr;
    if (keep_depth) p_W = worldPoint(l, *T_W_C);
    std::vector<Observation> kept;
    for (Observation o : l.observations) {
      if (o.frame == frame) continue;
      if (o.frame > frame) --o.frame;
      kept.push_back(o);
    }
    l.observations.swap(kept);
    if (l.observations.empty()) {
      it = landmarks_.erase(it);
      continue;
    }
    if (was_host) {
      l.has_depth = false;
      if (keep_depth) {
        // New host index after the shift; its pose in the old indexing is one further.
        const int old_index = l.hostFrame() >= frame ? l.hostFrame() + 1 : l.hostFrame();
        const Eigen::Vector3d p_C = (*T_W_C)[old_index].inverse() * p_W;
        if (p_C.z() > 1e-3) {
          l.inverse_depth = 1.0 / p_C.z();
          l.has_depth = true;
        }
      }
    }
    ++it;
  }
}

bool triangulatePoint(const std::vector<Eigen::Vector2d>& points,
                      const std::vector<Eigen::Isometry3d>& T_W_C, Eigen::Vector3d* p_W) {
  const int n = static_cast<int>(points.size());
  if (n < 2) return false;
  // Each observation x = P X / (P X)_z gives two rows: x * P_3 - P_1, y * P_3 - P_2 (P = T_C_W).
  // X is the null vector of A: the eigenvector of the 4x4 A^T A with the smallest eigenvalue
  // (far cheaper than an SVD of A, and this runs for every depthless landmark every frame).
  Eigen::Matrix4d AtA = Eigen::Matrix4d::Zero();
  for (int k = 0; k < n; ++k) {
    const Eigen::Matrix<double, 3, 4> P = T_W_C[k].inverse().matrix().topRows<3>();
    const Eigen::RowVector4d r1 = points[k].x() * P.row(2) - P.row(0);
    const Eigen::RowVector4d r2 = points[k].y() * P.row(2) - P.row(1);
    AtA += r1.transpose() * r1 + r2.transpose() * r2;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(AtA);
  const Eigen::Vector4d X = eig.eigenvectors().col(0);
  if (std::abs(X(3)) < 1e-12) return false;
  *p_W = X.head<3>() / X(3);
  return p_W->allFinite();
}

int LandmarkMap::triangulate(const std::vector<Eigen::Isometry3d>& T_W_C, double min_depth,
                             double max_depth, double min_angle_rad) {
  int count = 0;
  for (auto& [id, l] : landmarks_) {
    if (l.has_depth || l.observations.size() < 2) continue;
    std::vector<Eigen::Vector2d> pts;
    std::vector<Eigen::Isometry3d> poses;
    for (const Observation& o : l.observations) {
      pts.push_back(o.point);
      poses.push_back(T_W_C.at(o.frame));
    }
    Eigen::Vector3d p_W;
    if (!triangulatePoint(pts, poses, &p_W)) continue;
    // Need parallax: the largest angle at the point between the host ray and another ray. Tiny
    // angles (standing still, features near the focus of expansion) give depths that are noise.
    double max_angle = 0;
    const Eigen::Vector3d host_ray = (p_W - poses.front().translation()).normalized();
    for (const auto& T : poses)
      max_angle = std::max(
          max_angle,
          std::acos(std::clamp(host_ray.dot((p_W - T.translation()).normalized()), -1.0, 1.0)));
    if (max_angle < min_angle_rad) continue;
    // Every observing camera must see it in front.
    bool in_front = true;
    for (const auto& T : poses) in_front = in_front && (T.inverse() * p_W).z() > min_depth;
    const double depth = (poses.front().inverse() * p_W).z();
    if (!in_front || depth > max_depth) continue;
    l.inverse_depth = 1.0 / depth;
    l.has_depth = true;
    ++count;
  }
  return count;
}

}  // namespace adugs::vio

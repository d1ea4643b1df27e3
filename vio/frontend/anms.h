#pragma once
// Adaptive non-maximal suppression (ANMS) of detected keypoints, as doc/architecture.md ("The
// method") defines it:
//   rho_i = min ||p_i - p_j|| over all keypoints j with response r_j > r_i   (strictly stronger)
//   rho_i = +inf when no keypoint is stronger (the strongest, and ties with it)
// then keep the keypoints with the largest radii while enforcing a minimum distance D_min to the
// points already kept and to existing (tracked) features.
//
// D_min is enforced greedily in order of decreasing radius, skipping violators and continuing down
// the list until N are kept (or candidates run out), so the caller gets exactly N whenever the
// candidates allow it - the compensation rule needs exactly N_max - s + r new points. Note that
// among keypoints whose radius is >= D_min the distance rule never bites between them (the weaker
// of any pair has a radius <= their distance), so only the tail and the existing features matter.
#include <limits>
#include <opencv2/core.hpp>
#include <vector>

namespace adugs::vio {

// Suppression radius of each keypoint (same order as the input), +inf for unsuppressed ones.
// Exact; a uniform grid searched in growing rings makes it ~O(n) for image-like point sets.
std::vector<float> suppressionRadii(const std::vector<cv::KeyPoint>& keypoints);
// The O(n^2) definition itself, as the reference the tests compare the grid version against.
std::vector<float> suppressionRadiiBruteForce(const std::vector<cv::KeyPoint>& keypoints);

// Indices (into keypoints) of at most n_keep keypoints, in order of decreasing radius (ties:
// stronger response first, then lower index). A keypoint closer than min_distance to an already
// selected one or to any of `existing` is skipped; min_distance <= 0 disables the rule.
// radii may be passed when already computed (same size as keypoints).
std::vector<int> selectAnms(const std::vector<cv::KeyPoint>& keypoints, int n_keep,
                            double min_distance, const std::vector<cv::Point2f>& existing = {},
                            const std::vector<float>* radii = nullptr);

}  // namespace adugs::vio

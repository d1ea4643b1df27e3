#pragma once
// Ground-truth poses from a ROS1 bag topic, ordered by header.stamp:
//   nav_msgs/Odometry                   pose.pose (frame header.frame_id -> child_frame_id)
//   geometry_msgs/PoseStamped           pose
//   geometry_msgs/PoseWithCovarianceStamped  pose.pose
//   geometry_msgs/TransformStamped      transform
//   tf2_msgs/TFMessage (/tf)            the transforms from `parent_frame` to `child_frame`
//                                       (both required for this type)
// The pose is taken as T_W_B of the body the message describes; `doc/formats.md` says which body
// that is for each dataset. Exact duplicate stamps keep the first pose (counted); an empty result,
// a wrong type or non-finite values are InputErrors naming the bag and topic.
#include <string>

#include "data/types.h"

namespace adugs::data {

struct BagGroundTruthOptions {
  std::string topic;
  std::string parent_frame, child_frame;  // tf2_msgs/TFMessage only
};

struct BagGroundTruth {
  Trajectory poses;  // strictly increasing time
  size_t duplicates_dropped = 0;
};

BagGroundTruth readBagGroundTruth(const std::string& bag_path, const BagGroundTruthOptions& options);

}  // namespace adugs::data

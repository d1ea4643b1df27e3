#include "data/sources/rosbag_ground_truth.h"

#include <algorithm>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>
#include <tf2_msgs/TFMessage.h>

#include "data/input_error.h"
#include "data/sources/rosbag_topics.h"

namespace adugs::data {
namespace {

StampedPose toPose(const ros::Time& stamp, const geometry_msgs::Point& p, const geometry_msgs::Quaternion& q) {
  StampedPose s;
  s.t_ns = static_cast<int64_t>(stamp.toNSec());
  s.p_W_B = {p.x, p.y, p.z};
  s.q_W_B = Eigen::Quaterniond(q.w, q.x, q.y, q.z);
  return s;
}

StampedPose toPose(const ros::Time& stamp, const geometry_msgs::Transform& t) {
  geometry_msgs::Point p;
  p.x = t.translation.x;
  p.y = t.translation.y;
  p.z = t.translation.z;
  return toPose(stamp, p, t.rotation);
}

// Strips a leading '/' (tf frame ids are written both ways).
std::string frameName(const std::string& f) { return !f.empty() && f[0] == '/' ? f.substr(1) : f; }

}  // namespace

BagGroundTruth readBagGroundTruth(const std::string& bag_path, const BagGroundTruthOptions& o) {
  const auto bag = openBag(bag_path);
  const auto topics = listBagTopics(*bag);
  const std::string field = "gt_topic";
  requireTopic(bag_path, topics, field, o.topic,
               {"nav_msgs/Odometry", "geometry_msgs/PoseStamped", "geometry_msgs/PoseWithCovarianceStamped",
                "geometry_msgs/TransformStamped", "tf2_msgs/TFMessage"});
  const std::string type = topics.at(o.topic).type;
  if (type == "tf2_msgs/TFMessage" && (o.parent_frame.empty() || o.child_frame.empty()))
    throw InputError(bag_path, 0, field,
                     "ground truth from " + o.topic + " (tf2_msgs/TFMessage) needs the parent and child frame names");

  BagGroundTruth gt;
  auto bad = [&](const std::string& what) { return InputError(bag_path, 0, "topic " + o.topic, what); };
  try {
    rosbag::View view(*bag, rosbag::TopicQuery(o.topic));
    for (const rosbag::MessageInstance& m : view) {
      if (type == "nav_msgs/Odometry") {
        const auto msg = m.instantiate<nav_msgs::Odometry>();
        if (!msg) throw bad("message does not decode as " + type);
        gt.poses.push_back(toPose(msg->header.stamp, msg->pose.pose.position, msg->pose.pose.orientation));
      } else if (type == "geometry_msgs/PoseStamped") {
        const auto msg = m.instantiate<geometry_msgs::PoseStamped>();
        if (!msg) throw bad("message does not decode as " + type);
        gt.poses.push_back(toPose(msg->header.stamp, msg->pose.position, msg->pose.orientation));
      } else if (type == "geometry_msgs/PoseWithCovarianceStamped") {
        const auto msg = m.instantiate<geometry_msgs::PoseWithCovarianceStamped>();
        if (!msg) throw bad("message does not decode as " + type);
        gt.poses.push_back(toPose(msg->header.stamp, msg->pose.pose.position, msg->pose.pose.orientation));
      } else if (type == "geometry_msgs/TransformStamped") {
        const auto msg = m.instantiate<geometry_msgs::TransformStamped>();
        if (!msg) throw bad("message does not decode as " + type);
        gt.poses.push_back(toPose(msg->header.stamp, msg->transform));
      } else {
        const auto msg = m.instantiate<tf2_msgs::TFMessage>();
        if (!msg) throw bad("message does not decode as " + type);
        for (const geometry_msgs::TransformStamped& t : msg->transforms)
          if (frameName(t.header.frame_id) == frameName(o.parent_frame) &&
              frameName(t.child_frame_id) == frameName(o.child_frame))
            gt.poses.push_back(toPose(t.header.stamp, t.transform));
      }
    }
  } catch (const rosbag::BagException& e) {
    throw InputError(bag_path, 0, "", std::string("corrupt ROS bag: ") + e.what());
  }
  if (gt.poses.empty())
    throw bad(type == "tf2_msgs/TFMessage"
                  ? "no transform from '" + o.parent_frame + "' to '" + o.child_frame + "' on this topic"
                  : "no ground-truth message on this topic");

  std::stable_sort(gt.poses.begin(), gt.poses.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.t_ns < b.t_ns; });
  Trajectory unique;
  unique.reserve(gt.poses.size());
  for (StampedPose& p : gt.poses) {
    if (!p.p_W_B.allFinite() || !p.q_W_B.coeffs().allFinite() || p.q_W_B.norm() < 0.5)
      throw bad("non-finite or zero pose at stamp " + std::to_string(p.t_ns) + " ns");
    p.q_W_B.normalize();
    if (!unique.empty() && unique.back().t_ns == p.t_ns) {
      ++gt.duplicates_dropped;
      continue;
    }
    unique.push_back(p);
  }
  gt.poses = std::move(unique);
  return gt;
}

}  // namespace adugs::data

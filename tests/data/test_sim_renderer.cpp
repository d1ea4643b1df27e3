// Renderer ground truth: 3-D points land where the camera model says (sub-pixel), masks are
// exactly the object pixels, boxes and visibility are consistent, output is deterministic.
#include <cmath>
#include <iostream>
#include <map>

#include <gtest/gtest.h>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "data/sim/sim_random.h"
#include "data/sim/sim_renderer.h"
#include "data/types.h"

namespace adugs::data {
namespace {

Eigen::Isometry3d pose(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

// The camera of the marker tests, looking along world +x, tilted.
Eigen::Isometry3d markerViewPose() {
  return pose(eulerZyxToRotation(0.1, -0.05, 0.03) * eulerZyxToRotation(-M_PI / 2, 0, -M_PI / 2),
              Eigen::Vector3d(0.2, -0.1, 1.3));
}

// A TUM-VI-like fisheye (512x512 equidistant).
SimCamera fisheyeCamera() {
  SimCamera cam;
  cam.width = cam.height = 512;
  cam.fx = 190.97;
  cam.fy = 190.97;
  cam.cx = 254.93;
  cam.cy = 256.9;
  cam.distortion_model = DistortionModel::kEquidistant;
  cam.distortion = {0.00348, 0.000715, -0.00205, 0.000203};
  return cam;
}

// Checkerboard markers (2x2 checker quads) at known 3-D points, rendered from a tilted pose; the
// X-corner found by cornerSubPix must sit on the projection of the 3-D point.
struct Marker {
  Eigen::Vector3d center, normal;
};

void expectMarkerCornersReprojectSubPixel(const SimCamera& cam, const std::vector<Marker>& markers,
                                          double size_m, const std::string& name) {
  SimScene scene;
  SimRng rng(1);
  const int checker = scene.addTexture(makeTexture(SimTextureKind::kChecker, 64, rng));
  scene.background = 128;
  for (const Marker& m : markers) {
    scene.static_quads.push_back(
        makeFacingQuad(m.center, m.normal, Eigen::Vector3d::UnitZ(), size_m, size_m, checker, 0));
    scene.static_quads.back().texels_u = scene.static_quads.back().texels_v = 64;
  }
  SimRenderer renderer(cam);
  SimFrame frame;
  renderer.render(scene, markerViewPose(), 0, SimRenderOptions{}, &frame);

  int checked = 0;
  double worst = 0;
  for (const Marker& m : markers) {
    Eigen::Vector2d uv;
    ASSERT_TRUE(cam.project(markerViewPose().inverse() * m.center, &uv));
    if (uv.x() < 12 || uv.y() < 12 || uv.x() > cam.width - 12 || uv.y() > cam.height - 12) continue;
    std::vector<cv::Point2f> corner{cv::Point2f(float(uv.x() + 1.3), float(uv.y() - 1.1))};
    cv::cornerSubPix(frame.image, corner, cv::Size(5, 5), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4));
    const double err = std::hypot(corner[0].x - uv.x(), corner[0].y - uv.y());
    worst = std::max(worst, err);
    ++checked;
  }
  testing::Test::RecordProperty("worst_corner_error_px_" + name, std::to_string(worst));
  testing::Test::RecordProperty("corners_checked_" + name, checked);
  EXPECT_GE(checked, 8) << name;
  EXPECT_LT(worst, 0.1) << name << " pixels";
}

// The EuRoC lens: a grid of markers in front of the camera.
TEST(SimRenderer, MarkerCornersReprojectSubPixel) {
  std::vector<Marker> markers;
  for (double y : {-1.6, -0.6, 0.4, 1.4})
    for (double z : {0.5, 1.3, 2.1})  // facing the camera roughly, with some slant
      markers.push_back({{3.0 + 0.3 * y, y, z}, Eigen::Vector3d(-1, 0.3 * y, 0.1).normalized()});
  expectMarkerCornersReprojectSubPixel(SimCamera(), markers, 0.4, "radtan");
}

// The fisheye: markers 1.5 m away on rings out to 72 degrees off-axis, where the lens compresses
// the image most.
TEST(SimRenderer, FisheyeMarkerCornersReprojectSubPixel) {
  const Eigen::Isometry3d T_W_C = markerViewPose();
  std::vector<Marker> markers;
  for (double off_axis_deg : {0.0, 35.0, 60.0, 72.0})
    for (double around_deg : {20.0, 110.0, 200.0, 290.0}) {
      const double th = off_axis_deg * M_PI / 180, ph = around_deg * M_PI / 180;
      const Eigen::Vector3d dir_C(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph),
                                  std::cos(th));
      const Eigen::Vector3d slant(0.1, -0.05, 0);
      markers.push_back({T_W_C * (1.5 * dir_C), T_W_C.linear() * (slant - dir_C).normalized()});
      if (off_axis_deg == 0) break;
    }
  expectMarkerCornersReprojectSubPixel(fisheyeCamera(), markers, 0.35, "equidistant");
}

SimScene dynamicScene(const std::string& name, SimLevel level, const SineTrajectory& traj) {
  SimScene scene = buildStaticScene(name, 5, traj);
  addDynamicObjects(scene, level, 5, traj, defaultSimT_B_C());
  return scene;
}

Eigen::Isometry3d cameraPose(const SimTrajectory& traj, int64_t t) {
  const SimBodyState s = traj.stateAt(t);
  return pose(s.q_W_B.toRotationMatrix(), s.p_W_B) * defaultSimT_B_C();
}

// Objects painted 255 and the static world 0: the rendered image IS the mask, pixel for pixel.
TEST(SimRenderer, MaskEqualsObjectPixels) {
  for (const std::string name : {"room", "street", "courtyard"}) {
    const int64_t t0 = 1000000000;
    const SineTrajectory traj = makeSceneTrajectory(name, 5, t0, t0 + secToNs(30));
    const SimScene scene = dynamicScene(name, SimLevel::kHigh, traj);
    ASSERT_FALSE(scene.objects.empty());
    const SimCamera cam = SimCamera().scaled(0.5);
    SimRenderer renderer(cam);
    SimRenderOptions flat;
    flat.static_value = 0;
    flat.object_value = 255;
    int frames_with_objects = 0;
    for (double ts = 0; ts < 30; ts += 1.5) {
      const int64_t t = t0 + secToNs(ts);
      SimFrame f;
      renderer.render(scene, cameraPose(traj, t), t, flat, &f);
      EXPECT_EQ(cv::norm(f.image, f.mask, cv::NORM_INF), 0) << name << " t=" << ts;
      // Boxes: visible pixel counts agree with the id image; boxes hold the visible pixels.
      for (const SimObjectBox& b : f.boxes) {
        const cv::Mat mine = f.object_ids == b.id;
        EXPECT_EQ(cv::countNonZero(mine), b.visible_pixels);
        EXPECT_LE(b.visible_pixels, b.total_pixels);
        if (b.visible_pixels > 0) {
          EXPECT_EQ(cv::countNonZero(mine(b.box)), b.visible_pixels);
        }
      }
      frames_with_objects += f.boxes.empty() ? 0 : 1;
    }
    EXPECT_GT(frames_with_objects, 3) << name;
  }
}

// The courtyard is the scene the estimator was not tuned on: far walls and faint texture. Over
// 20 s of its path the median depth of what the camera sees is several times the room's, and the
// image has fewer FAST corners than the room's or the street's.
TEST(SimRenderer, CourtyardIsFarAndFaint) {
  std::map<std::string, std::pair<double, double>> seen;  // median depth, corners per frame
  for (const std::string name : {"room", "street", "courtyard"}) {
    const int64_t t0 = 1000000000;
    const SineTrajectory traj = makeSceneTrajectory(name, 3, t0, t0 + secToNs(20));
    const SimScene scene = buildStaticScene(name, 3, traj);
    SimRenderer renderer(SimCamera().scaled(0.5));
    std::vector<float> depths;
    double corners = 0;
    int frames = 0;
    for (double ts = 0; ts < 20; ts += 4.0, ++frames) {
      const int64_t t = t0 + secToNs(ts);
      SimFrame f;
      renderer.render(scene, cameraPose(traj, t), t, SimRenderOptions{}, &f);
      for (int y = 0; y < f.depth.rows; y += 4)
        for (int x = 0; x < f.depth.cols; x += 4)
          if (std::isfinite(f.depth.at<float>(y, x))) depths.push_back(f.depth.at<float>(y, x));
      std::vector<cv::KeyPoint> kps;
      cv::FAST(f.image, kps, 20);
      corners += static_cast<double>(kps.size());
    }
    std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
    seen[name] = {depths[depths.size() / 2], corners / frames};
  }
  for (const auto& [name, s] : seen)
    std::cout << name << ": median depth " << s.first << " m, " << s.second << " corners\n";
  EXPECT_GT(seen["courtyard"].first, 3.0 * seen["room"].first);
  EXPECT_GT(seen["courtyard"].first, 8.0);
  EXPECT_LT(seen["courtyard"].second, 0.7 * seen["room"].second);
  EXPECT_LT(seen["courtyard"].second, 0.7 * seen["street"].second);
}

// The fisheye sees the whole street around it; the corners beyond its image circle (85 degrees
// off-axis) are black with no ground truth, and the mask still equals the object pixels.
TEST(SimRenderer, FisheyeImageCircle) {
  const int64_t t0 = 1000000000;
  const SineTrajectory traj = makeSceneTrajectory("street", 5, t0, t0 + secToNs(10));
  const SimScene scene = dynamicScene("street", SimLevel::kHigh, traj);
  const SimCamera cam = fisheyeCamera();
  SimRenderer renderer(cam);
  const double max_tan = std::tan(85.0 * M_PI / 180.0);
  int frames_with_objects = 0;
  for (double ts = 0; ts < 10; ts += 2.5) {
    const int64_t t = t0 + secToNs(ts);
    SimFrame f;
    renderer.render(scene, cameraPose(traj, t), t, SimRenderOptions{}, &f);
    int outside = 0, dark_outside = 0, lit_inside = 0, inside = 0;
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; ++x) {
        const bool in = cam.unproject({double(x), double(y)}).head<2>().norm() < max_tan;
        if (in) {
          ++inside;
          lit_inside += f.image.at<uint8_t>(y, x) > 0;
        } else {
          ++outside;
          dark_outside += f.image.at<uint8_t>(y, x) == 0;
          EXPECT_EQ(f.object_ids.at<uint16_t>(y, x), 0);
          EXPECT_TRUE(std::isinf(f.depth.at<float>(y, x)));
        }
      }
    EXPECT_GT(outside, 10000);  // the four corners
    EXPECT_EQ(dark_outside, outside);
    EXPECT_GT(lit_inside, 0.99 * inside);
    SimRenderOptions flat;
    flat.static_value = 0;
    flat.object_value = 255;
    SimFrame m;
    renderer.render(scene, cameraPose(traj, t), t, flat, &m);
    EXPECT_EQ(cv::norm(m.image, m.mask, cv::NORM_INF), 0) << "t=" << ts;
    frames_with_objects += m.boxes.empty() ? 0 : 1;
  }
  EXPECT_GT(frames_with_objects, 1);
}

// Independent check without distortion: one box in front of a wall; its mask is the set of pixel
// centres inside the convex hull of its projected corners.
TEST(SimRenderer, MaskMatchesProjectedSilhouette) {
  SimScene scene;
  SimRng rng(2);
  const int tex = scene.addTexture(makeTexture(SimTextureKind::kPosters, 64, rng));
  scene.static_quads.push_back(makeFacingQuad({6, 0, 1}, -Eigen::Vector3d::UnitX(),
                                              Eigen::Vector3d::UnitZ(), 20, 10, tex, 30));
  SimObject obj;
  obj.id = 1;
  obj.size = {1.2, 0.8, 1.0};
  obj.quads = makeBoxQuads(Eigen::Vector3d::Zero(), obj.size, tex, 0, true, 64);
  obj.motion.kind = SimObjectMotion::Kind::kPasses;
  obj.motion.passes = {{0, 1000, Eigen::Vector3d(3, 0.3, 0.4), Eigen::Vector3d(3, 0.3, 0.4)}};
  obj.motion.passes[0].to.y() += 1e-6;  // heading along +y: the box turns 90 degrees
  scene.objects.push_back(obj);

  SimCamera cam;
  cam.distortion = {0, 0, 0, 0};
  const Eigen::Isometry3d T_W_C =
      pose(eulerZyxToRotation(0.05, 0.1, 0) * eulerZyxToRotation(-M_PI / 2, 0, -M_PI / 2),
           Eigen::Vector3d(0, 0, 1.2));
  SimRenderer renderer(cam);
  SimFrame f;
  renderer.render(scene, T_W_C, 500, SimRenderOptions{}, &f);

  Eigen::Isometry3d T_W_O;
  ASSERT_TRUE(obj.poseAt(500, &T_W_O));
  std::vector<cv::Point2f> pts, hull;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d c((i & 1 ? 0.5 : -0.5) * obj.size.x(), (i & 2 ? 0.5 : -0.5) * obj.size.y(),
                            (i & 4 ? 1.0 : 0.0) * obj.size.z());
    Eigen::Vector2d uv;
    ASSERT_TRUE(cam.project(T_W_C.inverse() * (T_W_O * c), &uv));
    pts.emplace_back(float(uv.x()), float(uv.y()));
  }
  cv::convexHull(pts, hull);
  int inside = 0, disagree = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const double d = cv::pointPolygonTest(hull, cv::Point2f(float(x), float(y)), true);
      if (std::abs(d) < 1e-3) continue;  // exactly on the outline: either answer is right
      const bool in = d > 0;
      inside += in;
      disagree += in != (f.mask.at<uint8_t>(y, x) == 255);
    }
  EXPECT_GT(inside, 5000);
  EXPECT_EQ(disagree, 0);
  ASSERT_EQ(f.boxes.size(), 1u);
  EXPECT_EQ(f.boxes[0].visible_pixels, f.boxes[0].total_pixels);
  const cv::Rect hull_box = cv::boundingRect(hull);
  EXPECT_NEAR(f.boxes[0].box.x, hull_box.x, 1);
  EXPECT_NEAR(f.boxes[0].box.br().x, hull_box.br().x, 1);
}

// A near object hides part of a far one: the far one's box still spans its whole silhouette and
// its visible fraction drops accordingly.
TEST(SimRenderer, OcclusionGivesPartialVisibility) {
  SimScene scene;
  SimRng rng(3);
  const int tex = scene.addTexture(makeTexture(SimTextureKind::kPerson, 64, rng));
  for (int k = 0; k < 2; ++k) {
    SimObject o;
    o.id = k + 1;
    o.size = {0.4, 1.0, 1.8};
    o.quads = makeBoxQuads(Eigen::Vector3d::Zero(), o.size, tex, 0, true, 64);
    o.motion.kind = SimObjectMotion::Kind::kPingPong;
    const double x = k == 0 ? 6.0 : 3.0, y = k == 0 ? 0.0 : 0.45;
    o.motion.a = {x, y, 0};
    o.motion.b = {x + 1, y, 0};
    o.motion.speed = 0;
    scene.objects.push_back(o);
  }
  SimCamera cam;
  const Eigen::Isometry3d T_W_C = pose(eulerZyxToRotation(-M_PI / 2, 0, -M_PI / 2), Eigen::Vector3d(0, 0, 1));
  SimRenderer renderer(cam);
  SimFrame f;
  renderer.render(scene, T_W_C, 0, SimRenderOptions{}, &f);
  ASSERT_EQ(f.boxes.size(), 2u);
  const SimObjectBox& far = f.boxes[0];
  const SimObjectBox& near = f.boxes[1];
  EXPECT_EQ(near.visibility(), 1.0);
  EXPECT_GT(far.visibility(), 0.2);
  EXPECT_LT(far.visibility(), 0.9);
  EXPECT_LT(far.visible_pixels, far.total_pixels);
}

// A walker: an asymmetric cut-out (a top band and a left column opaque, grey 60; the rest
// transparent with grey 250 behind it, as a video's background would be) drawn as a billboard.
// The mask is exactly the opaque part, none of the background leaks into the object's pixels,
// the sprite is mirrored when the walker crosses the view the other way, and the cycle plays.
SimScene walkerScene(double walk_direction_y, const cv::Mat& sprite0, const cv::Mat& sprite1) {
  SimScene scene;
  SimRng rng(4);
  scene.addTexture(makeTexture(SimTextureKind::kNoise, 64, rng));
  scene.background = 200;
  scene.sprites = {SimSprite(sprite0), SimSprite(sprite1)};
  scene.walk_cycles = {{"w", {0, 1}, "right"}};
  SimObject o;
  o.id = 1;
  o.size = {0.4, 0.72, 1.8};
  o.walk_cycle = 0;
  o.motion.kind = SimObjectMotion::Kind::kPingPong;
  o.motion.a = {4, 0, 0};
  o.motion.b = {4, walk_direction_y, 0};
  o.motion.speed = 1e-9;  // stands still, heading from a to b
  scene.objects.push_back(o);
  return scene;
}

cv::Mat walkerSprite(int grey) {
  cv::Mat bgra(100, 40, CV_8UC4, cv::Scalar(250, 250, 250, 0));
  bgra.rowRange(0, 30).setTo(cv::Scalar(grey, grey, grey, 255));
  bgra(cv::Rect(0, 30, 15, 70)).setTo(cv::Scalar(grey, grey, grey, 255));
  return bgra;
}

TEST(SimRenderer, WalkerIsItsSilhouetteMirroredToItsDirection) {
  SimCamera cam;
  cam.distortion = {0, 0, 0, 0};
  const Eigen::Isometry3d T_W_C = pose(eulerZyxToRotation(-M_PI / 2, 0, -M_PI / 2), Eigen::Vector3d(0, 0, 0.9));
  SimRenderer renderer(cam);
  double left_column_side[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    const double dir = k == 0 ? -1.0 : 1.0;  // world -y is the camera's right (x_C = -y_W)
    const SimScene scene = walkerScene(dir, walkerSprite(60), walkerSprite(60));
    SimFrame f;
    renderer.render(scene, T_W_C, 0, SimRenderOptions{}, &f);
    ASSERT_EQ(f.boxes.size(), 1u);
    const cv::Rect box = f.boxes[0].box;
    // 1.8 m tall at 4 m: fy * 1.8 / 4 pixels; 0.72 m wide.
    EXPECT_NEAR(box.height, cam.fy * 1.8 / 4, 2.0);
    EXPECT_NEAR(box.width, cam.fx * 0.72 / 4, 2.0);
    const int masked = cv::countNonZero(f.mask);
    EXPECT_NEAR(masked, 0.5625 * box.area(), 0.03 * box.area());  // 0.3 + 0.7 * 15 / 40 opaque
    EXPECT_EQ(masked, f.boxes[0].visible_pixels);
    double lo, hi;
    cv::minMaxLoc(f.image, &lo, &hi, nullptr, nullptr, f.mask);
    EXPECT_GE(lo, 59);  // no background grey (250) blended in at the silhouette
    EXPECT_LE(hi, 61);
    // Where is the column (below the band)? Its mean x relative to the box centre.
    const cv::Moments m = cv::moments(f.mask(cv::Rect(box.x, box.y + box.height / 2, box.width, box.height / 2)), true);
    left_column_side[k] = m.m10 / m.m00 - box.width / 2.0;
  }
  // Walking to the camera's right, as in the video: column on the image left; the other way: mirrored.
  EXPECT_LT(left_column_side[0], -0.2 * cam.fx * 0.72 / 4);
  EXPECT_GT(left_column_side[1], 0.2 * cam.fx * 0.72 / 4);
}

TEST(SimRenderer, WalkerCyclePlaysItsFrames) {
  SimCamera cam;
  cam.distortion = {0, 0, 0, 0};
  const Eigen::Isometry3d T_W_C = pose(eulerZyxToRotation(-M_PI / 2, 0, -M_PI / 2), Eigen::Vector3d(0, 0, 0.9));
  SimScene scene = walkerScene(-1, walkerSprite(60), walkerSprite(90));
  scene.objects[0].motion.speed = 1.3;  // 10 frames per second
  scene.objects[0].motion.b = {4, -1000, 0};
  SimRenderer renderer(cam);
  std::vector<double> greys;
  for (int64_t t_ms : {20, 120, 220, 320}) {
    SimFrame f;
    renderer.render(scene, T_W_C, t_ms * 1000000, SimRenderOptions{}, &f);
    ASSERT_GT(cv::countNonZero(f.mask), 100);
    greys.push_back(cv::mean(f.image, f.mask)[0]);
  }
  EXPECT_NEAR(greys[0], 60, 1);
  EXPECT_NEAR(greys[1], 90, 1);
  EXPECT_NEAR(greys[2], 60, 1);
  EXPECT_NEAR(greys[3], 90, 1);
}

// Vignetting darkens by the squared distance from the principal point: nothing there, the given
// share in the farthest corner, a quarter of it halfway.
TEST(SimRenderer, VignettingDarkensTheCornersByItsStrength) {
  const int64_t t0 = 0;
  const SineTrajectory traj = makeSceneTrajectory("room", 4, t0, t0 + secToNs(5));
  const SimScene scene = dynamicScene("room", SimLevel::kNone, traj);
  const SimCamera camera = SimCamera().scaled(0.5);
  SimRenderer renderer(camera);
  SimRenderOptions plain, vignetted;
  vignetted.vignetting = 0.4;
  SimFrame a, b;
  renderer.render(scene, cameraPose(traj, secToNs(2)), secToNs(2), plain, &a);
  renderer.render(scene, cameraPose(traj, secToNs(2)), secToNs(2), vignetted, &b);
  cv::Mat fa, fb;
  a.image.convertTo(fa, CV_32F);
  b.image.convertTo(fb, CV_32F);
  // Mean ratio over a small window (8-bit rounding is +-0.5 grey level per pixel).
  auto ratioAt = [&](double x, double y) {
    const cv::Rect r(static_cast<int>(x) - 3, static_cast<int>(y) - 3, 7, 7);
    const cv::Rect inside = r & cv::Rect(0, 0, fa.cols, fa.rows);
    return cv::sum(fb(inside))[0] / cv::sum(fa(inside))[0];
  };
  const double cx = camera.cx, cy = camera.cy;
  // The farthest corner from the principal point, and the point halfway to it.
  const double fx = cx < camera.width / 2.0 ? camera.width - 1 : 0, fy = cy < camera.height / 2.0 ? camera.height - 1 : 0;
  EXPECT_NEAR(ratioAt(cx, cy), 1.0, 0.02);
  EXPECT_NEAR(ratioAt((cx + fx) / 2, (cy + fy) / 2), 1.0 - 0.4 / 4, 0.03);
  EXPECT_NEAR(ratioAt(fx - (fx > 0 ? 3 : -3), fy - (fy > 0 ? 3 : -3)), 0.6, 0.03);
}

TEST(SimRenderer, DeterministicBytes) {
  const int64_t t0 = 0;
  const SineTrajectory traj = makeSceneTrajectory("street", 9, t0, t0 + secToNs(5));
  SimRenderOptions opt;
  opt.noise_sigma = 2.0;
  opt.noise_seed = 9;
  cv::Mat first;
  for (int run = 0; run < 2; ++run) {
    const SimScene scene = dynamicScene("street", SimLevel::kMid, traj);
    SimRenderer renderer(SimCamera().scaled(0.5));
    SimFrame f;
    renderer.render(scene, cameraPose(traj, secToNs(2)), secToNs(2), opt, &f);
    if (run == 0)
      first = f.image.clone();
    else
      EXPECT_EQ(cv::norm(first, f.image, cv::NORM_INF), 0);
  }
}

}  // namespace
}  // namespace adugs::data

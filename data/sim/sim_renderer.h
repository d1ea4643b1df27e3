#pragma once
// Software renderer of a SimScene: per-pixel ray casting through the camera model
// (data/camera_model.h: any of its projections and distortions). Each pixel's ray is undistorted once (at
// construction); pixels whose ray is 85 degrees or more off-axis (a fisheye's corners, outside its
// image circle) stay black. A frame then rasterises every quad in the pixel box its
// frustum-clipped outline covers (outline edges sampled until samples are at most 4 pixels apart,
// as distortion bends them), intersects the pixel rays with its plane and keeps the nearest hit
// (z-buffer). Only the winning surface is shaded: trilinear (mip-mapped bilinear) texture lookup
// with the level chosen from the pixel footprint, so distant and grazing surfaces are low-pass
// filtered as a real lens/sensor would and KLT sees no texture aliasing.
// The same pass yields exact ground truth: the id of the object seen at each pixel centre (those
// of moving objects: the dynamic mask), each object's full silhouette (box ignoring occluders) and its visible fraction.
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "data/sim/sim_camera.h"
#include "data/sim/sim_scene.h"

namespace adugs::data {

struct SimRenderOptions {
  float exposure_gain = 1.0f;  // multiplies the rendered radiance (auto-exposure changes)
  double noise_sigma = 0.0;    // additive Gaussian pixel noise [grey levels]; 0 = off
  // Vignetting: the light lost in the corner farthest from the principal point (0.3 = 30 %
  // darker there), falling off with the squared distance from it, the leading term of the cos^4
  // law and of the polynomial vignette models calibrated for real cameras (TUM-VI's). 0 = off.
  double vignetting = 0.0;
  uint64_t noise_seed = 0;     // noise is deterministic in (noise_seed, frame time)
  // Motion blur: average of blur_samples renders spread over exposure_ns around the frame time
  // (ground truth is for the centre time). 1 = off.
  int blur_samples = 1;
  int64_t exposure_ns = 0;
  // Validation aid: >= 0 paints every static (resp. object) pixel with this flat grey.
  int static_value = -1;
  int object_value = -1;
};

// Ground truth of one object in one frame.
struct SimObjectBox {
  int id = 0;
  SimObjectClass cls = SimObjectClass::kPerson;
  cv::Rect box;             // pixels the object would cover without occluders, clipped to the image
  int total_pixels = 0;     // pixel centres inside that unoccluded silhouette (in the image)
  int visible_pixels = 0;   // pixel centres where the object is the nearest surface
  bool moving = true;       // false: standing (SimObjectMotion::kStanding), not in the dynamic mask
  double visibility() const { return total_pixels > 0 ? double(visible_pixels) / total_pixels : 0.0; }
};

struct SimFrame {
  cv::Mat image;       // CV_8UC1
  cv::Mat object_ids;  // CV_16UC1: object id at the pixel centre, 0 = static world / sky
  cv::Mat mask;        // CV_8UC1: 255 where object_ids is a moving object (the dynamic mask)
  cv::Mat depth;       // CV_32FC1: z-depth of the nearest surface [m], +inf for sky (and
                       // outside a fisheye's image circle)
  std::vector<SimObjectBox> boxes;  // objects with at least one pixel in the image (by id)
};

// T_W_C at a time, for motion blur.
using SimCameraPoseFn = std::function<Eigen::Isometry3d(int64_t t_ns)>;

class SimRenderer {
 public:
  explicit SimRenderer(const SimCamera& camera);

  const SimCamera& camera() const { return camera_; }

  void render(const SimScene& scene, const SimCameraPoseFn& T_W_C, int64_t t_ns,
              const SimRenderOptions& options, SimFrame* out);
  // No motion blur: one pose.
  void render(const SimScene& scene, const Eigen::Isometry3d& T_W_C, int64_t t_ns,
              const SimRenderOptions& options, SimFrame* out);

 private:
  // A quad in the camera frame, in the form the per-pixel loop wants (floats for speed).
  struct CamQuad {
    Eigen::Vector3d corners[4];       // camera frame, for clipping
    float nx, ny, nz, c;              // plane n . X = c
    float ux, uy, uz, a0;             // a = X . u' - a0 (u' = edge_u / |edge_u|^2)
    float vx, vy, vz, b0;             // b likewise
    float su, sv;                     // texels across edge u / edge v
    float lod_bias;                   // log2(texels per metre) - 0.5 log2|c|: see shade()
    float gain;
    int texture;
    const SimSprite* sprite;          // non-null: alpha-tested cut-out instead of the texture
    int object;                       // object id, 0 = static
  };
  struct ObjectStats {
    int id = 0;
    SimObjectClass cls = SimObjectClass::kPerson;
    int total = 0, visible = 0;
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
    uint32_t stamp = 0;
  };

  // Fills depth_ and quad_ for the scene at time t seen from T_W_C; with stats, also the objects'
  // unoccluded silhouettes.
  void rasterize(const SimScene& scene, const Eigen::Isometry3d& T_W_C, int64_t t_ns,
                 std::vector<ObjectStats>* stats);
  void rasterizeQuad(const CamQuad& q, int index, ObjectStats* stats);
  // Shades the winners into radiance (float), adding into acc.
  void shade(const SimScene& scene, const SimRenderOptions& options, cv::Mat& acc) const;
  // The vignetting factor per pixel for `strength` (cached: the camera does not change).
  const cv::Mat& vignette(double strength);

  SimCamera camera_;
  cv::Mat vignette_;  // CV_32F factors for vignette_strength_
  double vignette_strength_ = 0;
  CameraModel model_;                  // camera_.model()
  int n_ = 0;
  std::vector<float> ray_x_, ray_y_;   // undistorted normalised ray (x, y, 1) per pixel; NaN
                                       // outside the image circle
  std::vector<float> lod_pixel_;       // log2(sqrt(solid angle) * |ray|^1.5), see shade()
  float x_lo_, x_hi_, y_lo_, y_hi_;    // frustum in normalised coordinates
  bool monotonic_distortion_ = true;   // else every quad scans the whole image
  cv::Mat depth_;                      // CV_32F
  std::vector<int> quad_;              // winning CamQuad index per pixel, -1 = none
  std::vector<uint32_t> stamp_;        // silhouette bookkeeping per object
  uint32_t stamp_counter_ = 0;
  std::vector<CamQuad> quads_;
};

}  // namespace adugs::data

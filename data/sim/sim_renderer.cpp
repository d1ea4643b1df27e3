#include "data/sim/sim_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include <opencv2/core.hpp>

namespace adugs::data {

namespace {

constexpr float kNear = 0.02f;  // metres: nothing closer is drawn
constexpr int kEdgeSamples = 16;
// Projected outlines are sampled until consecutive samples are at most this far apart (pixels),
// so the bounding box of a strongly bent (fisheye) edge misses at most a fraction of a pixel,
// well inside the box's 2-pixel margin.
constexpr double kMaxSampleGapPx = 4.0;
constexpr int kMaxEdgeSplits = 10;
// Pixels whose ray is this far off the optical axis or more stay black: the lens' image circle
// (a fisheye's corners). The rays are kept as (x, y, 1), which cannot reach 90 degrees.
constexpr double kMaxRayAngle = 85.0 * M_PI / 180.0;

// log2 to ~0.01 (enough to pick a mip level), much cheaper than std::log2 per pixel.
inline float fastLog2(float x) {
  uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  const float e = static_cast<float>(static_cast<int>((bits >> 23) & 255u) - 127);
  bits = (bits & 0x7FFFFFu) | 0x3F800000u;
  float m;
  std::memcpy(&m, &bits, sizeof m);
  return e + (-0.34484843f * m + 2.02466578f) * m - 0.67487759f;
}

// Pixel bounding box of projected points.
struct PixelBox {
  double u0 = 1e18, v0 = 1e18, u1 = -1e18, v1 = -1e18;
  void add(const Eigen::Vector2d& p) {
    u0 = std::min(u0, p.x()), u1 = std::max(u1, p.x());
    v0 = std::min(v0, p.y()), v1 = std::max(v1, p.y());
  }
};

// Adds the projections of the normalised-plane segment a-b (pixels pa, pb; pa already added)
// between its ends, splitting it in halves while the ends are more than kMaxSampleGapPx apart.
void addSegment(const CameraModel& camera, const Eigen::Vector2d& a, const Eigen::Vector2d& pa,
                const Eigen::Vector2d& b, const Eigen::Vector2d& pb, int depth, PixelBox* box) {
  if (depth >= kMaxEdgeSplits || (pb - pa).squaredNorm() <= kMaxSampleGapPx * kMaxSampleGapPx)
    return;
  const Eigen::Vector2d m = 0.5 * (a + b);
  const Eigen::Vector2d pm = camera.normalizedToPixel(m);
  box->add(pm);
  addSegment(camera, a, pa, m, pm, depth + 1, box);
  addSegment(camera, m, pm, b, pb, depth + 1, box);
}

// Sutherland-Hodgman clip of a convex polygon against the half-space a.X >= 0.
void clipPolygon(std::vector<Eigen::Vector3d>& poly, const Eigen::Vector3d& a, double offset) {
  std::vector<Eigen::Vector3d> out;
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = poly[i];
    const Eigen::Vector3d& q = poly[(i + 1) % n];
    const double dp = a.dot(p) - offset, dq = a.dot(q) - offset;
    if (dp >= 0) out.push_back(p);
    if ((dp >= 0) != (dq >= 0)) out.push_back(p + (q - p) * (dp / (dp - dq)));
  }
  poly.swap(out);
}

}  // namespace

SimRenderer::SimRenderer(const SimCamera& camera) : camera_(camera), model_(camera.model()) {
  const int w = camera.width, h = camera.height;
  const double max_tan = std::tan(kMaxRayAngle);
  n_ = w * h;
  ray_x_.resize(static_cast<size_t>(n_));
  ray_y_.resize(static_cast<size_t>(n_));
  lod_pixel_.resize(static_cast<size_t>(n_));
  float xl = 1e9f, xh = -1e9f, yl = 1e9f, yh = -1e9f;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector3d r = model_.unproject({double(x), double(y)});
      const size_t i = static_cast<size_t>(y * w + x);
      if (!(r.head<2>().norm() < max_tan)) {  // outside the image circle: no ray, never hit
        ray_x_[i] = ray_y_[i] = std::numeric_limits<float>::quiet_NaN();
        lod_pixel_[i] = 0;
        continue;
      }
      // Solid angle of the pixel from the unit-ray derivatives (central differences).
      const Eigen::Vector3d rx = model_.unproject({x + 0.5, double(y)}).normalized() -
                                 model_.unproject({x - 0.5, double(y)}).normalized();
      const Eigen::Vector3d ry = model_.unproject({double(x), y + 0.5}).normalized() -
                                 model_.unproject({double(x), y - 0.5}).normalized();
      ray_x_[i] = static_cast<float>(r.x());
      ray_y_[i] = static_cast<float>(r.y());
      lod_pixel_[i] = static_cast<float>(std::log2(std::sqrt(rx.cross(ry).norm()) * std::pow(r.norm(), 1.5)));
      xl = std::min(xl, ray_x_[i]);
      xh = std::max(xh, ray_x_[i]);
      yl = std::min(yl, ray_y_[i]);
      yh = std::max(yh, ray_y_[i]);
    }
  const float mx = 0.02f * (xh - xl), my = 0.02f * (yh - yl);
  x_lo_ = xl - mx;
  x_hi_ = xh + mx;
  y_lo_ = yl - my;
  y_hi_ = yh + my;
  // Projecting clipped outlines is only safe where distortion maps radius monotonically.
  const double rmax = std::hypot(std::max(-x_lo_, x_hi_), std::max(-y_lo_, y_hi_));
  double prev = -1;
  for (int k = 0; k <= 400 && monotonic_distortion_; ++k) {
    const double r = rmax * k / 400.0;
    const double rd = model_.distort({r, 0}).norm();
    const double rd2 = model_.distort({0, r}).norm();
    if (std::min(rd, rd2) <= prev) monotonic_distortion_ = false;
    prev = std::max(rd, rd2);
  }
  depth_ = cv::Mat(h, w, CV_32F);
  quad_.resize(static_cast<size_t>(n_));
  stamp_.assign(static_cast<size_t>(n_), 0);
}

void SimRenderer::render(const SimScene& scene, const Eigen::Isometry3d& T_W_C, int64_t t_ns,
                         const SimRenderOptions& options, SimFrame* out) {
  SimRenderOptions single = options;
  single.blur_samples = 1;
  render(scene, [&](int64_t) { return T_W_C; }, t_ns, single, out);
}

void SimRenderer::render(const SimScene& scene, const SimCameraPoseFn& T_W_C, int64_t t_ns,
                         const SimRenderOptions& options, SimFrame* out) {
  const int w = camera_.width, h = camera_.height;
  std::vector<ObjectStats> stats;
  rasterize(scene, T_W_C(t_ns), t_ns, &stats);

  // Ground truth from the centre-time pass.
  out->object_ids.create(h, w, CV_16U);
  out->mask.create(h, w, CV_8U);
  uint16_t* ids = out->object_ids.ptr<uint16_t>();
  uint8_t* mask = out->mask.ptr<uint8_t>();
  for (int i = 0; i < n_; ++i) {
    const int q = quad_[static_cast<size_t>(i)];
    const int obj = q >= 0 ? quads_[static_cast<size_t>(q)].object : 0;
    ids[i] = static_cast<uint16_t>(obj);
    mask[i] = obj > 0 && scene.objects[static_cast<size_t>(obj - 1)].moves() ? 255 : 0;
  }
  for (int i = 0; i < n_; ++i)
    if (ids[i] > 0) ++stats[static_cast<size_t>(ids[i] - 1)].visible;
  out->boxes.clear();
  for (const ObjectStats& s : stats) {
    if (s.total <= 0) continue;
    SimObjectBox b;
    b.id = s.id;
    b.cls = s.cls;
    b.moving = scene.objects[static_cast<size_t>(s.id - 1)].moves();
    b.box = cv::Rect(s.x0, s.y0, s.x1 - s.x0 + 1, s.y1 - s.y0 + 1);
    b.total_pixels = s.total;
    b.visible_pixels = s.visible;
    out->boxes.push_back(b);
  }
  depth_.copyTo(out->depth);

  cv::Mat radiance = cv::Mat::zeros(h, w, CV_32F);
  shade(scene, options, radiance);
  const int samples = std::max(1, options.blur_samples);
  if (samples > 1) {
    // The other sub-exposure instants, spread evenly over the exposure window.
    for (int k = 0; k < samples; ++k) {
      const double f = (k + 0.5) / samples - 0.5;
      const int64_t tk = t_ns + static_cast<int64_t>(std::llround(f * static_cast<double>(options.exposure_ns)));
      if (k == samples / 2 && samples % 2 == 1) continue;  // the centre pass is already in
      rasterize(scene, T_W_C(tk), tk, nullptr);
      shade(scene, options, radiance);
    }
    const int passes = samples % 2 == 1 ? samples : samples + 1;
    radiance /= static_cast<double>(passes);
  }
  if (options.exposure_gain != 1.0f && options.static_value < 0 && options.object_value < 0)
    radiance *= options.exposure_gain;
  if (options.vignetting > 0 && options.static_value < 0 && options.object_value < 0)
    radiance = radiance.mul(vignette(options.vignetting));  // optics: before the sensor's noise
  if (options.noise_sigma > 0) {
    cv::Mat noise(h, w, CV_32F);
    cv::RNG rng(options.noise_seed * 0x9E3779B97F4A7C15ull ^ static_cast<uint64_t>(t_ns));
    rng.fill(noise, cv::RNG::NORMAL, 0.0, options.noise_sigma);
    radiance += noise;
  }
  radiance.convertTo(out->image, CV_8U);  // rounds and saturates
}

const cv::Mat& SimRenderer::vignette(double strength) {
  if (vignette_.empty() || vignette_strength_ != strength) {
    const int w = camera_.width, h = camera_.height;
    const double cx = camera_.cx, cy = camera_.cy;
    double r2_max = 0;
    for (const double x : {0.0, w - 1.0})
      for (const double y : {0.0, h - 1.0}) r2_max = std::max(r2_max, (x - cx) * (x - cx) + (y - cy) * (y - cy));
    vignette_.create(h, w, CV_32F);
    for (int y = 0; y < h; ++y) {
      float* row = vignette_.ptr<float>(y);
      for (int x = 0; x < w; ++x)
        row[x] = static_cast<float>(1.0 - strength * ((x - cx) * (x - cx) + (y - cy) * (y - cy)) / r2_max);
    }
    vignette_strength_ = strength;
  }
  return vignette_;
}

void SimRenderer::rasterize(const SimScene& scene, const Eigen::Isometry3d& T_W_C, int64_t t_ns,
                            std::vector<ObjectStats>* stats) {
  depth_.setTo(std::numeric_limits<float>::infinity());
  std::fill(quad_.begin(), quad_.end(), -1);
  quads_.clear();
  const Eigen::Isometry3d T_C_W = T_W_C.inverse();

  auto addQuad = [&](const SimQuad& sq, const Eigen::Isometry3d& T_C_X, int object) {
    CamQuad q;
    const Eigen::Vector3d o = T_C_X * sq.origin;
    const Eigen::Vector3d u = T_C_X.linear() * sq.edge_u, v = T_C_X.linear() * sq.edge_v;
    const Eigen::Vector3d n = u.cross(v).normalized();
    const double c = n.dot(o);
    if (sq.one_sided && c <= 0) return false;  // back face (or seen edge-on)
    q.corners[0] = o;
    q.corners[1] = o + u;
    q.corners[2] = o + u + v;
    q.corners[3] = o + v;
    const Eigen::Vector3d up = u / u.squaredNorm(), vp = v / v.squaredNorm();
    q.nx = float(n.x()), q.ny = float(n.y()), q.nz = float(n.z()), q.c = float(c);
    q.ux = float(up.x()), q.uy = float(up.y()), q.uz = float(up.z()), q.a0 = float(up.dot(o));
    q.vx = float(vp.x()), q.vy = float(vp.y()), q.vz = float(vp.z()), q.b0 = float(vp.dot(o));
    q.su = float(sq.texels_u);
    q.sv = float(sq.texels_v);
    q.lod_bias = float(0.5 * std::log2(sq.texels_u / u.norm() * sq.texels_v / v.norm()) -
                       0.5 * std::log2(std::max(std::abs(c), 1e-9)));
    q.gain = sq.gain;
    q.texture = sq.texture;
    q.sprite = sq.sprite >= 0 ? &scene.sprites.at(static_cast<size_t>(sq.sprite)) : nullptr;
    q.object = object;
    quads_.push_back(q);
    return true;
  };

  for (const SimQuad& sq : scene.static_quads)
    if (addQuad(sq, T_C_W, 0)) rasterizeQuad(quads_.back(), int(quads_.size()) - 1, nullptr);

  if (stats) stats->assign(scene.objects.size(), ObjectStats{});
  for (size_t k = 0; k < scene.objects.size(); ++k) {
    const SimObject& obj = scene.objects[k];
    if (obj.id != static_cast<int>(k) + 1)
      throw std::invalid_argument("SimScene: object ids must be 1..N in order");
    Eigen::Isometry3d T_W_O;
    ObjectStats* st = nullptr;
    if (stats) {
      st = &(*stats)[k];
      st->id = obj.id;
      st->cls = obj.cls;
      if (++stamp_counter_ == 0) {  // wrapped: forget old stamps
        std::fill(stamp_.begin(), stamp_.end(), 0);
        stamp_counter_ = 1;
      }
      st->stamp = stamp_counter_;
      st->x0 = camera_.width;
      st->y0 = camera_.height;
    }
    if (!obj.poseAt(t_ns, &T_W_O)) continue;
    if (obj.walk_cycle >= 0) {
      SimQuad billboard;
      if (walkerBillboard(scene, obj, T_W_O, T_W_C.translation(), t_ns, &billboard) &&
          addQuad(billboard, T_C_W, obj.id))
        rasterizeQuad(quads_.back(), int(quads_.size()) - 1, st);
      continue;
    }
    const Eigen::Isometry3d T_C_O = T_C_W * T_W_O;
    for (const SimQuad& sq : obj.quads)
      if (addQuad(sq, T_C_O, obj.id)) rasterizeQuad(quads_.back(), int(quads_.size()) - 1, st);
  }
}

void SimRenderer::rasterizeQuad(const CamQuad& q, int index, ObjectStats* stats) {
  const int w = camera_.width, h = camera_.height;
  int bx0 = 0, by0 = 0, bx1 = w - 1, by1 = h - 1;
  if (monotonic_distortion_) {
    // Clip the outline to the view frustum, project it (edges sampled: distortion bends them) and
    // scan only its bounding box.
    std::vector<Eigen::Vector3d> poly(q.corners, q.corners + 4);
    clipPolygon(poly, Eigen::Vector3d::UnitZ(), kNear);
    clipPolygon(poly, Eigen::Vector3d(1, 0, -x_lo_), 0);
    clipPolygon(poly, Eigen::Vector3d(-1, 0, x_hi_), 0);
    clipPolygon(poly, Eigen::Vector3d(0, 1, -y_lo_), 0);
    clipPolygon(poly, Eigen::Vector3d(0, -1, y_hi_), 0);
    if (poly.size() < 3) return;
    PixelBox box;
    const bool bent = camera_.hasDistortion();
    const int samples = bent ? kEdgeSamples : 1;
    for (size_t i = 0; i < poly.size(); ++i) {
      const Eigen::Vector2d a = poly[i].head<2>() / poly[i].z();
      const Eigen::Vector3d& nb = poly[(i + 1) % poly.size()];
      const Eigen::Vector2d b = nb.head<2>() / nb.z();
      Eigen::Vector2d prev_x, prev_p;
      for (int s = 0; s <= samples; ++s) {
        const Eigen::Vector2d x =
            s == samples ? b : Eigen::Vector2d(a + (b - a) * (double(s) / samples));
        const Eigen::Vector2d p = model_.normalizedToPixel(x);
        if (s < samples) box.add(p);  // b is the next edge's first sample
        if (bent && s > 0) addSegment(model_, prev_x, prev_p, x, p, 0, &box);
        prev_x = x;
        prev_p = p;
      }
    }
    bx0 = std::max(0, int(std::floor(box.u0)) - 2);
    by0 = std::max(0, int(std::floor(box.v0)) - 2);
    bx1 = std::min(w - 1, int(std::ceil(box.u1)) + 2);
    by1 = std::min(h - 1, int(std::ceil(box.v1)) + 2);
    if (bx0 > bx1 || by0 > by1) return;
  }
  float* depth = depth_.ptr<float>();
  for (int y = by0; y <= by1; ++y) {
    const int row = y * w;
    for (int x = bx0; x <= bx1; ++x) {
      const int i = row + x;
      const float rx = ray_x_[size_t(i)], ry = ray_y_[size_t(i)];
      const float denom = q.nx * rx + q.ny * ry + q.nz;
      if (denom == 0.0f) continue;
      const float t = q.c / denom;  // z-depth: the ray has z = 1
      if (!(t > kNear)) continue;
      if (!stats && t >= depth[i]) continue;
      const float a = t * (q.ux * rx + q.uy * ry + q.uz) - q.a0;
      if (a < 0.0f || a >= 1.0f) continue;
      const float b = t * (q.vx * rx + q.vy * ry + q.vz) - q.b0;
      if (b < 0.0f || b >= 1.0f) continue;
      if (q.sprite && !q.sprite->opaque(a, b)) continue;  // a cut-out's transparent texel
      if (stats && stamp_[size_t(i)] != stats->stamp) {
        stamp_[size_t(i)] = stats->stamp;
        ++stats->total;
        stats->x0 = std::min(stats->x0, x), stats->x1 = std::max(stats->x1, x);
        stats->y0 = std::min(stats->y0, y), stats->y1 = std::max(stats->y1, y);
      }
      if (t >= depth[i]) continue;
      depth[i] = t;
      quad_[size_t(i)] = index;
    }
  }
}

void SimRenderer::shade(const SimScene& scene, const SimRenderOptions& options, cv::Mat& acc) const {
  const float* depth = depth_.ptr<float>();
  float* out = acc.ptr<float>();
  for (int i = 0; i < n_; ++i) {
    const int qi = quad_[size_t(i)];
    if (qi < 0) {
      if (std::isnan(ray_x_[size_t(i)])) continue;  // outside the image circle: black
      out[i] += options.static_value >= 0 ? float(options.static_value) : scene.background;
      continue;
    }
    const CamQuad& q = quads_[size_t(qi)];
    if (q.object > 0 ? options.object_value >= 0 : options.static_value >= 0) {
      out[i] += float(q.object > 0 ? options.object_value : options.static_value);
      continue;
    }
    const float rx = ray_x_[size_t(i)], ry = ray_y_[size_t(i)], t = depth[i];
    const float a = t * (q.ux * rx + q.uy * ry + q.uz) - q.a0;
    const float b = t * (q.vx * rx + q.vy * ry + q.vz) - q.b0;
    // Mip level = log2(texels per metre * pixel footprint on the surface). The footprint is
    // distance * angle / sqrt(cos) (geometric mean of the foreshortened and the unforeshortened
    // axes) with distance = t |ray| and cos = |c| / distance, which splits into a per-quad term,
    // a per-pixel term and 1.5 log2 t.
    const float lod = q.lod_bias + lod_pixel_[size_t(i)] + 1.5f * fastLog2(t);
    if (q.sprite) {
      out[i] += q.gain * q.sprite->sample(a * q.su, b * q.sv, lod);
      continue;
    }
    const SimTexture& tex = scene.textures[size_t(q.texture)];
    out[i] += q.gain * tex.sample(a * q.su, b * q.sv, lod);
  }
}

}  // namespace adugs::data

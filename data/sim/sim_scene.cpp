#include "data/sim/sim_scene.h"

#include <algorithm>
#include <cmath>

#include "data/input_error.h"
#include "data/sim/sim_random.h"
#include "data/types.h"

namespace adugs::data {

namespace {

constexpr int kStaticTextureSize = 512;
constexpr int kObjectTextureSize = 256;
// Independent random streams per purpose: the static world never depends on the level.
constexpr uint64_t kStreamTrajectory = 11, kStreamWorld = 12, kStreamObjects = 13, kStreamStanding = 14;

const Eigen::Vector3d kUp = Eigen::Vector3d::UnitZ();

float lightGain(const Eigen::Vector3d& normal) {
  // Flat shading from a fixed sky light so that walls of different orientation differ.
  const Eigen::Vector3d light = Eigen::Vector3d(0.4, 0.6, 0.7).normalized();
  return static_cast<float>(0.65 + 0.35 * std::abs(normal.normalized().dot(light)));
}

// Body positions sampled along the path (every 0.1 s).
std::vector<Eigen::Vector3d> samplePath(const SimTrajectory& path, double step_s = 0.1) {
  std::vector<Eigen::Vector3d> out;
  const int64_t step = secToNs(step_s);
  for (int64_t t = path.startNs(); t <= path.endNs(); t += step)
    out.push_back(path.stateAt(t).p_W_B);
  out.push_back(path.stateAt(path.endNs()).p_W_B);
  return out;
}

Eigen::AlignedBox3d pathBounds(const std::vector<Eigen::Vector3d>& samples) {
  Eigen::AlignedBox3d box;
  for (const auto& p : samples) box.extend(p);
  return box;
}

// Horizontal distance from point p to the box footprint [c +- half] (0 inside).
double footprintDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& c, double hx, double hy) {
  const double dx = std::max(0.0, std::abs(p.x() - c.x()) - hx);
  const double dy = std::max(0.0, std::abs(p.y() - c.y()) - hy);
  return std::hypot(dx, dy);
}

double minFootprintDistance(const std::vector<Eigen::Vector3d>& path, const Eigen::Vector3d& c,
                            double hx, double hy) {
  double best = 1e300;
  for (const auto& p : path) best = std::min(best, footprintDistance(p, c, hx, hy));
  return best;
}

// Adds a static box unless it comes within `clearance` of the path (horizontally).
bool tryAddStaticBox(SimScene& scene, const std::vector<Eigen::Vector3d>& path,
                     const Eigen::Vector3d& bottom_center, const Eigen::Vector3d& size, int texture,
                     double clearance, double texels_per_meter) {
  if (minFootprintDistance(path, bottom_center, size.x() / 2, size.y() / 2) < clearance)
    return false;
  for (SimQuad q : makeBoxQuads(bottom_center, size, texture, texels_per_meter, false,
                                kStaticTextureSize))
    scene.static_quads.push_back(q);
  return true;
}

// A wall from p0 to p1 (horizontal), between z0 and z1, facing `normal`, in panels of varied
// texture.
void addWall(SimScene& scene, SimRng& rng, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
             double z0, double z1, const Eigen::Vector3d& normal, const std::vector<int>& textures,
             double texels_per_meter) {
  const Eigen::Vector3d along = (p1 - p0).normalized();
  const double length = (p1 - p0).norm();
  double pos = 0;
  while (pos < length - 1e-9) {
    const double w = std::min(length - pos, rng.uniform(1.8, 3.5));
    const Eigen::Vector3d mid = p0 + along * (pos + w / 2);
    const Eigen::Vector3d center(mid.x(), mid.y(), (z0 + z1) / 2);
    const int tex = textures[static_cast<size_t>(rng.uniformInt(0, static_cast<int>(textures.size()) - 1))];
    scene.static_quads.push_back(makeFacingQuad(center, normal, kUp, w, z1 - z0, tex, texels_per_meter));
    pos += w;
  }
}

void buildRoom(SimScene& scene, SimRng& rng, const std::vector<Eigen::Vector3d>& path) {
  const Eigen::AlignedBox3d b = pathBounds(path);
  const double margin = 2.2;
  const double x0 = b.min().x() - margin, x1 = b.max().x() + margin;
  const double y0 = b.min().y() - margin, y1 = b.max().y() + margin;
  const double z0 = std::min(0.0, b.min().z() - 1.0), z1 = b.max().z() + 1.3;
  scene.floor_z = z0;
  scene.background = 128.0f;

  std::vector<int> wall_tex;
  wall_tex.push_back(scene.addTexture(makeTexture(SimTextureKind::kBricks, kStaticTextureSize, rng)));
  wall_tex.push_back(scene.addTexture(makeTexture(SimTextureKind::kPosters, kStaticTextureSize, rng)));
  wall_tex.push_back(scene.addTexture(makeTexture(SimTextureKind::kNoise, kStaticTextureSize, rng)));
  wall_tex.push_back(scene.addTexture(makeTexture(SimTextureKind::kPosters, kStaticTextureSize, rng)));
  const int floor_tex = scene.addTexture(makeTexture(SimTextureKind::kTiles, kStaticTextureSize, rng));
  const int ceil_tex = scene.addTexture(makeTexture(SimTextureKind::kNoise, kStaticTextureSize, rng));
  const int box_tex = scene.addTexture(makeTexture(SimTextureKind::kPosters, kStaticTextureSize, rng));

  const double tpm = 160;  // texels per metre on walls: 3.2 m per texture tile
  addWall(scene, rng, {x0, y0, 0}, {x1, y0, 0}, z0, z1, Eigen::Vector3d::UnitY(), wall_tex, tpm);
  addWall(scene, rng, {x1, y0, 0}, {x1, y1, 0}, z0, z1, -Eigen::Vector3d::UnitX(), wall_tex, tpm);
  addWall(scene, rng, {x1, y1, 0}, {x0, y1, 0}, z0, z1, -Eigen::Vector3d::UnitY(), wall_tex, tpm);
  addWall(scene, rng, {x0, y1, 0}, {x0, y0, 0}, z0, z1, Eigen::Vector3d::UnitX(), wall_tex, tpm);
  const Eigen::Vector3d c((x0 + x1) / 2, (y0 + y1) / 2, 0);
  scene.static_quads.push_back(makeFacingQuad({c.x(), c.y(), z0}, kUp, Eigen::Vector3d::UnitX(),
                                              x1 - x0, y1 - y0, floor_tex, 128));
  scene.static_quads.push_back(makeFacingQuad({c.x(), c.y(), z1}, -kUp, Eigen::Vector3d::UnitX(),
                                              x1 - x0, y1 - y0, ceil_tex, 100));

  // Furniture: crates, cabinets and pillars away from the path.
  int placed = 0;
  for (int attempt = 0; attempt < 400 && placed < 12; ++attempt) {
    const bool pillar = rng.uniform() < 0.25;
    const Eigen::Vector3d size = pillar ? Eigen::Vector3d(0.4, 0.4, z1 - z0)
                                        : Eigen::Vector3d(rng.uniform(0.4, 1.4), rng.uniform(0.4, 1.2),
                                                          rng.uniform(0.4, 1.8));
    const Eigen::Vector3d at(rng.uniform(x0 + size.x() / 2, x1 - size.x() / 2),
                             rng.uniform(y0 + size.y() / 2, y1 - size.y() / 2), z0);
    const int tex = rng.uniform() < 0.5 ? box_tex : wall_tex[0];
    if (tryAddStaticBox(scene, path, at, size, tex, 0.9, 200)) ++placed;
  }
}

// The street's layout from the camera path's bounds: the road's edges 6 m beside the path (lanes
// 3 m from it), sidewalks beyond them; objects on the 30 m of street before and after the path.
struct StreetLayout {
  double road0, road1, x0, x1;
  explicit StreetLayout(const Eigen::AlignedBox3d& path)
      : road0(path.min().y() - 6), road1(path.max().y() + 6), x0(path.min().x() - 30), x1(path.max().x() + 30) {}
  // Strip along the street between y0 and y1.
  Eigen::AlignedBox2d strip(double y0, double y1) const {
    return Eigen::AlignedBox2d(Eigen::Vector2d(x0, y0), Eigen::Vector2d(x1, y1));
  }
  Eigen::AlignedBox2d nearSidewalk() const { return strip(road0 - 3.0, road0 - 0.5); }
  Eigen::AlignedBox2d farSidewalk() const { return strip(road1 + 0.5, road1 + 3.0); }
};
constexpr double kSidewalkHeight = 0.12;

void buildStreet(SimScene& scene, SimRng& rng, const std::vector<Eigen::Vector3d>& path) {
  const Eigen::AlignedBox3d b = pathBounds(path);
  const double x0 = b.min().x() - 35, x1 = b.max().x() + 35;
  const StreetLayout street(b);
  const double road0 = street.road0, road1 = street.road1;
  const double side0 = road0 - 3.5, side1 = road1 + 3.5;  // facades behind sidewalks
  const double z0 = std::min(0.0, b.min().z() - 1.2);
  scene.floor_z = z0;
  scene.background = 215.0f;  // sky

  const int road_tex = scene.addTexture(makeTexture(SimTextureKind::kRoad, kStaticTextureSize, rng));
  const int walk_tex = scene.addTexture(makeTexture(SimTextureKind::kTiles, kStaticTextureSize, rng));
  std::vector<int> facade_tex;
  for (int i = 0; i < 4; ++i)
    facade_tex.push_back(scene.addTexture(makeTexture(SimTextureKind::kFacade, kStaticTextureSize, rng)));
  const int brick_tex = scene.addTexture(makeTexture(SimTextureKind::kBricks, kStaticTextureSize, rng));
  const int poster_tex = scene.addTexture(makeTexture(SimTextureKind::kPosters, kStaticTextureSize, rng));
  facade_tex.push_back(brick_tex);

  const double cx = (x0 + x1) / 2;
  // Road: the lane marks run along x, the road texture tile is 8 m.
  scene.static_quads.push_back(makeFacingQuad({cx, (road0 + road1) / 2, z0}, kUp, Eigen::Vector3d::UnitY(),
                                              x1 - x0, road1 - road0, road_tex, 64));
  scene.static_quads.push_back(makeFacingQuad({cx, (side0 + road0) / 2, z0 + kSidewalkHeight}, kUp,
                                              Eigen::Vector3d::UnitX(), x1 - x0, road0 - side0, walk_tex, 128));
  scene.static_quads.push_back(makeFacingQuad({cx, (road1 + side1) / 2, z0 + kSidewalkHeight}, kUp,
                                              Eigen::Vector3d::UnitX(), x1 - x0, side1 - road1, walk_tex, 128));
  // Kerbs: the vertical step between road and sidewalks.
  scene.static_quads.push_back(makeFacingQuad({cx, road0, z0 + 0.06}, Eigen::Vector3d::UnitY(), kUp,
                                              x1 - x0, kSidewalkHeight, brick_tex, 200));
  scene.static_quads.push_back(makeFacingQuad({cx, road1, z0 + 0.06}, -Eigen::Vector3d::UnitY(), kUp,
                                              x1 - x0, kSidewalkHeight, brick_tex, 200));

  // Facades: buildings of random width and height on both sides, and closing the street ends.
  auto pickFacade = [&]() {
    return facade_tex[static_cast<size_t>(rng.uniformInt(0, static_cast<int>(facade_tex.size()) - 1))];
  };
  for (int side = 0; side < 2; ++side) {
    const double y = side == 0 ? side0 : side1;
    const Eigen::Vector3d normal = Eigen::Vector3d(0, side == 0 ? 1 : -1, 0);
    double x = x0;
    while (x < x1 - 1e-9) {
      const double w = std::min(x1 - x, rng.uniform(6.0, 14.0));
      const double h = rng.uniform(8.0, 20.0);
      scene.static_quads.push_back(
          makeFacingQuad({x + w / 2, y, z0 + h / 2}, normal, kUp, w, h, pickFacade(), 40));
      // Shop front: a poster band at street level makes close-range texture.
      scene.static_quads.push_back(makeFacingQuad({x + w / 2, y + normal.y() * 0.02, z0 + 1.6},
                                                  normal, kUp, w * 0.8, 2.4, poster_tex, 160));
      x += w;
    }
  }
  for (int end = 0; end < 2; ++end) {
    const double x = end == 0 ? x0 : x1;
    const Eigen::Vector3d normal = Eigen::Vector3d(end == 0 ? 1 : -1, 0, 0);
    scene.static_quads.push_back(makeFacingQuad({x, (side0 + side1) / 2, z0 + 9}, normal, kUp,
                                                side1 - side0, 18, pickFacade(), 40));
  }

  // Street furniture on the sidewalks: kiosks, bins, poles.
  int placed = 0;
  for (int attempt = 0; attempt < 400 && placed < 24; ++attempt) {
    const int kind = rng.uniformInt(0, 2);
    const Eigen::Vector3d size = kind == 0   ? Eigen::Vector3d(2.0, 1.5, 2.5)
                                 : kind == 1 ? Eigen::Vector3d(0.6, 0.6, 1.0)
                                             : Eigen::Vector3d(0.2, 0.2, 4.0);
    const bool left = rng.uniform() < 0.5;
    const double y = left ? rng.uniform(side0 + 1.0, road0 - 0.5) : rng.uniform(road1 + 0.5, side1 - 1.0);
    const Eigen::Vector3d at(rng.uniform(x0 + 3, x1 - 3), y, z0 + kSidewalkHeight);
    if (tryAddStaticBox(scene, path, at, size, kind == 2 ? brick_tex : poster_tex, 2.0, 200)) ++placed;
  }
}


// Contrast of an 8-bit texture scaled about its mean (plaster and paving seen from afar: few
// corners, weak gradients).
cv::Mat fadeContrast(const cv::Mat& u8, double factor) {
  const double mean = cv::mean(u8)[0];
  cv::Mat out;
  u8.convertTo(out, CV_8U, factor, mean * (1.0 - factor));
  return out;
}

// An open square between buildings, a scene no option of the estimator was tuned on: the walls
// stand 10-16 m beyond the path on every side (small parallax, depths of 10-30 m), the ground is
// large low-contrast paving, the buildings are faint plaster with rows of identical windows
// (repeated texture), the sky fills the upper part of the view, and a few benches, planters, lamp
// posts and a fountain basin give the only close texture.
void buildCourtyard(SimScene& scene, SimRng& rng, const std::vector<Eigen::Vector3d>& path) {
  const Eigen::AlignedBox3d b = pathBounds(path);
  const double x0 = b.min().x() - rng.uniform(10, 16), x1 = b.max().x() + rng.uniform(10, 16);
  const double y0 = b.min().y() - rng.uniform(10, 16), y1 = b.max().y() + rng.uniform(10, 16);
  const double z0 = std::min(0.0, b.min().z() - 1.4);
  scene.floor_z = z0;
  scene.background = 225.0f;  // overcast sky

  const int paving = scene.addTexture(
      fadeContrast(makeTexture(SimTextureKind::kTiles, kStaticTextureSize, rng), 0.3));
  std::vector<int> walls;
  for (int i = 0; i < 2; ++i)
    walls.push_back(scene.addTexture(
        fadeContrast(makeTexture(SimTextureKind::kFacade, kStaticTextureSize, rng), 0.6)));
  const int plaster = scene.addTexture(
      fadeContrast(makeTexture(SimTextureKind::kNoise, kStaticTextureSize, rng), 0.35));
  walls.push_back(plaster);
  const int stone = scene.addTexture(
      fadeContrast(makeTexture(SimTextureKind::kBricks, kStaticTextureSize, rng), 0.5));
  const int posters = scene.addTexture(makeTexture(SimTextureKind::kPosters, kStaticTextureSize, rng));

  const Eigen::Vector3d c((x0 + x1) / 2, (y0 + y1) / 2, 0);
  scene.static_quads.push_back(makeFacingQuad({c.x(), c.y(), z0}, kUp, Eigen::Vector3d::UnitX(),
                                              x1 - x0, y1 - y0, paving, 40));  // 12.8 m slabs tile
  // Buildings of 9-15 m around the square, facade panels 6-12 m wide.
  const double h = rng.uniform(9.0, 15.0);
  auto building = [&](const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& n) {
    const Eigen::Vector3d along = (p1 - p0).normalized();
    const double length = (p1 - p0).norm();
    for (double pos = 0; pos < length - 1e-9;) {
      const double w = std::min(length - pos, rng.uniform(6.0, 12.0));
      const Eigen::Vector3d mid = p0 + along * (pos + w / 2);
      const int tex = walls[static_cast<size_t>(rng.uniformInt(0, static_cast<int>(walls.size()) - 1))];
      scene.static_quads.push_back(
          makeFacingQuad({mid.x(), mid.y(), z0 + h / 2}, n, kUp, w, h, tex, 48));
      pos += w;
    }
  };
  building({x0, y0, 0}, {x1, y0, 0}, Eigen::Vector3d::UnitY());
  building({x1, y0, 0}, {x1, y1, 0}, -Eigen::Vector3d::UnitX());
  building({x1, y1, 0}, {x0, y1, 0}, -Eigen::Vector3d::UnitY());
  building({x0, y1, 0}, {x0, y0, 0}, Eigen::Vector3d::UnitX());
  // One notice board per side at eye level: the only rich texture, and far away.
  const Eigen::Vector3d normals[4] = {Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(-1, 0, 0),
                                      Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(1, 0, 0)};
  for (const Eigen::Vector3d& n : normals) {
    const double u = rng.uniform(0.25, 0.75);
    // On the wall whose inward normal is n, u of the way along it.
    const Eigen::Vector3d at(n.x() != 0 ? (n.x() > 0 ? x0 : x1) + 0.02 * n.x() : x0 + u * (x1 - x0),
                             n.y() != 0 ? (n.y() > 0 ? y0 : y1) + 0.02 * n.y() : y0 + u * (y1 - y0),
                             z0 + 1.8);
    scene.static_quads.push_back(makeFacingQuad(at, n, kUp, 3.0, 2.0, posters, 120));
  }
  // Street furniture away from the path: benches, planters, lamp posts, a fountain basin.
  bool fountain = false;
  int placed = 0;
  for (int attempt = 0; attempt < 400 && placed < 14; ++attempt) {
    const int kind = fountain ? rng.uniformInt(0, 2) : 3;
    const Eigen::Vector3d size = kind == 0   ? Eigen::Vector3d(1.8, 0.5, 0.45)   // bench
                                 : kind == 1 ? Eigen::Vector3d(1.0, 1.0, 0.8)    // planter
                                 : kind == 2 ? Eigen::Vector3d(0.15, 0.15, 4.5)  // lamp post
                                             : Eigen::Vector3d(3.0, 3.0, 0.6);   // fountain
    const Eigen::Vector3d at(rng.uniform(x0 + 2, x1 - 2), rng.uniform(y0 + 2, y1 - 2), z0);
    if (tryAddStaticBox(scene, path, at, size, kind == 2 ? plaster : stone, 1.5, 150)) {
      ++placed;
      fountain = true;
    }
  }
}

}  // namespace

const char* toString(SimLevel level) {
  switch (level) {
    case SimLevel::kNone: return "none";
    case SimLevel::kLow: return "low";
    case SimLevel::kMid: return "mid";
    case SimLevel::kHigh: return "high";
  }
  return "?";
}

SimLevel parseSimLevel(const std::string& text, const std::string& field) {
  for (SimLevel l : {SimLevel::kNone, SimLevel::kLow, SimLevel::kMid, SimLevel::kHigh})
    if (text == toString(l)) return l;
  throw InputError("command line", 0, field, "unknown dynamic level '" + text + "' (use none, low, mid, high)");
}

const char* toString(SimObjectClass cls) {
  switch (cls) {
    case SimObjectClass::kPerson: return "person";
    case SimObjectClass::kCar: return "car";
    case SimObjectClass::kBus: return "bus";
  }
  return "?";
}

int cocoClassId(SimObjectClass cls) {
  switch (cls) {
    case SimObjectClass::kPerson: return 0;
    case SimObjectClass::kCar: return 2;
    case SimObjectClass::kBus: return 5;
  }
  return -1;
}

SimQuad makeFacingQuad(const Eigen::Vector3d& center, const Eigen::Vector3d& normal,
                       const Eigen::Vector3d& up, double width, double height, int texture,
                       double texels_per_meter) {
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d u = (up - up.dot(n) * n).normalized();
  // The viewer looks along -n; its right is (-n) x up.
  const Eigen::Vector3d right = (-n).cross(u);
  SimQuad q;
  q.origin = center - right * (width / 2) + u * (height / 2);
  q.edge_u = right * width;
  q.edge_v = -u * height;
  q.texture = texture;
  q.texels_u = width * texels_per_meter;
  q.texels_v = height * texels_per_meter;
  q.gain = lightGain(n);
  return q;
}

std::vector<SimQuad> makeBoxQuads(const Eigen::Vector3d& bottom_center, const Eigen::Vector3d& size,
                                  int texture, double texels_per_meter, bool stretch,
                                  int texture_size) {
  const Eigen::Vector3d c = bottom_center + Eigen::Vector3d(0, 0, size.z() / 2);
  const Eigen::Vector3d h = size / 2;
  std::vector<SimQuad> quads;
  auto face = [&](const Eigen::Vector3d& n, const Eigen::Vector3d& up, double w, double ht,
                  double offset) {
    SimQuad q = makeFacingQuad(c + n * offset, n, up, w, ht, texture, texels_per_meter);
    if (stretch) q.texels_u = q.texels_v = texture_size;
    quads.push_back(q);
  };
  face(Eigen::Vector3d::UnitX(), kUp, size.y(), size.z(), h.x());
  face(-Eigen::Vector3d::UnitX(), kUp, size.y(), size.z(), h.x());
  face(Eigen::Vector3d::UnitY(), kUp, size.x(), size.z(), h.y());
  face(-Eigen::Vector3d::UnitY(), kUp, size.x(), size.z(), h.y());
  face(kUp, Eigen::Vector3d::UnitX(), size.y(), size.x(), h.z());
  return quads;
}

bool SimObject::poseAt(int64_t t_ns, Eigen::Isometry3d* T_W_O) const {
  const SimObjectMotion& m = motion;
  Eigen::Vector3d p, heading;
  if (m.kind == SimObjectMotion::Kind::kPingPong) {
    const Eigen::Vector3d d = m.b - m.a;
    const double len = d.norm();
    const double s = std::fmod(m.phase + m.speed * nsToSec(t_ns - m.origin_ns), 2 * len);
    const double along = s < 0 ? s + 2 * len : s;
    const bool forward = along <= len;
    p = m.a + d / len * (forward ? along : 2 * len - along);
    heading = forward ? d : Eigen::Vector3d(-d);
  } else if (m.kind == SimObjectMotion::Kind::kEllipse) {
    const double a = m.angle0 + m.angular_speed * nsToSec(t_ns - m.origin_ns);
    p = m.center + Eigen::Vector3d(m.radius_x * std::cos(a), m.radius_y * std::sin(a), 0);
    heading = Eigen::Vector3d(-m.radius_x * std::sin(a), m.radius_y * std::cos(a), 0) *
              (m.angular_speed >= 0 ? 1.0 : -1.0);
  } else if (m.kind == SimObjectMotion::Kind::kStanding) {
    p = m.center;
    heading = Eigen::Vector3d(std::cos(m.angle0), std::sin(m.angle0), 0);
  } else {
    const SimObjectPass* pass = nullptr;
    for (const SimObjectPass& candidate : m.passes)
      if (t_ns >= candidate.begin_ns && t_ns <= candidate.end_ns) pass = &candidate;
    if (!pass) return false;
    const double f = static_cast<double>(t_ns - pass->begin_ns) /
                     static_cast<double>(pass->end_ns - pass->begin_ns);
    p = pass->from + f * (pass->to - pass->from);
    heading = pass->to - pass->from;
  }
  const double yaw = std::atan2(heading.y(), heading.x());
  T_W_O->setIdentity();
  T_W_O->linear() = Eigen::AngleAxisd(yaw, kUp).toRotationMatrix();
  T_W_O->translation() = p;
  return true;
}

std::vector<std::string> simSceneNames() { return {"room", "street", "courtyard"}; }

void checkSimSceneName(const std::string& name) {
  for (const std::string& n : simSceneNames())
    if (n == name) return;
  throw InputError("command line", 0, "--scene", "unknown scene '" + name + "' (use room, street or courtyard)");
}

Eigen::Isometry3d defaultSimT_B_C() {
  // Camera axes in the body frame: x_C = -y_B, y_C = -z_B, z_C = x_B, then a small mounting tilt.
  Eigen::Matrix3d R;
  R.col(0) = -Eigen::Vector3d::UnitY();
  R.col(1) = -Eigen::Vector3d::UnitZ();
  R.col(2) = Eigen::Vector3d::UnitX();
  const Eigen::Matrix3d tilt = eulerZyxToRotation(0.012, -0.02, 0.008);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = tilt * R;
  T.translation() = Eigen::Vector3d(0.065, -0.018, 0.012);
  return T;
}

std::vector<std::string> simMotionNames() { return {"glide", "handheld"}; }

void checkSimMotionName(const std::string& name) {
  for (const std::string& n : simMotionNames())
    if (n == name) return;
  throw InputError("command line", 0, "--motion", "unknown motion '" + name + "' (use glide or handheld)");
}

SineTrajectory makeSceneTrajectory(const std::string& scene, uint64_t seed, int64_t start_ns,
                                   int64_t end_ns, const std::string& motion) {
  checkSimSceneName(scene);
  checkSimMotionName(motion);
  SimRng rng = SimRng::derive(seed, kStreamTrajectory);
  auto ph = [&]() { return rng.uniform(0, 2 * M_PI); };
  auto vary = [&](double x) { return x * rng.uniform(0.85, 1.15); };
  std::array<SineChannel, 6> ch;
  if (scene == "room") {
    ch[SineTrajectory::kX] = {0.0, 0.0, {{vary(2.0), vary(0.21), ph()}, {0.35, vary(0.57), ph()}}};
    ch[SineTrajectory::kY] = {0.0, 0.0, {{vary(1.5), vary(0.17), ph()}, {0.3, vary(0.63), ph()}}};
    ch[SineTrajectory::kZ] = {1.4, 0.0, {{0.25, vary(0.4), ph()}, {0.05, vary(1.3), ph()}}};
    ch[SineTrajectory::kYaw] = {ph(), vary(0.22), {{0.6, vary(0.3), ph()}, {0.1, vary(1.1), ph()}}};
    ch[SineTrajectory::kPitch] = {0.0, 0.0, {{0.08, vary(0.7), ph()}, {0.03, vary(2.1), ph()}}};
    ch[SineTrajectory::kRoll] = {0.0, 0.0, {{0.06, vary(0.9), ph()}, {0.02, vary(2.5), ph()}}};
  } else if (scene == "courtyard") {  // wandering across an open square, turning to look around
    ch[SineTrajectory::kX] = {0.0, 0.0, {{vary(5.0), vary(0.13), ph()}, {0.4, vary(0.5), ph()}}};
    ch[SineTrajectory::kY] = {0.0, 0.0, {{vary(3.5), vary(0.11), ph()}, {0.3, vary(0.6), ph()}}};
    ch[SineTrajectory::kZ] = {1.5, 0.0, {{0.1, vary(0.45), ph()}, {0.03, vary(1.5), ph()}}};
    ch[SineTrajectory::kYaw] = {ph(), vary(0.15), {{0.5, vary(0.25), ph()}, {0.1, vary(0.9), ph()}}};
    ch[SineTrajectory::kPitch] = {0.0, 0.0, {{0.06, vary(0.6), ph()}, {0.02, vary(2.0), ph()}}};
    ch[SineTrajectory::kRoll] = {0.0, 0.0, {{0.04, vary(0.8), ph()}, {0.015, vary(2.4), ph()}}};
  } else {  // street: back and forth along the street, looking down it and at the facades
    ch[SineTrajectory::kX] = {0.0, 0.0, {{vary(18.0), vary(0.1), ph()}, {0.5, vary(0.7), ph()}}};
    ch[SineTrajectory::kY] = {0.0, 0.0, {{0.8, vary(0.23), ph()}, {0.2, vary(0.9), ph()}}};
    ch[SineTrajectory::kZ] = {1.5, 0.0, {{0.1, vary(0.5), ph()}, {0.03, vary(1.7), ph()}}};
    ch[SineTrajectory::kYaw] = {0.0, 0.0, {{0.7, vary(0.12), ph()}, {0.15, vary(0.6), ph()}}};
    ch[SineTrajectory::kPitch] = {0.0, 0.0, {{0.05, vary(0.8), ph()}, {0.02, vary(2.3), ph()}}};
    ch[SineTrajectory::kRoll] = {0.0, 0.0, {{0.04, vary(1.0), ph()}, {0.015, vary(2.7), ph()}}};
  }
  if (motion == "handheld") {  // drawn after the glide terms, so those stay as they were
    const double step = vary(11.0);  // rad/s: 1.75 steps per second
    const double sway_phase = ph();
    ch[SineTrajectory::kZ].terms.push_back({0.02, step, ph()});
    // Sideways sway at half the step rate; the room and courtyard paths turn all the time, so
    // both axes there.
    ch[SineTrajectory::kY].terms.push_back({0.015, step / 2, sway_phase});
    if (scene != "street")
      ch[SineTrajectory::kX].terms.push_back({0.015, step / 2, sway_phase + M_PI / 2});
    ch[SineTrajectory::kPitch].terms.push_back({0.015, step, ph()});
    ch[SineTrajectory::kRoll].terms.push_back({0.012, step / 2, ph()});
    ch[SineTrajectory::kYaw].terms.push_back({0.01, step / 2, ph()});
  }
  return SineTrajectory(start_ns, end_ns, ch);
}

SimScene buildStaticScene(const std::string& scene, uint64_t seed, const SimTrajectory& body_path) {
  checkSimSceneName(scene);
  SimRng rng = SimRng::derive(seed, kStreamWorld);
  SimScene out;
  out.name = scene;
  const std::vector<Eigen::Vector3d> path = samplePath(body_path);
  if (scene == "room")
    buildRoom(out, rng, path);
  else if (scene == "street")
    buildStreet(out, rng, path);
  else
    buildCourtyard(out, rng, path);
  return out;
}

namespace {

struct LevelSpec {
  int people = 0, cars = 0, buses = 0;
  double speed_scale = 1.0;
  double pass_period_s = 0;  // 0: no close passes
  double pass_distance = 0;  // metres in front of the camera
};

LevelSpec levelSpec(const std::string& scene, SimLevel level) {
  const bool street = scene == "street";
  switch (level) {
    case SimLevel::kNone: return {};
    case SimLevel::kLow: return street ? LevelSpec{3, 2, 0, 0.8, 0, 0} : LevelSpec{2, 0, 0, 0.8, 0, 0};
    case SimLevel::kMid:
      return street ? LevelSpec{6, 4, 1, 1.0, 20, 5.0} : LevelSpec{5, 0, 0, 1.0, 14, 1.6};
    case SimLevel::kHigh:
      return street ? LevelSpec{12, 7, 2, 1.3, 9, 3.0} : LevelSpec{9, 0, 0, 1.3, 7, 0.8};
  }
  return {};
}

Eigen::Vector3d objectSize(SimObjectClass cls, SimRng& rng) {
  switch (cls) {
    case SimObjectClass::kPerson:
      return {rng.uniform(0.3, 0.45), rng.uniform(0.45, 0.6), rng.uniform(1.6, 1.9)};
    case SimObjectClass::kCar:
      return {rng.uniform(3.8, 4.8), rng.uniform(1.7, 1.95), rng.uniform(1.4, 1.7)};
    case SimObjectClass::kBus:
      return {rng.uniform(10.0, 12.0), 2.55, rng.uniform(3.0, 3.4)};
  }
  return Eigen::Vector3d::Ones();
}

class ObjectFactory {
 public:
  // walkers: people are cut-outs from this set (its sprites are added to the scene once).
  ObjectFactory(SimScene& scene, SimRng& rng, const SimTrajectory& path, const SimWalkerSet* walkers)
      : scene_(scene), rng_(rng), path_(path), walkers_(walkers && !walkers->cycles.empty()) {
    if (walkers_ && scene_.walk_cycles.empty()) {
      scene_.sprites = walkers->sprites;
      scene_.walk_cycles = walkers->cycles;
    }
    for (int i = 0; i < 6; ++i)
      person_tex_.push_back(scene_.addTexture(makeTexture(SimTextureKind::kPerson, kObjectTextureSize, rng_)));
    for (int i = 0; i < 6; ++i)
      vehicle_tex_.push_back(scene_.addTexture(makeTexture(SimTextureKind::kVehicle, kObjectTextureSize, rng_)));
    for (int64_t t = path.startNs(); t <= path.endNs(); t += secToNs(0.1))
      samples_.push_back({t, path.stateAt(t).p_W_B});
  }

  SimObject make(SimObjectClass cls) {
    SimObject o;
    o.id = static_cast<int>(scene_.objects.size()) + 1;
    o.cls = cls;
    o.size = objectSize(cls, rng_);
    const auto& pool = cls == SimObjectClass::kPerson ? person_tex_ : vehicle_tex_;
    const int tex = pool[static_cast<size_t>(rng_.uniformInt(0, static_cast<int>(pool.size()) - 1))];
    o.motion.origin_ns = path_.startNs();
    if (walkers_ && cls == SimObjectClass::kPerson) {
      // A cut-out of a real walker, as tall as the box would have been, as wide as its sprite.
      o.walk_cycle = rng_.uniformInt(0, static_cast<int>(scene_.walk_cycles.size()) - 1);
      o.walk_phase = rng_.uniform(0, 100);
      const SimSprite& first = scene_.sprites[static_cast<size_t>(scene_.walk_cycles[o.walk_cycle].frames[0])];
      o.size.y() = o.size.z() * first.width() / first.height();
      return o;
    }
    o.quads = makeBoxQuads(Eigen::Vector3d::Zero(), o.size, tex, 0, true, kObjectTextureSize);
    return o;
  }

  // Minimum horizontal distance between the object's centre and the camera path over time.
  double clearance(const SimObject& o) const {
    double best = 1e300;
    for (const auto& [t, p] : samples_) {
      Eigen::Isometry3d T;
      if (!o.poseAt(t, &T)) continue;
      best = std::min(best, (T.translation() - p).head<2>().norm());
    }
    return best;
  }

  double required(const SimObject& o) const { return 0.5 * o.size.head<2>().norm() + 0.45; }

  void add(SimObject o) { scene_.objects.push_back(std::move(o)); }

  SimRng& rng() { return rng_; }
  const std::vector<std::pair<int64_t, Eigen::Vector3d>>& samples() const { return samples_; }
  Eigen::AlignedBox3d pathBox() const {
    std::vector<Eigen::Vector3d> path;
    for (const auto& s : samples_) path.push_back(s.second);
    return pathBounds(path);
  }

 private:
  SimScene& scene_;
  SimRng& rng_;
  const SimTrajectory& path_;
  bool walkers_;
  std::vector<int> person_tex_, vehicle_tex_;
  std::vector<std::pair<int64_t, Eigen::Vector3d>> samples_;
};


// Random walkers / drivers on ping-pong or ellipse paths inside `area` (ground z), kept clear of
// the camera path.
void addWanderers(ObjectFactory& f, SimObjectClass cls, int count, const Eigen::AlignedBox2d& area,
                  double z, double speed_lo, double speed_hi, bool along_x_only) {
  SimRng& rng = f.rng();
  for (int added = 0, attempt = 0; added < count && attempt < 200; ++attempt) {
    SimObject o = f.make(cls);
    SimObjectMotion& m = o.motion;
    const double speed = rng.uniform(speed_lo, speed_hi);
    auto randomPoint = [&]() {
      return Eigen::Vector3d(rng.uniform(area.min().x(), area.max().x()),
                             rng.uniform(area.min().y(), area.max().y()), z);
    };
    if (along_x_only) {
      m.kind = SimObjectMotion::Kind::kPingPong;
      const Eigen::Vector3d p = randomPoint();
      m.a = {area.min().x(), p.y(), z};
      m.b = {area.max().x(), p.y(), z};
    } else if (rng.uniform() < 0.6) {
      m.kind = SimObjectMotion::Kind::kPingPong;
      m.a = randomPoint();
      m.b = randomPoint();
      if ((m.b - m.a).norm() < 2.0) continue;
    } else {
      m.kind = SimObjectMotion::Kind::kEllipse;
      m.center = randomPoint();
      m.radius_x = rng.uniform(0.8, 2.5);
      m.radius_y = rng.uniform(0.8, 2.5);
      m.angular_speed = speed / (0.5 * (m.radius_x + m.radius_y)) * (rng.uniform() < 0.5 ? -1 : 1);
      m.angle0 = rng.uniform(0, 2 * M_PI);
    }
    m.speed = speed;
    m.phase = rng.uniform(0, 100);
    if (f.clearance(o) < f.required(o)) continue;
    f.add(std::move(o));
    ++added;
  }
}

// Objects that cross right in front of the camera every `period` seconds.
void addClosePasses(ObjectFactory& f, SimObjectClass cls, double period_s, double distance,
                    double speed, double half_length, double floor_z,
                    const SimTrajectory& path, const Eigen::Isometry3d& T_B_C) {
  SimRng& rng = f.rng();
  SimObject o = f.make(cls);
  o.motion.kind = SimObjectMotion::Kind::kPasses;
  const double duration = nsToSec(path.endNs() - path.startNs());
  for (double tc = rng.uniform(2.0, period_s); tc + 1.0 < duration; tc += period_s * rng.uniform(0.8, 1.2)) {
    const int64_t t_ns = path.startNs() + secToNs(tc);
    const SimBodyState s = path.stateAt(t_ns);
    const Eigen::Vector3d cam = s.p_W_B + s.q_W_B * T_B_C.translation();
    Eigen::Vector3d fwd = s.q_W_B * (T_B_C.linear() * Eigen::Vector3d::UnitZ());
    fwd.z() = 0;
    if (fwd.norm() < 0.3) continue;
    fwd.normalize();
    const Eigen::Vector3d side(-fwd.y(), fwd.x(), 0);
    const double dir = rng.uniform() < 0.5 ? 1.0 : -1.0;
    const double half_time = half_length / speed;
    // Try the nominal distance, then further away, until the pass keeps clear of the camera.
    for (double d = distance; d < distance + 3.0; d += 0.25) {
      const Eigen::Vector3d mid(cam.x() + fwd.x() * (d + 0.5 * o.size.x()),
                                cam.y() + fwd.y() * (d + 0.5 * o.size.x()), floor_z);
      SimObjectPass pass{t_ns - secToNs(half_time), t_ns + secToNs(half_time),
                         mid - dir * half_length * side, mid + dir * half_length * side};
      if (!o.motion.passes.empty() && pass.begin_ns <= o.motion.passes.back().end_ns) break;
      SimObject probe = o;
      probe.motion.passes = {pass};
      if (f.clearance(probe) >= 0.5 * o.size.y() + 0.3) {
        o.motion.passes.push_back(pass);
        break;
      }
    }
  }
  if (!o.motion.passes.empty()) f.add(std::move(o));
}

}  // namespace

void addDynamicObjects(SimScene& scene, SimLevel level, uint64_t seed,
                       const SimTrajectory& body_path, const Eigen::Isometry3d& T_B_C,
                       const SimWalkerSet* walkers) {
  if (level == SimLevel::kNone) return;
  SimRng rng = SimRng::derive(seed, kStreamObjects * 16 + static_cast<uint64_t>(level));
  const LevelSpec spec = levelSpec(scene.name, level);
  ObjectFactory f(scene, rng, body_path, walkers);
  const Eigen::AlignedBox3d b = f.pathBox();
  const double z = scene.floor_z;
  const double v = spec.speed_scale;
  if (scene.name == "street") {
    const StreetLayout street(b);
    // People on the sidewalks, cars and buses in the lanes 3 m from the path.
    addWanderers(f, SimObjectClass::kPerson, spec.people, street.nearSidewalk(), z + kSidewalkHeight, 0.8 * v,
                 1.6 * v, true);
    addWanderers(f, SimObjectClass::kPerson, spec.people / 2, street.farSidewalk(), z + kSidewalkHeight, 0.8 * v,
                 1.6 * v, true);
    addWanderers(f, SimObjectClass::kCar, spec.cars, street.strip(street.road0 + 1.2, street.road0 + 3.6), z,
                 4.0 * v, 9.0 * v, true);
    addWanderers(f, SimObjectClass::kBus, spec.buses, street.strip(street.road1 - 3.6, street.road1 - 1.6), z,
                 3.0 * v, 6.0 * v, true);
    if (spec.pass_period_s > 0) {
      addClosePasses(f, SimObjectClass::kCar, spec.pass_period_s, spec.pass_distance, 6.0 * v, 15,
                     z, body_path, T_B_C);
      if (level == SimLevel::kHigh)
        addClosePasses(f, SimObjectClass::kBus, spec.pass_period_s * 1.5, spec.pass_distance + 1.0,
                       5.0, 20, z, body_path, T_B_C);
    }
  } else {
    const Eigen::AlignedBox2d area(b.min().head<2>() - Eigen::Vector2d(1.8, 1.8),
                                   b.max().head<2>() + Eigen::Vector2d(1.8, 1.8));
    addWanderers(f, SimObjectClass::kPerson, spec.people, area, z, 0.6 * v, 1.2 * v, false);
    if (spec.pass_period_s > 0) {
      addClosePasses(f, SimObjectClass::kPerson, spec.pass_period_s, spec.pass_distance, 1.3 * v, 3.5,
                     z, body_path, T_B_C);
      if (level == SimLevel::kHigh)
        addClosePasses(f, SimObjectClass::kPerson, spec.pass_period_s, spec.pass_distance + 0.4,
                       1.1 * v, 3.5, z, body_path, T_B_C);
    }
  }
}

void addStandingObjects(SimScene& scene, int count, uint64_t seed, const SimTrajectory& body_path,
                        const SimWalkerSet* walkers) {
  if (count <= 0) return;
  SimRng rng = SimRng::derive(seed, kStreamStanding);
  ObjectFactory f(scene, rng, body_path, walkers);
  const Eigen::AlignedBox3d b = f.pathBox();
  const double z = scene.floor_z;
  // Places `n` objects of `cls` at random in `area`, facing along x (or anywhere when !along_x).
  auto place = [&](SimObjectClass cls, int n, const Eigen::AlignedBox2d& area, double height, bool along_x) {
    for (int added = 0, attempt = 0; added < n && attempt < 200; ++attempt) {
      SimObject o = f.make(cls);
      o.motion.kind = SimObjectMotion::Kind::kStanding;
      o.motion.speed = 0;
      o.motion.center = {rng.uniform(area.min().x(), area.max().x()), rng.uniform(area.min().y(), area.max().y()), height};
      o.motion.angle0 = along_x ? (rng.uniform() < 0.5 ? 0.0 : M_PI) : rng.uniform(0, 2 * M_PI);
      if (f.clearance(o) < f.required(o)) continue;
      // Apart from the ones already standing (two parked cars in one place would show as one).
      bool apart = true;
      for (const SimObject& other : scene.objects)
        if (!other.moves() && (other.motion.center - o.motion.center).head<2>().norm() <
                                  f.required(other) + f.required(o))
          apart = false;
      if (!apart) continue;
      f.add(std::move(o));
      ++added;
    }
  };
  if (scene.name == "street") {
    // People waiting on both sidewalks; cars parked at both kerbs (the lanes' outer edges).
    const StreetLayout street(b);
    place(SimObjectClass::kPerson, (count + 1) / 2, street.nearSidewalk(), z + kSidewalkHeight, false);
    place(SimObjectClass::kPerson, count / 2, street.farSidewalk(), z + kSidewalkHeight, false);
    place(SimObjectClass::kCar, (count + 1) / 2, street.strip(street.road0 + 0.9, street.road0 + 1.1), z, true);
    place(SimObjectClass::kCar, count / 2, street.strip(street.road1 - 1.1, street.road1 - 0.9), z, true);
  } else {
    place(SimObjectClass::kPerson, count,
          Eigen::AlignedBox2d(b.min().head<2>() - Eigen::Vector2d(1.8, 1.8), b.max().head<2>() + Eigen::Vector2d(1.8, 1.8)),
          z, false);
  }
}

bool walkerBillboard(const SimScene& scene, const SimObject& object, const Eigen::Isometry3d& T_W_O,
                     const Eigen::Vector3d& camera_W, int64_t t_ns, SimQuad* quad) {
  const SimWalkCycle& cycle = scene.walk_cycles.at(static_cast<size_t>(object.walk_cycle));
  const double height = object.size.z();
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d center = T_W_O.translation() + up * (height / 2);
  Eigen::Vector3d to_camera = camera_W - center;
  to_camera.z() = 0;
  if (to_camera.norm() < 1e-3) return false;
  // The video shows about 10 frames per second of people walking at about 1.3 m/s; play the
  // frames forward then backward so the cycle has no jump.
  const int n = static_cast<int>(cycle.frames.size());
  const double speed = object.motion.kind == SimObjectMotion::Kind::kPasses ? 1.3 : std::abs(object.motion.speed);
  const double position = nsToSec(t_ns - object.motion.origin_ns) * 10.0 * speed / 1.3 + object.walk_phase;
  const int period = std::max(1, 2 * n - 2);
  int k = static_cast<int>(std::fmod(position, period));
  if (k >= n) k = period - k;
  const SimSprite& sprite = scene.sprites.at(static_cast<size_t>(cycle.frames[static_cast<size_t>(k)]));
  const double width = height * sprite.width() / sprite.height();
  *quad = makeFacingQuad(center, to_camera, up, width, height, 0, sprite.height() / height);
  quad->sprite = cycle.frames[static_cast<size_t>(k)];
  quad->gain = 1.0f;
  quad->one_sided = false;
  // Mirror when the person walks across the view the other way than in the video.
  const double across = T_W_O.linear().col(0).dot(quad->edge_u.normalized());
  if ((cycle.direction == "right" && across < 0) || (cycle.direction == "left" && across > 0)) {
    quad->origin += quad->edge_u;
    quad->edge_u = -quad->edge_u;
  }
  return true;
}

}  // namespace adugs::data

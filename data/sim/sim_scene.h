#pragma once
// The simulator's world: textured planar quads (static walls, floor, facades, boxes) and moving
// rigid objects (boxes standing for people, cars, buses) with their own trajectories.
// Scenes are generated deterministically from a seed. Dynamic levels (none/low/mid/high, as in
// VIODE) change only the moving objects: the static world and the camera path depend on the seed
// alone, so the four levels of one seed form a benchmark set.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "data/sim/sim_sprite.h"
#include "data/sim/sim_texture.h"
#include "data/sim/sim_trajectory.h"

namespace adugs::data {

enum class SimLevel { kNone, kLow, kMid, kHigh };

// "none", "low", "mid", "high".
const char* toString(SimLevel level);
// Throws InputError (field `field`) naming the valid levels.
SimLevel parseSimLevel(const std::string& text, const std::string& field = "--level");

enum class SimObjectClass { kPerson, kCar, kBus };
const char* toString(SimObjectClass cls);
// COCO class index as YOLO detectors report it (person 0, car 2, bus 5).
int cocoClassId(SimObjectClass cls);

// A textured rectangle: corners origin, origin + edge_u, origin + edge_u + edge_v, origin + edge_v.
// Texture coordinates: s = a * texels_u, t = b * texels_v for the point origin + a edge_u + b edge_v
// (wrapping), so edge_u runs along the texture's rows (right) and edge_v down its columns.
// One-sided quads are seen only from the side where u x v points AWAY from the viewer (u to the
// viewer's right, v down) - closed boxes and room walls skip their back faces.
struct SimQuad {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d edge_u = Eigen::Vector3d::UnitX();
  Eigen::Vector3d edge_v = Eigen::Vector3d::UnitY();
  int texture = 0;
  double texels_u = 128, texels_v = 128;
  float gain = 1.0f;  // flat lighting factor
  bool one_sided = true;
  // >= 0: textured by SimScene::sprites[sprite] instead (not tiled; alpha-tested, so the quad
  // covers only the sprite's opaque texels).
  int sprite = -1;
};

// A quad facing the viewer: `normal` points toward the viewer, `up` is the texture's up direction.
SimQuad makeFacingQuad(const Eigen::Vector3d& center, const Eigen::Vector3d& normal,
                       const Eigen::Vector3d& up, double width, double height, int texture,
                       double texels_per_meter);
// Outer faces (no bottom) of an axis-aligned box given by its bottom centre and size (x, y, z).
// stretch: map the texture once over each face instead of texels_per_meter.
std::vector<SimQuad> makeBoxQuads(const Eigen::Vector3d& bottom_center, const Eigen::Vector3d& size,
                                  int texture, double texels_per_meter, bool stretch,
                                  int texture_size);

// A straight pass: the object moves from `from` to `to` during [begin_ns, end_ns] and is absent
// outside all passes.
struct SimObjectPass {
  int64_t begin_ns = 0, end_ns = 0;
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
};

struct SimObjectMotion {
  // kStanding: at `center` for the whole sequence, facing angle0 (a parked car, a person waiting):
  // an object of a mover class that does not move, so not in the exact dynamic masks.
  enum class Kind { kPingPong, kEllipse, kPasses, kStanding };
  Kind kind = Kind::kPingPong;
  int64_t origin_ns = 0;  // time of phase 0
  // kPingPong: back and forth between a and b at `speed`, starting `phase` metres along.
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
  double speed = 1.0, phase = 0.0;
  // kEllipse: centre + (rx cos w t, ry sin w t), heading along the tangent.
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius_x = 1.0, radius_y = 1.0, angular_speed = 0.5, angle0 = 0.0;
  // kPasses
  std::vector<SimObjectPass> passes;
};

// A moving rigid object. Its frame O: x forward (direction of motion), z up, origin at the bottom
// centre; T_W_O keeps z up and yaws to the heading.
struct SimObject {
  int id = 0;  // >= 1; the MOT track id and the value in the object-id image
  SimObjectClass cls = SimObjectClass::kPerson;
  Eigen::Vector3d size = Eigen::Vector3d::Ones();  // length (x), width (y), height (z)
  std::vector<SimQuad> quads;                      // in frame O
  SimObjectMotion motion;
  // >= 0: a walker drawn from SimScene::walk_cycles[walk_cycle] as a billboard of height size.z()
  // (walkerBillboard) instead of `quads`; walk_phase offsets its cycle.
  int walk_cycle = -1;
  double walk_phase = 0.0;

  // False when the object is absent at t (between passes).
  bool poseAt(int64_t t_ns, Eigen::Isometry3d* T_W_O) const;
  bool moves() const { return motion.kind != SimObjectMotion::Kind::kStanding; }
};

struct SimScene {
  std::string name;
  std::vector<SimTexture> textures;
  std::vector<SimQuad> static_quads;  // world frame
  std::vector<SimObject> objects;
  std::vector<SimSprite> sprites;          // walker cut-outs (data/sim/sim_sprite.h)
  std::vector<SimWalkCycle> walk_cycles;   // frames index `sprites`
  float background = 200.0f;  // grey level where no surface is hit (sky)
  double floor_z = 0.0;

  int addTexture(const cv::Mat& u8) {
    textures.emplace_back(u8);
    return static_cast<int>(textures.size()) - 1;
  }
};

// Names of the built-in scenes: "room", "street".
std::vector<std::string> simSceneNames();
// Throws InputError naming the valid scenes.
void checkSimSceneName(const std::string& name);

// The default camera-to-body extrinsic: camera looking along body x (forward), body z up, with a
// small offset and tilt as on a real rig.
Eigen::Isometry3d defaultSimT_B_C();

// How the rig is carried. "glide": a smooth vehicle-like path (the slow sums of sines alone; RMS
// acceleration 0.15-0.3 m/s^2). "handheld": the same path walked with the rig in hand: vertical
// bob at the step frequency (~1.75 Hz, ~2 cm), sideways sway at half of it, small pitch and roll
// nods (RMS acceleration ~1.5-2 m/s^2, as in handheld recordings such as TUM-VI).
std::vector<std::string> simMotionNames();
// Throws InputError naming the valid motions.
void checkSimMotionName(const std::string& name);

// The camera path of a built-in scene: smooth sums of sines, fixed by the seed. The glide part
// does not depend on `motion` (same seed, same path; handheld adds its terms on top).
SineTrajectory makeSceneTrajectory(const std::string& scene, uint64_t seed, int64_t start_ns,
                                   int64_t end_ns, const std::string& motion = "glide");

// The static world around a body path (sampled to size the room / street). Depends on the seed
// only. "room": textured walls, floor, ceiling, furniture boxes; "street": road, sidewalks, rows
// of facades, street furniture.
SimScene buildStaticScene(const std::string& scene, uint64_t seed, const SimTrajectory& body_path);

// Adds the moving objects of `level`: counts, sizes and speeds grow with the level; the high level
// also sends objects right past the camera so that they fill most of the image. Objects keep a
// clearance from the camera path so they never pass through the camera.
// With `walkers`, the people are cut-outs of real walking people (billboards) instead of textured
// boxes; the boxes mode keeps its exact output.
void addDynamicObjects(SimScene& scene, SimLevel level, uint64_t seed,
                       const SimTrajectory& body_path, const Eigen::Isometry3d& T_B_C,
                       const SimWalkerSet* walkers = nullptr);

// Adds `count` people standing still and, in the street, as many parked cars at the kerb, kept
// clear of the camera path: objects of the detector's classes that do not move (issue 30's scene
// with parked cars and people waiting). Their own random stream: the moving objects of a seed stay
// as they are. With `walkers`, the people are cut-outs of real people (a still frame of a cycle).
void addStandingObjects(SimScene& scene, int count, uint64_t seed, const SimTrajectory& body_path,
                        const SimWalkerSet* walkers = nullptr);

// The quad (world frame) that draws walker `object` at time t: upright at its bottom centre,
// turned about the vertical toward the camera at camera_W, the cycle frame of time t (played
// forward and back at 10 frames per second, the video's rate, scaled by the walking speed),
// mirrored when the person walks the other way across the view than in the video. False when the
// camera is right above it.
bool walkerBillboard(const SimScene& scene, const SimObject& object, const Eigen::Isometry3d& T_W_O,
                     const Eigen::Vector3d& camera_W, int64_t t_ns, SimQuad* quad);

}  // namespace adugs::data

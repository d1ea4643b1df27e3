#include <iostream>

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "tracking/sort/sort_tracker.h"

namespace adugs::tracking {
namespace {

const TrackedObject* findById(const std::vector<TrackedObject>& v, int64_t id) {
  for (const auto& o : v)
    if (o.id == id) return &o;
  return nullptr;
}

// Two people walking towards each other along the same line, crossing in the middle: one is
// partly hidden behind the other for a few frames (no detection), yet both keep their ids.
TEST(SortTracker, CrossingObjectsKeepTheirIdsThroughAMissedDetection) {
  SortTracker sort;
  std::map<int64_t, double> start_x;  // id -> the x it started from
  for (int k = 0; k < 40; ++k) {
    const double xa = 100 + 8.0 * k, xb = 420 - 8.0 * k;  // cross at k = 20
    std::vector<Detection> dets{{Box{xa, 240, 40, 100}, 0}};
    const bool b_hidden = k >= 18 && k <= 21;  // B is behind A around the crossing
    if (!b_hidden) dets.push_back({Box{xb, 250, 40, 100}, 0});
    const auto out = sort.update(dets);
    if (k == 2) {
      ASSERT_EQ(out.size(), 2u);
      for (const auto& o : out) start_x[o.id] = o.box.cx < 260 ? 100.0 : 420.0;
    }
    if (k > 2) {
      ASSERT_EQ(out.size(), 2u) << "frame " << k;
      for (const auto& [id, x0] : start_x) {
        const TrackedObject* o = findById(out, id);
        ASSERT_NE(o, nullptr) << "id " << id << " lost at frame " << k;
        const double expected = x0 == 100.0 ? xa : xb;
        EXPECT_NEAR(o->box.cx, expected, 6.0) << "id " << id << " frame " << k;
        if (x0 == 420.0) {
          EXPECT_EQ(o->detected, !b_hidden);
        }
      }
    }
  }
}

TEST(SortTracker, TracksAreDeletedAfterMaxAgeAndIdsAreNotReused) {
  SortOptions o;
  o.max_age = 3;
  SortTracker sort(o);
  for (int k = 0; k < 5; ++k) sort.update({{Box{50.0 + k, 50, 20, 20}, 2}});
  EXPECT_EQ(sort.liveTracks(), 1);
  for (int k = 0; k < 3; ++k) {
    const auto out = sort.update({});
    ASSERT_EQ(out.size(), 1u);
    EXPECT_FALSE(out[0].detected);
    EXPECT_EQ(out[0].frames_missed, k + 1);
  }
  EXPECT_TRUE(sort.update({}).empty());
  EXPECT_EQ(sort.liveTracks(), 0);
  sort.update({{Box{50, 50, 20, 20}, 2}});
  const auto out = sort.update({{Box{51, 50, 20, 20}, 2}});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].id, 2);  // a new track, not the deleted id 1
}

TEST(SortTracker, DifferentClassesNeverMatchAndLowIouStartsANewTrack) {
  SortTracker sort;
  sort.update({{Box{100, 100, 50, 50}, 0}});
  auto out = sort.update({{Box{100, 100, 50, 50}, 1}});  // same place, other class
  EXPECT_EQ(sort.liveTracks(), 2);
  out = sort.update({{Box{400, 100, 50, 50}, 0}});  // far away: IoU 0 with the class-0 track
  EXPECT_EQ(sort.liveTracks(), 3);
}

TEST(SortTracker, NewTracksNeedMinHitsOnceTheTrackerIsRunning) {
  SortOptions o;
  o.min_hits = 3;
  SortTracker sort(o);
  for (int k = 0; k < 5; ++k) sort.update({});
  EXPECT_TRUE(sort.update({{Box{10, 10, 8, 8}, 0}}).empty());
  EXPECT_TRUE(sort.update({{Box{11, 10, 8, 8}, 0}}).empty());
  EXPECT_EQ(sort.update({{Box{12, 10, 8, 8}, 0}}).size(), 1u);
}

}  // namespace
}  // namespace adugs::tracking

namespace adugs::tracking {
namespace {

// A wide object (a cart, 200 px) moves right at 10 px/frame, is hidden for 5 frames during which
// it stops, and is seen again standing where it stopped. Coasting carried the old velocity; the
// observation-centric re-update replaces it by the motion between the two detections, so the next
// prediction lands closer to where the cart stands.
double predictionErrorAfterOcclusion(bool recovery) {
  SortOptions o;
  o.max_age = 10;
  o.min_hits = 1;
  o.observation_centric_recovery = recovery;
  SortTracker tracker(o);
  for (int f = 0; f < 10; ++f) tracker.update({{Box{100.0 + 10 * f, 200, 200, 80}, 0, 1.0}});
  for (int f = 0; f < 5; ++f) tracker.update({});  // hidden; the person stops at x = 190
  tracker.update({{Box{190, 200, 200, 80}, 0, 1.0}});
  const std::vector<TrackedObject> next = tracker.update({});  // the prediction one frame on
  EXPECT_EQ(next.size(), 1u);
  EXPECT_EQ(next[0].id, 1);  // same identity throughout
  return std::abs(next[0].box.cx - 190.0);
}

TEST(SortTracker, ObservationCentricRecoveryForgetsTheCoastingVelocity) {
  const double with = predictionErrorAfterOcclusion(true), without = predictionErrorAfterOcclusion(false);
  EXPECT_LT(with, 0.5 * without) << "with " << with << " px, without " << without << " px";
  std::cout << "prediction error after the occlusion: " << with << " px with the re-update, " << without
            << " px without\n";
  EXPECT_LT(with, 3.0);
}

// Between detector runs (--detect-every) the boxes are SORT's predictions: a box moving 6 px per
// frame, detected every 3rd frame with dt = 3, is predicted 1 and 2 frames on where it is, and
// predicting does not change the tracker (the next detection matches the same track).
TEST(SortTracker, PredictCarriesTheBoxesBetweenDetectionsWithoutChangingTheState) {
  SortOptions o;
  o.min_hits = 1;
  SortTracker tracker(o);
  std::vector<TrackedObject> out;
  for (int f = 0; f <= 30; f += 3) out = tracker.update({{Box{100.0 + 6 * f, 200, 40, 80}, 0, 1.0}}, f == 0 ? 1 : 3);
  ASSERT_EQ(out.size(), 1u);
  for (int ahead : {1, 2}) {
    const std::vector<TrackedObject> p = tracker.predict(ahead);
    ASSERT_EQ(p.size(), 1u);
    EXPECT_EQ(p[0].id, out[0].id);
    EXPECT_FALSE(p[0].detected);
    EXPECT_EQ(p[0].frames_missed, 0);  // found at the last detection
    EXPECT_NEAR(p[0].box.cx, 100.0 + 6 * (30 + ahead), 1.0) << ahead << " frames on";
    EXPECT_NEAR(p[0].box.w, 40, 0.5);
  }
  const std::vector<TrackedObject> next = tracker.update({{Box{100.0 + 6 * 33, 200, 40, 80}, 0, 1.0}}, 3);
  ASSERT_EQ(next.size(), 1u);
  EXPECT_EQ(next[0].id, out[0].id);
  EXPECT_TRUE(next[0].detected);
  // Tracks not yet reported are not predicted either.
  SortOptions strict;
  strict.min_hits = 3;
  SortTracker young(strict);
  young.update({{Box{10, 10, 5, 5}, 0, 1.0}});
  young.update({});
  young.update({});
  young.update({{Box{300, 300, 20, 20}, 0, 1.0}});
  EXPECT_TRUE(young.predict(1).empty());
}

}  // namespace
}  // namespace adugs::tracking

namespace adugs::tracking {
namespace {

// The camera pans so that a standing person slides 40 px per frame across the image, and is
// missed for 3 frames. With the image motion removed (what the gyro gives `adugs run`) the coasting
// box stays on the person and the same id picks it up again; without, the filter has to learn the
// pan from the detections first.
TEST(SortTracker, CameraMotionCompensationKeepsTheBoxOnAPannedObject) {
  auto run = [](bool compensate) {
    SortOptions o;
    o.min_hits = 1;
    o.max_age = 5;
    SortTracker tracker(o);
    const auto pan = [](const Eigen::Vector2d& p) { return Eigen::Vector2d(p.x() + 40, p.y()); };
    std::vector<TrackedObject> out;
    double worst = 0;
    for (int f = 0; f < 12; ++f) {
      if (compensate && f > 0) tracker.compensateCameraMotion(pan);
      const Box person{50.0 + 40 * f, 200, 40, 100};
      const bool missed = f >= 2 && f <= 4;  // right after the track started: no velocity learnt yet
      out = tracker.update(missed ? std::vector<Detection>{} : std::vector<Detection>{{person, 0, 1.0}});
      if (missed && !out.empty()) worst = std::max(worst, std::abs(out[0].box.cx - person.cx));
    }
    return std::make_pair(worst, out.size() == 1 ? out[0].id : -1);
  };
  const auto [with_error, with_id] = run(true);
  const auto [without_error, without_id] = run(false);
  EXPECT_LT(with_error, 1.0);
  EXPECT_GT(without_error, 40.0);
  EXPECT_EQ(with_id, 1);  // one identity throughout
  std::cout << "coasting box error while missed: " << with_error << " px compensated, " << without_error
            << " px not (final id " << without_id << ")\n";
}

}  // namespace
}  // namespace adugs::tracking

namespace adugs::tracking {
namespace {

// ByteTrack's two stages (high_score): a person whose detector score drops to 0.5 for two frames
// (partly hidden) keeps the track, found in those frames; a lone 0.5 detection elsewhere starts no
// track. Without the split, the low-score box starts a track of its own.
TEST(SortTracker, LowScoreDetectionsExtendTracksButStartNone) {
  SortOptions o;
  o.min_hits = 1;
  o.high_score = 0.8;
  SortTracker sort(o);
  for (int f = 0; f < 3; ++f) sort.update({{Box{100.0 + 5 * f, 100, 40, 100}, 0, 0.95}});
  for (int f = 3; f < 5; ++f) {
    const auto out = sort.update({{Box{100.0 + 5 * f, 100, 40, 100}, 0, 0.5}, {Box{400, 100, 40, 100}, 0, 0.5}});
    ASSERT_EQ(out.size(), 1u) << "frame " << f;
    EXPECT_EQ(out[0].id, 1);
    EXPECT_TRUE(out[0].detected);
    EXPECT_EQ(sort.liveTracks(), 1);
  }
  SortOptions plain = o;
  plain.high_score = 0;
  SortTracker all(plain);
  all.update({{Box{100, 100, 40, 100}, 0, 0.95}});
  all.update({{Box{105, 100, 40, 100}, 0, 0.95}, {Box{400, 100, 40, 100}, 0, 0.5}});
  EXPECT_EQ(all.liveTracks(), 2);
}

// A low-score detection is offered only to tracks found in the previous frame: a track that
// coasted through a gap is not revived by one (a detector's doubtful box near a lost track).
TEST(SortTracker, LowScoreDetectionsDoNotReviveLostTracks) {
  SortOptions o;
  o.min_hits = 1;
  o.max_age = 5;
  o.high_score = 0.8;
  SortTracker sort(o);
  for (int f = 0; f < 3; ++f) sort.update({{Box{100, 100, 40, 100}, 0, 0.95}});
  sort.update({});
  const auto out = sort.update({{Box{100, 100, 40, 100}, 0, 0.5}});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].detected);
  EXPECT_EQ(out[0].frames_missed, 2);
}

// OC-SORT's recovery (last_box_association): a person walking at 10 px per frame stops behind a
// pillar for 4 frames and reappears where they were last seen. The coasting prediction ran 50 px
// ahead (IoU 0 with a 30 px wide box): without the recovery a new identity starts, with it the
// track's last detected box finds them.
int64_t idAfterStoppingBehindAPillar(bool last_box) {
  SortOptions o;
  o.min_hits = 1;
  o.max_age = 10;
  o.last_box_association = last_box;
  SortTracker sort(o);
  for (int f = 0; f < 10; ++f) sort.update({{Box{100.0 + 10 * f, 200, 30, 90}, 0, 1.0}});
  for (int f = 0; f < 4; ++f) sort.update({});
  const auto out = sort.update({{Box{190, 200, 30, 90}, 0, 1.0}});
  for (const TrackedObject& t : out)
    if (t.detected) return t.id;
  return -1;
}

TEST(SortTracker, LastBoxAssociationFindsAPersonWhoStoppedWhileHidden) {
  EXPECT_EQ(idAfterStoppingBehindAPillar(true), 1);
  EXPECT_EQ(idAfterStoppingBehindAPillar(false), 2);
}

// OC-SORT's momentum (direction_weight): a track moving right at 4 px per frame (40 x 100 box) is
// offered a box 6 px above its prediction (IoU 0.89, direction 20.6 degrees off its motion seen
// from 3 detections back) and one 7 px ahead (IoU 0.70, on its line of motion). IoU alone takes
// the box above; the direction term (bonus w score (90 - angle) / 180: 0.386 w against 0.5 w)
// prefers the one ahead once 0.114 w outweighs the IoU difference 0.185 (w = 2).
double chosenY(double direction_weight) {
  SortOptions o;
  o.min_hits = 1;
  o.direction_weight = direction_weight;
  o.filter.beta_pos = o.filter.beta_size = 1e-3;  // trust the (exact) detections: prediction = last + 4
  SortTracker sort(o);
  for (int f = 0; f < 8; ++f) sort.update({{Box{100.0 + 4 * f, 200, 40, 100}, 0, 1.0}});
  const double x = 100.0 + 4 * 8;
  const auto out = sort.update({{Box{x, 194, 40, 100}, 0, 1.0}, {Box{x + 7, 200, 40, 100}, 0, 1.0}});
  for (const TrackedObject& t : out)
    if (t.id == 1) return t.box.cy;
  return -1;
}

TEST(SortTracker, DirectionConsistencyPrefersTheDetectionAheadOfTheMotion) {
  EXPECT_NEAR(chosenY(0), 194, 1.0);
  EXPECT_NEAR(chosenY(2), 200, 1.0);
}

// A box that grew while detected (an object coming closer) is reported coasting, by update() and
// by predict(), at most coasting_growth_max times its size when last detected; the filter, which
// keeps growing it, is not capped (0 = off shows how far it would go).
TEST(SortTracker, CoastingBoxesGrowLittlePastTheirLastDetectedSize) {
  for (const double cap : {1.2, 0.0}) {
    SortOptions options;
    options.coasting_growth_max = cap;
    SortTracker sort(options);
    std::vector<TrackedObject> out;
    for (int k = 0; k < 8; ++k) out = sort.update({{Box{320, 240, 40.0 + 12 * k, 80.0 + 24 * k}, 0}});
    ASSERT_EQ(out.size(), 1u);
    const Box seen = out[0].box;
    double widest = 0, tallest = 0;
    for (int k = 1; k <= 4; ++k) {
      out = sort.update({});
      ASSERT_EQ(out.size(), 1u);
      EXPECT_EQ(out[0].frames_missed, k);
      widest = std::max(widest, out[0].box.w / seen.w);
      tallest = std::max(tallest, out[0].box.h / seen.h);
      const std::vector<TrackedObject> ahead = sort.predict(3);
      ASSERT_EQ(ahead.size(), 1u);
      widest = std::max(widest, ahead[0].box.w / seen.w);
      tallest = std::max(tallest, ahead[0].box.h / seen.h);
    }
    if (cap > 0) {
      EXPECT_LE(widest, cap + 1e-9);
      EXPECT_LE(tallest, cap + 1e-9);
      EXPECT_GT(widest, 1.1);  // it still grows up to the cap
    } else {
      EXPECT_GT(widest, 1.5) << "the uncapped filter swells the box";
      EXPECT_GT(tallest, 1.5);
    }
  }
}

// Tentative tracks (drop_unconfirmed_on_miss): a one-frame false detection is forgotten at its
// first missed frame instead of coasting max_age frames.
TEST(SortTracker, UnconfirmedTracksAreDroppedAtTheirFirstMiss) {
  for (const bool drop : {true, false}) {
    SortOptions o;
    o.min_hits = 3;
    o.max_age = 10;
    o.drop_unconfirmed_on_miss = drop;
    SortTracker sort(o);
    for (int f = 0; f < 5; ++f) sort.update({{Box{100, 100, 40, 100}, 0, 1.0}});
    sort.update({{Box{100, 100, 40, 100}, 0, 1.0}, {Box{400, 100, 40, 100}, 0, 1.0}});  // a false box
    EXPECT_EQ(sort.liveTracks(), 2);
    sort.update({{Box{100, 100, 40, 100}, 0, 1.0}});
    EXPECT_EQ(sort.liveTracks(), drop ? 1 : 2) << (drop ? "drop" : "keep");
  }
}

}  // namespace
}  // namespace adugs::tracking

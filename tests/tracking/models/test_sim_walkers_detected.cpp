// The simulator's walkers (cut-outs of real people from vtest.avi, data/sim/sim_sprite.h) are what
// makes the detector chain testable in simulation: a real detector must recognise them, which it
// does not for the textured boxes that stood for people before.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "data/formats/mot_io.h"
#include "data/input_error.h"
#include "data/sim/sim_sequence.h"
#include "data/sim/sim_sprite.h"
#include "tests/test_support.h"
#include "tracking/detect/detector_factory.h"

namespace adugs::tracking {
namespace {

namespace fs = std::filesystem;

struct Recall {
  int people = 0, found = 0;
  double value() const { return people ? double(found) / people : 0.0; }
};

// Recall at IoU 0.5 of the people that are more than half visible and at least 40 px tall (the
// detectors' input sizes, 320-416 px, leave smaller people a few pixels high), every 4th frame.
Recall personRecall(const std::string& people, Detector& detector) {
  test::TempDir dir("adugs_sim_walkers");
  data::SimSequenceOptions o;
  o.scene = "room";
  o.level = data::SimLevel::kHigh;
  o.seed = 2;
  o.duration_s = 8;
  o.people = people;
  o.progress = false;
  data::generateSimSequence(o, dir.path().string());
  std::vector<std::string> images;
  for (const auto& e : fs::directory_iterator(dir / "mav0/cam0/data")) images.push_back(e.path().string());
  std::sort(images.begin(), images.end());
  const auto truth = data::readMotFile((dir / "mav0/objects0/gt.txt").string());
  Recall r;
  for (size_t f = 0; f < images.size(); f += 4) {
    const auto it = truth.find(static_cast<int>(f) + 1);
    if (it == truth.end()) continue;
    const std::vector<Detection> found = detector.detect(cv::imread(images[f], cv::IMREAD_GRAYSCALE));
    for (const data::MotBox& b : it->second) {
      if (b.class_id != 0 || b.visibility <= 0.5 || b.height < 40) continue;
      ++r.people;
      const Box person = Box::fromCorners(b.left, b.top, b.left + b.width, b.top + b.height);
      r.found += std::any_of(found.begin(), found.end(), [&](const Detection& d) {
        return d.class_id == 0 && intersectionOverUnion(d.box, person) > 0.5;
      });
    }
  }
  return r;
}

TEST(SimWalkers, ARealDetectorRecognisesThemAndNotTheOldBoxes) {
  const auto model = test::sharedModelsDir() / "yolox_nano" / "yolox_nano.onnx";
  ADUGS_REQUIRE_SHARED(model);
  ASSERT_FALSE(data::defaultWalkersDir().empty())
      << "the build did not cut the walker sprites (vtest.avi from Debian's opencv-doc): run scripts/setup.sh";
  const std::unique_ptr<Detector> detector = makeDetector(model.string());
  const Recall walkers = personRecall("walkers", *detector);
  const Recall boxes = personRecall("boxes", *detector);
  std::cout << "YOLOX-nano person recall in the simulated room (high level): walkers " << walkers.found << "/"
            << walkers.people << ", boxes " << boxes.found << "/" << boxes.people << "\n";
  ASSERT_GT(walkers.people, 40);
  EXPECT_GE(walkers.value(), 0.6);  // measured 0.85 (72/85), 2026-11-25
  EXPECT_LT(boxes.value(), 0.2);
}

TEST(SimWalkers, MissingOrBrokenSpritesAreNamed) {
  test::TempDir dir("adugs_walkers_bad");
  EXPECT_THROW(data::loadWalkerSet(dir.path().string()), data::InputError);
  test::writeText(dir / "walkers.yaml", "walkers:\n  - name: w0\n    frames: 2\n");
  fs::create_directories(dir / "w0");
  cv::imwrite((dir / "w0/frame_00.png").string(), cv::Mat(20, 10, CV_8UC4, cv::Scalar(1, 2, 3, 255)));
  try {
    data::loadWalkerSet(dir.path().string());
    FAIL() << "loaded a walker with a missing frame";
  } catch (const data::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frame_01.png"), std::string::npos) << e.what();
  }
  cv::imwrite((dir / "w0/frame_01.png").string(), cv::Mat(20, 10, CV_8UC1, cv::Scalar(1)));
  try {
    data::loadWalkerSet(dir.path().string());
    FAIL() << "loaded a sprite without alpha";
  } catch (const data::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no alpha"), std::string::npos) << e.what();
  }
  cv::imwrite((dir / "w0/frame_01.png").string(), cv::Mat(20, 10, CV_8UC4, cv::Scalar(1, 2, 3, 255)));
  const data::SimWalkerSet set = data::loadWalkerSet(dir.path().string());
  ASSERT_EQ(set.cycles.size(), 1u);
  EXPECT_EQ(set.cycles[0].frames, (std::vector<int>{0, 1}));
}

}  // namespace
}  // namespace adugs::tracking

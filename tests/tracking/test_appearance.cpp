// The appearance cue: box colour histograms, and SORT keeping identities by them where IoU alone
// swaps them.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "tracking/sort/appearance.h"
#include "tracking/sort/sort_tracker.h"

namespace adugs::tracking {
namespace {

TEST(Appearance, HistogramsCompareColoursAndGreyLevels) {
  cv::Mat image(200, 300, CV_8UC3, cv::Scalar(0, 0, 200));       // red (BGR)
  image(cv::Rect(150, 0, 150, 200)).setTo(cv::Scalar(200, 0, 0));  // blue right half
  const Box red{60, 100, 60, 100}, blue{230, 100, 60, 100}, red2{80, 120, 40, 60};
  const cv::Mat h_red = boxHistogram(image, red), h_blue = boxHistogram(image, blue);
  ASSERT_EQ(h_red.total(), 32u);
  EXPECT_NEAR(cv::sum(h_red)[0], 1.0, 1e-6);
  EXPECT_NEAR(histogramSimilarity(h_red, boxHistogram(image, red2)), 1.0, 1e-6);
  EXPECT_NEAR(histogramSimilarity(h_red, h_blue), 0.0, 1e-6);
  cv::Mat grey;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  const cv::Mat g = boxHistogram(grey, red);
  EXPECT_EQ(g.total(), 16u);
  EXPECT_NEAR(histogramSimilarity(g, g), 1.0, 1e-6);
  EXPECT_TRUE(boxHistogram(image, Box{-100, -100, 10, 10}).empty());
  EXPECT_EQ(histogramSimilarity(cv::Mat(), h_red), 0.0);
}

// Two people side by side (red at x = 100, blue at x = 120) trade places in one frame and stay
// there. On IoU alone each track takes the detection that stayed closest - the other person; with
// the appearance cue each keeps its colour.
TEST(Appearance, KeepsIdentitiesWhereIoUAloneSwapsThem) {
  cv::Mat red(10, 10, CV_8UC3, cv::Scalar(0, 0, 200)), blue(10, 10, CV_8UC3, cv::Scalar(200, 0, 0));
  const cv::Mat h_red = boxHistogram(red, {5, 5, 10, 10}), h_blue = boxHistogram(blue, {5, 5, 10, 10});
  for (double weight : {0.0, 1.0}) {
    SortOptions o;
    o.min_hits = 1;
    o.appearance_weight = weight;
    SortTracker tracker(o);
    std::vector<TrackedObject> out;
    for (int f = 0; f < 40; ++f) {  // swapped from frame 10 on; the filters settle by frame 40
      const bool swapped = f >= 10;
      out = tracker.update({{Box{swapped ? 118.0 : 100.0, 200, 40, 100}, 0, 1.0, h_red},
                            {Box{swapped ? 102.0 : 120.0, 200, 40, 100}, 0, 1.0, h_blue}});
      ASSERT_EQ(out.size(), 2u);
    }
    // Track 1 started on the red person: where is it now?
    const TrackedObject& first = out[0].id == 1 ? out[0] : out[1];
    if (weight > 0)
      EXPECT_GT(first.box.cx, 110) << "with the appearance cue, track 1 follows red to x = 118";
    else
      EXPECT_LT(first.box.cx, 110) << "on IoU alone, track 1 stays at x ~ 102 (blue)";
  }
}

}  // namespace
}  // namespace adugs::tracking

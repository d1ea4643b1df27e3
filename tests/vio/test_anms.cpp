// ANMS: a 5-point example worked by hand, the grid radii against the O(n^2) definition, the
// D_min rule, and the point of it all: kept points cover the image more evenly than top-N.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "tests/test_support.h"
#include "vio/frontend/anms.h"

namespace adugs::vio {
namespace {

cv::KeyPoint kp(float x, float y, float response) {
  cv::KeyPoint k(x, y, 7.0f);
  k.response = response;
  return k;
}

// P0 (10,10) r=50: nothing stronger                           -> rho = inf
// P1 (20,10) r=40: P0 at 10                                   -> rho = 10
// P2 (10,40) r=30: P0 at 30, P1 at sqrt(10^2+30^2) = 31.62    -> rho = 30
// P3 (60,60) r=20: P0 at 70.71, P1 at 64.03, P2 at sqrt(2900) -> rho = 53.852
// P4 (22,12) r=10: P0 at 12.17, P1 at sqrt(8), P2 30.46, ...  -> rho = 2.828
std::vector<cv::KeyPoint> fivePoints() {
  return {kp(10, 10, 50), kp(20, 10, 40), kp(10, 40, 30), kp(60, 60, 20), kp(22, 12, 10)};
}

TEST(Anms, HandWorkedRadii) {
  for (const auto& radii :
       {suppressionRadii(fivePoints()), suppressionRadiiBruteForce(fivePoints())}) {
    ASSERT_EQ(radii.size(), 5u);
    EXPECT_TRUE(std::isinf(radii[0]));
    EXPECT_NEAR(radii[1], 10.0, 1e-5);
    EXPECT_NEAR(radii[2], 30.0, 1e-5);
    EXPECT_NEAR(radii[3], std::sqrt(2900.0), 1e-4);
    EXPECT_NEAR(radii[4], std::sqrt(8.0), 1e-5);
  }
}

TEST(Anms, HandWorkedSelection) {
  // Radius order: P0 (inf), P3 (53.9), P2 (30), P1 (10), P4 (2.8). Top-3 by response would be
  // P0 P1 P2, all in one corner; ANMS takes P0 P3 P2.
  EXPECT_EQ(selectAnms(fivePoints(), 3, 0.0), (std::vector<int>{0, 3, 2}));
  // D_min = 12 and a tracked feature at (58,55): P3 is 5.4 px from it, P1 is 10 px from P0, so
  // the walk goes on to P4 (12.17 px from P0, 30.5 from P2).
  EXPECT_EQ(selectAnms(fivePoints(), 3, 12.0, {{58, 55}}), (std::vector<int>{0, 2, 4}));
  // Asking for more than the candidates allow returns what is left.
  EXPECT_EQ(selectAnms(fivePoints(), 10, 12.0, {{58, 55}}).size(), 3u);
  EXPECT_TRUE(selectAnms(fivePoints(), 0, 0.0).empty());
  EXPECT_TRUE(selectAnms({}, 5, 10.0).empty());
}

TEST(Anms, EqualResponsesDoNotSuppressEachOther) {
  const std::vector<cv::KeyPoint> k = {kp(0, 0, 5), kp(3, 4, 5), kp(100, 0, 1)};
  const auto radii = suppressionRadii(k);
  EXPECT_TRUE(std::isinf(radii[0]));
  EXPECT_TRUE(std::isinf(radii[1]));
  EXPECT_NEAR(radii[2], std::hypot(97.0, 4.0), 1e-4);
}

std::vector<cv::KeyPoint> randomKeypoints(int n, unsigned seed, bool integer_responses,
                                          bool clustered) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> ux(0, 752), uy(0, 480), ur(0, 100);
  std::normal_distribution<float> blob(0, 15);
  std::vector<cv::KeyPoint> k;
  for (int i = 0; i < n; ++i) {
    float x = ux(rng), y = uy(rng);
    if (clustered && i % 2 == 0) x = 200 + blob(rng), y = 150 + blob(rng);
    const float r = integer_responses ? std::floor(ur(rng) / 10) : ur(rng);
    k.push_back(kp(x, y, r));
  }
  return k;
}

TEST(Anms, GridRadiiEqualBruteForce) {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    const auto k = randomKeypoints(1500, seed, seed % 2 == 0, seed % 3 == 0);
    const auto fast = suppressionRadii(k), ref = suppressionRadiiBruteForce(k);
    for (size_t i = 0; i < k.size(); ++i) {
      if (std::isinf(ref[i])) {
        EXPECT_TRUE(std::isinf(fast[i])) << i;
      } else {
        EXPECT_FLOAT_EQ(fast[i], ref[i]) << "seed " << seed << " point " << i;
      }
    }
  }
}

TEST(Anms, KeptPointsRespectMinDistanceAndCount) {
  const auto k = randomKeypoints(3000, 7, false, true);
  const std::vector<cv::Point2f> existing = {{100, 100}, {400, 300}, {700, 50}};
  const double d_min = 20.0;
  const auto kept = selectAnms(k, 150, d_min, existing);
  EXPECT_EQ(kept.size(), 150u);  // 3000 candidates over 752x480 leave plenty of room
  for (size_t a = 0; a < kept.size(); ++a) {
    for (const auto& e : existing) EXPECT_GE(cv::norm(k[kept[a]].pt - e), d_min);
    for (size_t b = a + 1; b < kept.size(); ++b)
      EXPECT_GE(cv::norm(k[kept[a]].pt - k[kept[b]].pt), d_min);
  }
}

// Evenness of a point set: the mean distance from a dense grid of image samples to the nearest
// kept point (the smaller, the more evenly the points cover the image).
double meanCoverageDistance(const std::vector<cv::Point2f>& pts, int width, int height) {
  double sum = 0;
  int n = 0;
  for (int y = 4; y < height; y += 8) {
    for (int x = 4; x < width; x += 8) {
      double best = 1e18;
      for (const auto& p : pts) best = std::min(best, double(cv::norm(p - cv::Point2f(x, y))));
      sum += best;
      ++n;
    }
  }
  return sum / n;
}

void expectSpreadBetterThanTopN(const std::vector<cv::KeyPoint>& k, int n, int width, int height) {
  std::vector<cv::Point2f> anms, top;
  for (int i : selectAnms(k, n, 0.0)) anms.push_back(k[i].pt);
  std::vector<cv::KeyPoint> sorted = k;
  std::sort(sorted.begin(), sorted.end(),
            [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
  for (int i = 0; i < n; ++i) top.push_back(sorted[i].pt);
  const double d_anms = meanCoverageDistance(anms, width, height);
  const double d_top = meanCoverageDistance(top, width, height);
  EXPECT_LT(d_anms, 0.8 * d_top) << "ANMS " << d_anms << " px vs top-N " << d_top << " px";
}

TEST(Anms, SpreadsBetterThanTopNSynthetic) {
  // Responses rise to the left, as when one side of the scene is much more textured.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> ux(0, 752), uy(0, 480), noise(0, 10);
  std::vector<cv::KeyPoint> k;
  for (int i = 0; i < 2000; ++i) {
    const float x = ux(rng), y = uy(rng);
    k.push_back(kp(x, y, 100 - x / 10 + noise(rng)));
  }
  expectSpreadBetterThanTopN(k, 150, 752, 480);
}

TEST(Anms, SpreadsBetterThanTopNOnRealFrame) {
  const auto path =
      test::sharedDataDir() / "euroc_v101_micro/mav0/cam0/data/1403715273262142976.png";
  ADUGS_REQUIRE_SHARED(path);
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(image.empty());
  std::vector<cv::KeyPoint> k;
  cv::FAST(image, k, 20, true);
  ASSERT_GT(k.size(), 500u);
  expectSpreadBetterThanTopN(k, 150, image.cols, image.rows);
}

}  // namespace
}  // namespace adugs::vio

// Regression against numbers computed by the `evo` tool's algorithms (evo_ape, translation_part
// and rotation_angle_deg, --align / --correct_scale / --n_to_align) on a small checked-in pair:
// tests/data/reference/{gt_synthetic.csv, est_synthetic.txt} (see make_reference_pair.py there).
// The figures are tests/data/reference/evo_reference.txt, which derive_evo_reference.py there
// re-derives with numpy alone (evo's association, Umeyama alignment and APE statistics; posyaw
// as ov_eval's yaw-only AlignUtils): run it outside CI and compare. Pinned to 1e-9 relative.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "data/formats/trajectory_io.h"
#include "tests/test_support.h"
#include "vio/eval/trajectory_eval.h"

namespace adugs {
namespace {

std::string referenceFile(const std::string& name) {
  return std::string(ADUGS_SOURCE_DIR) + "/tests/data/reference/" + name;
}

struct Reference {
  std::string mode;
  int align_frames = -1;
  double scale = 1;
  double trans[6];  // rmse, mean, median, std, min, max [m]
  double rot[6];    // same [deg]
  size_t pairs = 0;
};

// evo_reference.txt, as tests/data/reference/derive_evo_reference.py writes it.
std::vector<Reference> readReferences() {
  std::ifstream in(referenceFile("evo_reference.txt"));
  std::vector<Reference> refs;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream row(line);
    Reference r;
    row >> r.mode >> r.align_frames >> r.scale;
    for (double& v : r.trans) row >> v;
    for (double& v : r.rot) row >> v;
    row >> r.pairs;
    EXPECT_FALSE(row.fail()) << "evo_reference.txt: " << line;
    refs.push_back(r);
  }
  return refs;
}

void expectStats(const vio::ErrorStats& s, const double (&want)[6], size_t pairs, const std::string& what) {
  const double got[6] = {s.rmse, s.mean, s.median, s.std, s.min, s.max};
  const char* names[6] = {"rmse", "mean", "median", "std", "min", "max"};
  for (int k = 0; k < 6; ++k)
    EXPECT_NEAR(got[k], want[k], 1e-9 * std::abs(want[k])) << what << " " << names[k];
  EXPECT_EQ(s.count, pairs) << what;
}

TEST(EvalReference, MatchesEvoNumbers) {
  const data::Trajectory est = data::readTrajectory(referenceFile("est_synthetic.txt"));
  const data::Trajectory gt = data::readTrajectory(referenceFile("gt_synthetic.csv"));
  const std::vector<Reference> refs = readReferences();
  ASSERT_EQ(refs.size(), 5u) << "se3, sim3, posyaw, none, se3 on the first 50";
  for (const Reference& ref : refs) {
    const std::string what = ref.mode + " N=" + std::to_string(ref.align_frames);
    vio::EvalOptions options;
    options.align = vio::parseAlignMode(ref.mode);
    options.align_frames = ref.align_frames;
    const vio::EvalResult r = vio::evaluateTrajectory(est, gt, options);  // max dt 0.01 s as evo
    EXPECT_EQ(r.pairs.size(), ref.pairs) << what;
    EXPECT_NEAR(r.T_G_E.scale, ref.scale, 1e-9) << what;
    expectStats(r.ate.translation, ref.trans, ref.pairs, what + " translation");
    expectStats(r.ate.rotation, ref.rot, ref.pairs, what + " rotation");
  }
}

TEST(EvalReference, CommandLinePrintsTheSameRmse) {
  std::string out;
  const int code = test::runAdugs("eval --est " + referenceFile("est_synthetic.txt") + " --gt " +
                                      referenceFile("gt_synthetic.csv") + " --align sim3",
                                  &out);
  ASSERT_EQ(code, 0) << out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, std::regex(R"(trans \[m\]\s+([0-9.]+))"))) << out;
  EXPECT_NEAR(std::stod(m[1]), 0.0518138712239, 1e-6) << out;
  EXPECT_NE(out.find("scale 1.105395"), std::string::npos) << out;
}

}  // namespace
}  // namespace adugs

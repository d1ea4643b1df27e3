// `adugs eval-mot --gt gt.txt --est tracks.txt [--gt ... --est ...] [--json out.json]`: CLEAR-MOT
// and identity metrics of tracker output against MOTChallenge ground truth, per sequence and
// OVERALL when several pairs are given. Ground-truth rows with confidence 0 are, by default,
// "ignore" regions: not scored, and hypotheses on them are neither matches nor false positives
// (--ignore-rule zero-confidence); --ignore-rule mot15 is TrackEval's MOT15 setting: those rows are
// dropped and every hypothesis is scored, so one on them is a false positive.
// Frames scored: the union of the two files' frames.
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.h"
#include "data/formats/atomic_file.h"
#include "data/formats/mot_io.h"
#include "data/input_error.h"
#include "tracking/eval/hota.h"
#include "tracking/eval/mot_metrics.h"

namespace adugs::app {
namespace {

// What a ground-truth row with confidence 0 means.
enum class IgnoreRule {
  kZeroConfidenceRegions,  // an ignore region: hypotheses on it are not scored (MOT16/17 devkits' spirit)
  kMot15,                  // TrackEval's MOT15: the row is dropped, hypotheses on it are false positives
};

const std::map<std::string, IgnoreRule> kIgnoreRules = {{"zero-confidence", IgnoreRule::kZeroConfidenceRegions},
                                                       {"mot15", IgnoreRule::kMot15}};

std::string ignoreRuleName(IgnoreRule rule) {
  for (const auto& [name, r] : kIgnoreRules)
    if (r == rule) return name;
  return "?";
}

struct EvalMotArgs {
  std::vector<std::string> gt, est;
  double iou_min = 0.5;
  IgnoreRule ignore_rule = IgnoreRule::kZeroConfidenceRegions;
  std::string json;
  std::string switches;  // CSV of the identity switches
};

struct PairResult {
  tracking::MotSummary summary;
  tracking::HotaSummary hota;
  std::vector<tracking::IdSwitch> switches;  // frame = the MOTChallenge frame number
};

tracking::Box toBox(const data::MotBox& b) {
  return tracking::Box::fromCorners(b.left, b.top, b.left + b.width, b.top + b.height);
}

PairResult evaluatePair(const std::string& gt_path, const std::string& est_path, double iou_min,
                        IgnoreRule ignore_rule) {
  const auto gt = data::readMotFile(gt_path);
  const auto est = data::readMotFile(est_path);
  std::set<int> frames;
  for (const auto& [f, boxes] : gt) frames.insert(f);
  for (const auto& [f, boxes] : est) frames.insert(f);
  tracking::MotAccumulator acc(iou_min);
  tracking::HotaAccumulator hota;
  for (int f : frames) {
    std::vector<tracking::LabelledBox> g, h;
    std::vector<tracking::Box> ignored;
    if (const auto it = gt.find(f); it != gt.end())
      for (const data::MotBox& b : it->second) {
        if (b.confidence != 0) g.push_back({b.id, toBox(b)});
        else if (ignore_rule == IgnoreRule::kZeroConfidenceRegions) ignored.push_back(toBox(b));
      }
    if (const auto it = est.find(f); it != est.end())
      for (const data::MotBox& b : it->second) h.push_back({b.id, toBox(b)});
    const std::vector<bool> scored = acc.addFrame(g, h, ignored);
    std::vector<tracking::LabelledBox> h_scored;  // HOTA leaves out the same boxes on ignored regions
    for (size_t j = 0; j < h.size(); ++j)
      if (scored[j]) h_scored.push_back(h[j]);
    hota.addFrame(g, h_scored);
  }
  PairResult r{acc.summary(), hota.summary(), acc.idSwitches()};
  const std::vector<int> frame_numbers(frames.begin(), frames.end());
  for (tracking::IdSwitch& s : r.switches) s.frame = frame_numbers[s.frame - 1];
  return r;
}

void printRow(std::ostream& o, const std::string& name, const tracking::MotSummary& s,
              const tracking::HotaSummary& h) {
  o << std::left << std::setw(28) << name << std::right << std::fixed << std::setprecision(3)
    << std::setw(7) << s.mota() << std::setw(7) << s.motpIou() << std::setw(7) << s.idf1()
    << std::setw(7) << s.idp() << std::setw(7) << s.idr() << std::setw(7) << s.recall()
    << std::setw(7) << s.precision() << std::setw(5) << s.unique_objects << std::setw(5)
    << s.mostly_tracked << std::setw(5) << s.partially_tracked << std::setw(5) << s.mostly_lost
    << std::setw(7) << s.counts.false_positives << std::setw(7) << s.counts.false_negatives
    << std::setw(6) << s.counts.id_switches << std::setw(6) << s.fragmentations << std::setw(7) << h.hota()
    << std::setw(7) << h.detA() << std::setw(7) << h.assA() << std::setw(7) << h.locA() << "\n";
}

std::string jsonObject(const tracking::MotSummary& s, const tracking::HotaSummary& h) {
  std::ostringstream o;
  o << std::setprecision(9) << "{\"mota\": " << s.mota() << ", \"motp\": " << s.motpIou()
    << ", \"motp_distance\": " << s.motpDistance() << ", \"idf1\": " << s.idf1() << ", \"idp\": " << s.idp()
    << ", \"idr\": " << s.idr() << ", \"recall\": " << s.recall() << ", \"precision\": " << s.precision()
    << ", \"num_unique_objects\": " << s.unique_objects << ", \"mostly_tracked\": " << s.mostly_tracked
    << ", \"partially_tracked\": " << s.partially_tracked << ", \"mostly_lost\": " << s.mostly_lost
    << ", \"num_false_positives\": " << s.counts.false_positives
    << ", \"num_misses\": " << s.counts.false_negatives << ", \"num_switches\": " << s.counts.id_switches
    << ", \"num_fragmentations\": " << s.fragmentations << ", \"num_objects\": " << s.counts.ground_truth
    << ", \"num_predictions\": " << s.predictions << ", \"num_matches\": " << s.counts.matches
    << ", \"num_frames\": " << s.counts.frames << ", \"hota\": " << h.hota() << ", \"deta\": " << h.detA()
    << ", \"assa\": " << h.assA() << ", \"deta_recall\": " << h.detRe() << ", \"deta_precision\": " << h.detPr()
    << ", \"assa_recall\": " << h.assRe() << ", \"assa_precision\": " << h.assPr() << ", \"loca\": " << h.locA()
    << "}";
  return o.str();
}

void runEvalMot(const EvalMotArgs& a) {
  if (a.gt.size() != a.est.size())
    throw CLI::ValidationError("--gt/--est", "give one --est per --gt (" + std::to_string(a.gt.size()) +
                                                 " --gt, " + std::to_string(a.est.size()) + " --est)");
  std::vector<tracking::MotSummary> rows;
  std::vector<tracking::HotaSummary> hota_rows;
  std::ostringstream switches;
  switches << "est,frame,gt_id,previous_hypothesis_id,hypothesis_id\n";
  for (size_t i = 0; i < a.gt.size(); ++i) {
    const PairResult r = evaluatePair(a.gt[i], a.est[i], a.iou_min, a.ignore_rule);
    rows.push_back(r.summary);
    hota_rows.push_back(r.hota);
    for (const tracking::IdSwitch& s : r.switches)
      switches << a.est[i] << "," << s.frame << "," << s.gt_id << "," << s.previous_hypothesis << "," << s.hypothesis
               << "\n";
  }
  if (!a.switches.empty()) data::writeTextFileAtomically(a.switches, switches.str());
  std::cout << "adugs eval-mot (IoU >= " << a.iou_min << ", MOTP = mean IoU of matches, confidence-0 ground truth: "
            << (a.ignore_rule == IgnoreRule::kMot15 ? "dropped, as TrackEval's MOT15" : "ignore regions") << ")\n"
            << std::left << std::setw(28) << "sequence" << std::right
            << "   MOTA   MOTP   IDF1    IDP    IDR   Rcll   Prcn   GT   MT   PT   ML     FP     FN  IDsw    FM   HOTA   DetA   AssA   LocA\n";
  for (size_t i = 0; i < rows.size(); ++i) {
    const std::filesystem::path est(a.est[i]);  // "TUD-Campus/test.txt": short, still telling
    printRow(std::cout, (est.parent_path().filename() / est.filename()).string(), rows[i], hota_rows[i]);
  }
  const tracking::MotSummary overall = tracking::combineMotSummaries(rows);
  const tracking::HotaSummary hota_overall = tracking::combineHotaSummaries(hota_rows);
  if (rows.size() > 1) printRow(std::cout, "OVERALL", overall, hota_overall);
  if (!a.json.empty()) {
    std::ostringstream j;
    j << "{\n  \"iou_min\": " << a.iou_min << ",\n  \"ignore_rule\": \"" << ignoreRuleName(a.ignore_rule)
      << "\",\n  \"sequences\": [\n";
    for (size_t i = 0; i < rows.size(); ++i)
      j << "    {\"gt\": \"" << a.gt[i] << "\", \"est\": \"" << a.est[i] << "\", \"metrics\": " << jsonObject(rows[i], hota_rows[i])
        << "}" << (i + 1 < rows.size() ? "," : "") << "\n";
    j << "  ],\n  \"overall\": " << jsonObject(overall, hota_overall) << "\n}\n";
    data::writeTextFileAtomically(a.json, j.str());
  }
}

}  // namespace

void registerEvalMotCommand(CLI::App& root) {
  auto args = std::make_shared<EvalMotArgs>();
  CLI::App* cmd = root.add_subcommand(
      "eval-mot", "MOT metrics (MOTA, MOTP, IDF1, IDP, IDR, MT/PT/ML, FP, FN, IDsw, FM, HOTA, DetA, AssA, LocA) of tracks against ground truth");
  cmd->add_option("--gt", args->gt, "MOTChallenge ground truth (repeat for several sequences)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--est", args->est, "tracker output in MOTChallenge format, one per --gt")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--iou", args->iou_min, "minimum IoU of a match")
      ->check(CLI::Range(0.01, 1.0))
      ->capture_default_str();
  cmd->add_option("--ignore-rule", args->ignore_rule,
                  "ground-truth rows with confidence 0: zero-confidence = ignore regions (a hypothesis on one is "
                  "not scored); mot15 = TrackEval's MOT15 setting (the rows are dropped, hypotheses on them are "
                  "false positives)")
      ->transform(CLI::CheckedTransformer(kIgnoreRules))
      ->default_str("zero-confidence");
  cmd->add_option("--json", args->json, "write the metrics as JSON (lower-case keys)");
  cmd->add_option("--switches", args->switches,
                  "write every identity switch as CSV (est, frame, gt id, previous and new hypothesis id)");
  cmd->callback([args] { runEvalMot(*args); });
}

}  // namespace adugs::app

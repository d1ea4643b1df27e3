// `adugs track`: the enhanced SORT tracker, fed either
//   --detections det.txt                       a MOTChallenge detection file (the public
//                                              detections trackers are benchmarked with), or
//   INPUT --detector-model M [--detector-config C]   a detector run on every frame of INPUT: a
//                                              video, a folder of images (name order) or a
//                                              sequence (its mav0/cam0/data); --detect-every n:
//                                              every n-th frame, SORT's predictions in between;
//                                              --write-detections keeps its boxes as DIR/det.txt;
//   --detections det.txt INPUT                 the file's detections, INPUT's images for the
//                                              appearance cue, masks and overlay;
// writes DIR/tracks.txt in MOTChallenge format for `adugs eval-mot` (frames numbered from 1);
// with --segmenter the dynamic stage's masks (DynamicMasker: its own SORT with the mask's rules,
// boxes segmented and refined), written as DIR/masks/NNNNNN.png with --masks; with --overlay a
// video of the tracked boxes, their ids and the tinted mask. --motion-cue adds the class-free
// motion cue's boxes (tracking/detect/motion_cue.h: points moving against the static scene,
// for a video without an IMU: no rotation given, a translation fitted) to the detections, for the
// tracker and the masks, and leaves the objects it judges static unmasked
// (tracking/object_motion.h), as `adugs run --mask detector --motion-cue` does; with it an INPUT
// needs no detector model (any moving object, of no class: tracks.txt then holds them).
//
// Track output rule (MOT files): a track is written in a frame when a detection was fused into it
// in that frame and it has min_hits detections (or the sequence is younger than min_hits frames),
// as the original SORT does; tracks that miss their detection are kept max_age frames to be found
// again under the same id, but not written: --write-coasting also writes their predicted boxes
// (what the dynamic mask uses, but false positives for MOT scoring). The original SORT:
// --max-age 1 --min-hits 3 --beta-pos 16 --beta-size 16 --high-score 0 --keep-unconfirmed.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <opencv2/imgproc.hpp>
#include <string>

#include "app/commands.h"
#include "app/live_sources.h"
#include "app/pipeline/overlay_video.h"
#include "app/run_config.h"
#include "data/formats/image_file.h"
#include "data/formats/mot_io.h"
#include "data/input_error.h"
#include "data/sources/image_source.h"
#include "tracking/detect/detector_factory.h"
#include "tracking/detect/motion_cue.h"
#include "tracking/dynamic_masker.h"
#include "tracking/dynamic_masker_options.h"
#include "tracking/object_motion.h"
#include "tracking/segment/segmenter_factory.h"
#include "tracking/sort/appearance.h"
#include "tracking/sort/sort_tracker.h"

namespace adugs::app {
namespace {
namespace fs = std::filesystem;

struct TrackArgs {
  std::string detections, out_dir = "out/track";
  std::string video, detector_model, detector_config, overlay;
  std::string segmenter, sam_encoder, sam_decoder;  // non-empty segmenter: compute the masks
  bool write_masks = false;
  double min_score = -1e9;
  bool write_coasting = false;
  bool write_detections = false;
  std::vector<int> classes;  // detector class ids kept (empty: every dynamic class the detector keeps)  // DIR/det.txt: the detector's boxes with scores, MOTChallenge det format
  int detect_every = 1;
  std::string config_path;  // run config whose dynamic: map sets the masker's options
  bool fixed_noise = false;
  bool motion_cue = false;
  std::vector<std::string> calibration;  // the motion cue's camera (else a guessed pinhole)
  tracking::SortOptions sort;
};

// One frame's worth of detections; false at the end of the input. The detections come from a
// detection file or a detector run on INPUT's images; with both a file and an INPUT, the images
// serve the appearance cue, the masks and the overlay (frame k of the file = the k-th image).
class DetectionFeed {
 public:
  explicit DetectionFeed(const TrackArgs& a) : a_(a) {
    if (a.detections.empty() && a.video.empty())
      throw CLI::ValidationError("input", "give --detections det.txt, or an INPUT (video, image folder, sequence) with --detector-model, or both");
    if (!a.detections.empty()) {
      if (!a.detector_model.empty())
        throw CLI::ValidationError("--detector-model", "the detections come from --detections; give one of the two");
      if (!a.classes.empty())
        throw CLI::ValidationError("--classes", "a detection file has no classes; --classes filters a detector's output");
      if (a.sort.appearance_weight > 0 && a.video.empty())
        throw CLI::ValidationError("--appearance", "the appearance cue needs the images: give the INPUT the detections belong to");
      file_ = data::readMotFile(a.detections);
      if (file_.empty()) throw data::InputError(a.detections, 0, "", "no detections in the file");
      last_frame_ = file_.rbegin()->first;
    } else {
      if (a.detector_model.empty() && !a.motion_cue)
        throw CLI::ValidationError("--detector-model", "an INPUT needs a detector model, --motion-cue, or --detections");
      if (!a.detector_model.empty()) detector_ = tracking::makeDetector(a.detector_model, a.detector_config);
    }
    if (a.video.empty()) return;
    // A sequence's camera images, an ASL camera folder, a folder of images (name order) or a video.
    const fs::path cam = fs::path(a.video) / "mav0" / "cam0";
    images_ = std::make_unique<data::ImageSource>(fs::is_directory(cam) ? cam.string() : a.video);
  }

  // detect: whether this frame's detections are wanted (--detect-every skips the others).
  bool next(int frame, bool detect, std::vector<tracking::Detection>* dets, cv::Mat* image) {
    dets->clear();
    if (images_) {
      data::ImageFrame f;
      if (!images_->next(f)) return false;
      *image = f.image;
    } else if (frame > last_frame_) {
      return false;
    }
    if (!detect) return true;
    if (detector_) {
      *dets = detector_->detect(*image);
      if (!a_.classes.empty())
        dets->erase(std::remove_if(dets->begin(), dets->end(),
                                   [&](const tracking::Detection& d) {
                                     return std::find(a_.classes.begin(), a_.classes.end(), d.class_id) == a_.classes.end();
                                   }),
                    dets->end());
    } else if (const auto it = file_.find(frame); it != file_.end()) {
      for (const data::MotBox& b : it->second)
        if (b.confidence >= a_.min_score)
          dets->push_back(
              {tracking::Box::fromCorners(b.left, b.top, b.left + b.width, b.top + b.height), 0, b.confidence});
    }
    if (a_.sort.appearance_weight > 0)
      for (tracking::Detection& d : *dets) d.appearance = tracking::boxHistogram(*image, d.box);
    return true;
  }

 private:
  const TrackArgs& a_;
  std::map<int, std::vector<data::MotBox>> file_;
  int last_frame_ = 0;
  std::unique_ptr<tracking::Detector> detector_;
  std::unique_ptr<data::ImageSource> images_;  // INPUT
};

void runTrack(const TrackArgs& a) {
  if (a.motion_cue && a.video.empty())
    throw CLI::ValidationError("--motion-cue", "the motion cue needs the images: give an INPUT");
  if (!a.calibration.empty() && !a.motion_cue)
    throw CLI::ValidationError("--calibration", "is the motion cue's camera: give it with --motion-cue");
  DetectionFeed feed(a);
  tracking::SortOptions options = a.sort;
  if (options.high_score < 0) options.high_score = a.detections.empty() ? 0.6 : 0.8;
  if (a.fixed_noise) options.filter.lambda = 1e6;  // erf saturates at once: R = beta, a fixed R
  tracking::SortTracker tracker(options);
  fs::create_directories(a.out_dir);
  const std::string path = (fs::path(a.out_dir) / "tracks.txt").string();
  std::ofstream out(path);
  if (!out) throw data::InputError(path, 0, "", "cannot write");
  out << std::fixed << std::setprecision(2);
  // The detections as a MOTChallenge det.txt, so the tracker can be re-run on them (--detections)
  // without the detector, as the MOT benchmarks' public detections are.
  std::ofstream det_out;
  const std::string det_path = (fs::path(a.out_dir) / "det.txt").string();
  if (a.write_detections) {
    if (a.detector_model.empty()) throw CLI::ValidationError("--write-detections", "needs an INPUT and --detector-model");
    det_out.open(det_path);
    if (!det_out) throw data::InputError(det_path, 0, "", "cannot write");
    det_out << std::fixed << std::setprecision(2);
  }
  std::unique_ptr<OverlayVideo> overlay;
  if (!a.overlay.empty()) overlay = std::make_unique<OverlayVideo>(a.overlay, 10.0);
  // The run config's dynamic: map (the masker's and the motion cue's options), read once.
  tracking::DynamicMaskerOptions m = loadRunConfig(a.config_path).dynamic;
  m.detect_every = a.detect_every;
  // The masks: the dynamic stage with its own SORT (the mask's rules: coasting boxes kept).
  std::unique_ptr<tracking::DynamicMasker> masker;
  if (!a.segmenter.empty()) {
    if (a.video.empty()) throw CLI::ValidationError("--segmenter", "masks need the images: give an INPUT, not --detections");
    masker = std::make_unique<tracking::DynamicMasker>(m, tracking::makeBoxSegmenter(a.segmenter, a.sam_encoder, a.sam_decoder, m.grabcut));
    if (a.write_masks) fs::create_directories(fs::path(a.out_dir) / "masks");
  } else if (a.write_masks) {
    throw CLI::ValidationError("--masks", "needs --segmenter grabcut|box|mobilesam");
  }
  // The motion cue and the object states, made at the first image (its size).
  std::unique_ptr<tracking::MotionCue> cue;
  std::optional<tracking::ObjectMotionClassifier> object_motion;
  size_t rows = 0;
  int frame = 1;
  std::vector<tracking::Detection> dets;
  cv::Mat image;
  int frames_since_detection = a.detect_every;
  // MOT frames count from 1, the detection rule's frame index from 0.
  for (bool detect = true; feed.next(frame, detect, &dets, &image); ++frame) {
    // Frames the detector skips get the tracks predicted to them; a track counts as found there
    // when it was found at the last detection.
    const bool detect_this = detect;
    if (det_out.is_open()) {
      for (const tracking::Detection& d : dets)
        det_out << frame << ",-1," << d.box.left() + 1 << "," << d.box.top() + 1 << "," << d.box.w << "," << d.box.h
                << "," << std::setprecision(4) << d.score << std::setprecision(2) << ",-1,-1,-1\n";
      det_out.flush();
    }
    if (a.motion_cue && !image.empty()) {
      if (!cue) {
        std::string from;
        const data::CameraModel camera(visionOnlyCamera(image.cols, image.rows, 0, a.calibration, &from));
        std::cerr << "track: motion cue camera " << from << "\n";
        cue = std::make_unique<tracking::MotionCue>(camera, m.motion_cue);
        object_motion.emplace(m.object_motion, camera);
      }
      const std::vector<tracking::Detection> moving = cue->detect(image, Eigen::Matrix3d::Identity());
      if (detect) dets.insert(dets.end(), moving.begin(), moving.end());
    }
    const std::vector<tracking::TrackedObject> tracks =
        detect ? tracker.update(dets, frames_since_detection) : tracker.predict(frames_since_detection);
    frames_since_detection = detect ? 1 : frames_since_detection + 1;
    detect = tracking::isDetectionFrame(frame, a.detect_every);
    for (const tracking::TrackedObject& t : tracks) {
      if (t.frames_missed > 0 && !a.write_coasting) continue;
      // MOTChallenge: 1-based top-left pixel coordinates.
      out << frame << "," << t.id << "," << t.box.left() + 1 << "," << t.box.top() + 1 << "," << t.box.w << ","
          << t.box.h << ",1,-1,-1,-1\n";
      ++rows;
    }
    out.flush();  // a killed run keeps the frames already tracked
    cv::Mat mask;
    if (masker) {
      if (object_motion) masker->setStaticObjects(object_motion->staticIds());  // judged up to the previous frame
      const std::vector<tracking::PointPrompt> points = cue ? tracking::cuePointPrompts(cue->points())
                                                            : std::vector<tracking::PointPrompt>{};
      const tracking::DynamicMaskResult r = detect_this ? masker->process(image, dets, points) : masker->carry(image);
      if (object_motion) object_motion->update(r.objects, cue->points(), cue->translating());
      mask = r.mask;
      if (a.write_masks) {
        char name[32];
        std::snprintf(name, sizeof name, "%06d.png", frame);
        const std::string mask_path = (fs::path(a.out_dir) / "masks" / name).string();
        data::writeImageFile(mask_path, mask);
      }
    }
    if (overlay && !image.empty()) {
      OverlayContent c;
      c.mask = mask;
      c.objects = tracks;
      c.status = "frame " + std::to_string(frame) + ", " + std::to_string(tracks.size()) + " tracks";
      overlay->write(drawOverlay(image, c));
    }
    if (!a.video.empty() && frame % 100 == 0) std::cerr << "track: " << frame << " frames\n" << std::flush;
  }
  out.close();
  if (!out) throw data::InputError(path, 0, "", "write failed");
  std::cout << "adugs track: " << frame - 1 << " frames, " << rows << " track boxes -> " << path << "\n";
}

}  // namespace

void registerTrackCommand(CLI::App& root) {
  auto args = std::make_shared<TrackArgs>();
  // The MOT output's defaults (doc/results.md "Enhanced SORT on real detections": chosen on
  // TUD-Campus and TUD-Stadtmitte only, then measured on the other MOT15 sequences): tracks kept 20
  // frames for re-identification but written only when detected, R up to 256 px^2, ByteTrack's
  // two stages, tentative tracks dropped at their first miss. The masker's SORT (`adugs run`,
  // dynamic: map) keeps its own options.
  args->sort.max_age = 20;
  args->sort.min_hits = 3;
  args->sort.filter.beta_pos = 256;
  args->sort.filter.beta_size = 256;
  args->sort.high_score = -1;  // set by the input in runTrack
  args->sort.drop_unconfirmed_on_miss = true;
  CLI::App* cmd = root.add_subcommand(
      "track", "Run the enhanced SORT tracker on MOTChallenge detections or on a detector's output for a video");
  cmd->add_option("input", args->video,
                  "video, folder of images or sequence: the detector's input, or with --detections the images the detections belong to")
      ->check(CLI::ExistingPath);
  cmd->add_option("--detections", args->detections, "MOTChallenge det.txt (frame,-1,left,top,w,h,score,...)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--detector-model", args->detector_model, "INPUT: ultralytics .torchscript, ultralytics/YOLOX .onnx or darknet .weights")
      ->check(CLI::ExistingFile);
  cmd->add_option("--detector-config", args->detector_config, "INPUT: darknet .cfg (default: beside the .weights)")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--motion-cue", args->motion_cue,
                "also box what moves against the static scene, of any class (class-free; no detector model needed)");
  cmd->add_option("--calibration", args->calibration,
                  "INPUT: --motion-cue's camera, cam0 of Kalibr/OpenVINS/VINS-Fusion/Basalt/EuRoC files (default: a guessed pinhole)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--overlay", args->overlay, "write the tracked boxes, ids and mask over the frames (.avi or .mp4)");
  cmd->add_option("--segmenter", args->segmenter, "INPUT: also compute the dynamic masks with this box segmenter")
      ->check(CLI::IsMember({"grabcut", "box", "mobilesam"}));
  cmd->add_option("--sam-encoder", args->sam_encoder, "--segmenter mobilesam: mobilesam_encoder.pt");
  cmd->add_option("--sam-decoder", args->sam_decoder, "--segmenter mobilesam: mobilesam_decoder.pt");
  cmd->add_flag("--masks", args->write_masks, "--segmenter: write each frame's mask to DIR/masks/NNNNNN.png");
  cmd->add_option("--config", args->config_path,
                  "--segmenter: run config (data/config/*.yaml) whose dynamic: map sets the masker's SORT, "
                  "segmentation and refinement, as in adugs run (default: the defaults in code)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", args->out_dir, "output folder (tracks.txt)")->capture_default_str();
  cmd->add_option("--min-score", args->min_score, "ignore detections scoring below this");
  cmd->add_option("--max-age", args->sort.max_age, "frames a track survives without a detection")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  cmd->add_option("--min-hits", args->sort.min_hits, "detections before a track is written")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  cmd->add_option("--iou-min", args->sort.iou_min, "smallest IoU of an association")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--detect-every", args->detect_every,
                  "use the detections of every n-th frame only; SORT's predictions fill the others")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--classes", args->classes,
                  "INPUT: keep only detections of these class ids (COCO ids for darknet / YOLOX, e.g. 0 = person for pedestrian benchmarks; the model's ids for ultralytics)")
      ->check(CLI::Range(0, 10000));
  cmd->add_flag("--write-detections", args->write_detections,
                "INPUT: also write the detector's boxes with their scores to DIR/det.txt (MOTChallenge det format, for --detections)");
  cmd->add_flag("--write-coasting", args->write_coasting,
                "also write predicted boxes of tracks without a detection in the frame");
  cmd->add_option("--appearance", args->sort.appearance_weight,
                  "needs INPUT: weight of the colour-histogram appearance cue in the association cost (0 = off)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmd->add_flag("--recovery", args->sort.observation_centric_recovery,
                "OC-SORT's observation-centric re-update when a coasting track is found again");
  cmd->add_option("--high-score", args->sort.high_score,
                  "ByteTrack: detections scoring below this start no track and only extend tracks found in the previous frame "
                  "(0 = off; default 0.8 with --detections, tuned on TUD's public detections, 0.6 with a detector, ByteTrack's birth threshold for YOLOX)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--low-iou-min", args->sort.low_iou_min, "ByteTrack: smallest IoU of a low-score association")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_flag("--last-box", args->sort.last_box_association,
                "OC-SORT's recovery: tracks left unmatched are matched by their last detected box");
  cmd->add_option("--direction", args->sort.direction_weight,
                  "OC-SORT's momentum: weight of the direction-consistency term in the association cost (0 = off)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmd->add_option("--direction-frames", args->sort.direction_frames, "OC-SORT's momentum: detections spanned by a direction")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  cmd->add_flag("--drop-unconfirmed,!--keep-unconfirmed", args->sort.drop_unconfirmed_on_miss,
                "delete a track that misses a frame before it has --min-hits detections (default; --keep-unconfirmed: let it coast)");
  tracking::AdaptiveNoiseOptions& r = args->sort.filter;
  cmd->add_option("--lambda", r.lambda, "adaptive R: R = beta * erf(lambda * innovation RMSE) [1/px]")
      ->check(CLI::Range(1e-6, 1e6))
      ->capture_default_str();
  cmd->add_option("--beta-pos", r.beta_pos, "adaptive R: largest R on cx, cy [px^2]")
      ->check(CLI::Range(1e-6, 1e6))
      ->capture_default_str();
  cmd->add_option("--beta-size", r.beta_size, "adaptive R: largest R on w, h [px^2]")
      ->check(CLI::Range(1e-6, 1e6))
      ->capture_default_str();
  cmd->add_option("--window", r.window, "adaptive R: innovations kept (N)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();

  cmd->add_flag("--fixed-noise", args->fixed_noise,
                "fixed measurement noise R = beta instead of the adaptive erf-shaped R (ablation)");
  cmd->callback([args] { runTrack(*args); });
}

}  // namespace adugs::app

// `adugs calib ...`: AprilGrid targets, detection, intrinsics, camera-IMU, IMU noise.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>


#include "app/commands.h"
#include "calib/calibration_verdict.h"
#include "calib/camera_imu/camera_imu_calibrator.h"
#include "calib/camera_imu/camera_imu_input.h"
#include "calib/camera_imu/camera_imu_report.h"
#include "calib/camera_imu/camera_imu_verdict.h"
#include "calib/imu_noise/allan_variance.h"
#include "calib/imu_noise/imu_noise_verdict.h"
#include "calib/intrinsics/intrinsics_calibrator.h"
#include "calib/intrinsics/intrinsics_report.h"
#include "calib/intrinsics/intrinsics_verdict.h"
#include "calib/intrinsics/visp_camera_xml.h"
#include "calib/kalibr_yaml.h"
#include "calib/lens_refit.h"
#include "calib/target/aprilgrid_detector.h"
#include "calib/target/aprilgrid_render.h"
#include "calib/target/aprilgrid_target_yaml.h"
#include "calib/target/chessboard.h"
#include "calib/target/corner_csv.h"
#include "calib/text_format.h"
#include "data/camera_model.h"
#include "data/formats/atomic_file.h"
#include "data/formats/euroc_sensor_yaml.h"
#include "data/formats/image_file.h"
#include "data/formats/yaml_options.h"
#include "data/input_error.h"
#include "data/sources/image_source.h"

namespace adugs::app {
namespace {
namespace fs = std::filesystem;
using calib::strprintf;

constexpr const char* kCli = "command line";

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void makeDir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw data::InputError(dir, 0, "--out", "cannot create folder");
}

// A failed verdict: nothing is written; main() prints the reason and exits with code 3. A file
// of an earlier run at would_write is pointed out, so nobody takes it for this run's result.
[[noreturn]] void failCalibration(const calib::CalibrationVerdict& verdict,
                                  const std::string& would_write) {
  std::string message = calib::failureReasons(verdict) + " (nothing was written";
  if (fs::exists(would_write)) message += "; " + would_write + " is from an earlier run";
  throw calib::CalibrationFailed(message + ")");
}

// ---------------------------------------------------------------- target
struct TargetArgs {
  std::string yaml;
  int rows = 0, cols = 0;
  double size = 0, spacing = -1;
  int border_bits = 0;
  std::string out = "aprilgrid";
  double dpi = 300;
  double margin_m = 0.02;
};

void runTarget(const TargetArgs& a) {
  calib::AprilGrid grid;
  const bool flags = a.rows > 0 || a.cols > 0 || a.size > 0 || a.spacing >= 0;
  if (!a.yaml.empty()) {
    if (flags) throw data::InputError(kCli, 0, "--target", "give a target YAML or the --tag-* flags, not both");
    grid = calib::readAprilGridYaml(a.yaml);
  } else {
    if (a.rows <= 0 || a.cols <= 0 || a.size <= 0 || a.spacing < 0)
      throw data::InputError(kCli, 0, "--target",
                             "give --target YAML, or all of --tag-rows --tag-cols --tag-size "
                             "--tag-spacing");
    grid.tag_rows = a.rows;
    grid.tag_cols = a.cols;
    grid.tag_size_m = a.size;
    grid.tag_spacing = a.spacing;
  }
  if (a.border_bits) grid.border_bits = a.border_bits;
  try {
    grid.validate();
  } catch (const std::invalid_argument& e) {
    throw data::InputError(a.yaml.empty() ? kCli : a.yaml, 0, "", e.what());
  }
  if (!(a.dpi >= 10 && a.dpi <= 2400)) throw data::InputError(kCli, 0, "--dpi", "must be 10..2400");
  if (!(a.margin_m >= 0 && a.margin_m <= 1)) throw data::InputError(kCli, 0, "--margin", "must be 0..1 m");
  const fs::path parent = fs::path(a.out).parent_path();
  if (!parent.empty()) makeDir(parent.string());
  const calib::TargetLayout layout = calib::aprilGridLayout(grid, a.margin_m);
  const calib::RenderedTarget png = calib::renderAprilGrid(grid, a.dpi, a.margin_m);
  data::writeImageFile(a.out + ".png", png.image);
  data::writeTextFileAtomically(a.out + ".pdf", calib::aprilGridPdf(layout));
  data::writeTextFileAtomically(a.out + ".yaml", calib::formatAprilGridYaml(grid));
  std::cout << strprintf(
      "AprilGrid %dx%d tag36h11, tag %.4g m, spacing %.4g, border %d bits\n"
      "  page %.1f x %.1f mm\n  %s.pdf (vector, print at 100%% / no scaling)\n"
      "  %s.png (%dx%d px at %.0f dpi)\n  %s.yaml (Kalibr target file)\n",
      grid.tag_rows, grid.tag_cols, grid.tag_size_m, grid.tag_spacing, grid.border_bits,
      (layout.max_x - layout.min_x) * 1000, (layout.max_y - layout.min_y) * 1000, a.out.c_str(),
      a.out.c_str(), png.image.cols, png.image.rows, a.dpi, a.out.c_str());
}

// ------------------------------------------------------------- detection
struct DetectArgs {
  std::string target;
  std::string images;
  std::string out;
  std::string options;
  int every = 1;
  int threads = 2;
};

struct LoadedOptions {
  calib::IntrinsicsOptions intrinsics;
  calib::IntrinsicsVerdictOptions verdict;
  calib::DetectorOptions detector;
};

LoadedOptions loadOptions(const std::string& path, bool with_intrinsics) {
  LoadedOptions o;
  if (path.empty()) return o;
  auto r = data::YamlOptionsReader::fromFile(path);
  if (with_intrinsics) {
    calib::readIntrinsicsOptions(r, o.intrinsics);
    auto v = r.child("verdict");
    calib::readIntrinsicsVerdictOptions(v, o.verdict);
    v.finish();
  }
  auto d = r.child("detector");
  d.optional("quad_decimate", o.detector.quad_decimate, 1.0f, 8.0f);
  d.optional("threads", o.detector.threads, 1, 256);
  d.optional("subpix", o.detector.subpix);
  d.optional("max_subpix_shift_px", o.detector.max_subpix_shift_px, 0.0, 100.0);
  d.optional("consistency_tol", o.detector.consistency_tol, 0.001, 10.0);
  d.optional("dilated_pass", o.detector.dilated_pass);
  d.finish();
  r.finish();
  return o;
}

struct Detected {
  std::vector<calib::TargetObservation> views;
  int width = 0, height = 0;
  int images = 0;
  double seconds = 0;
};

// chessboard: when non-null, detect this chessboard instead of the AprilGrid.
Detected detectAll(const calib::AprilGrid& grid, const std::string& images, int every,
                   const calib::DetectorOptions& options, bool verbose,
                   const calib::Chessboard* chessboard = nullptr) {
  data::ImageSource source(images, every);
  std::unique_ptr<calib::AprilGridDetector> detector;
  if (!chessboard) detector = std::make_unique<calib::AprilGridDetector>(grid, options);
  Detected d;
  const auto t0 = std::chrono::steady_clock::now();
  data::ImageFrame frame;
  while (source.next(frame)) {
    if (d.images == 0) {
      d.width = frame.gray.cols;
      d.height = frame.gray.rows;
    } else if (frame.gray.cols != d.width || frame.gray.rows != d.height) {
      throw data::InputError(frame.name, 0, "",
                             strprintf("image is %dx%d but the first one was %dx%d",
                                       frame.gray.cols, frame.gray.rows, d.width, d.height));
    }
    calib::DetectionStats stats;
    calib::TargetObservation obs =
        chessboard ? calib::detectChessboard(*chessboard, frame.gray, frame.t_ns)
                   : detector->detect(frame.gray, frame.t_ns, &stats);
    if (chessboard) stats.kept_tags = static_cast<int>(obs.corners.size());
    obs.source = frame.name;
    ++d.images;
    if (verbose)
      std::cerr << strprintf("\r  detecting: image %d/%zu, %d %s        ", d.images,
                             source.sizeHint(), stats.kept_tags,
                             chessboard ? "corners" : "tags");
    d.views.push_back(std::move(obs));
  }
  if (verbose) std::cerr << "\n";
  d.seconds = secondsSince(t0);
  return d;
}

void saveCorners(const std::string& dir, const calib::AprilGrid& grid, const Detected& d) {
  makeDir(dir);
  for (const auto& v : d.views)
    if (!v.corners.empty())
      calib::writeCornerCsv((fs::path(dir) / (std::to_string(v.t_ns) + ".csv")).string(), grid, v);
}

void runDetect(const DetectArgs& a) {
  const calib::AprilGrid grid = calib::readAprilGridYaml(a.target);
  LoadedOptions o = loadOptions(a.options, false);
  o.detector.threads = a.threads;
  const Detected d = detectAll(grid, a.images, a.every, o.detector, true);
  saveCorners(a.out, grid, d);
  size_t with = 0, corners = 0;
  for (const auto& v : d.views) {
    with += !v.corners.empty();
    corners += v.corners.size();
  }
  std::cout << strprintf("%d images (%dx%d) in %.2f s: %zu with the target, %zu corners -> %s\n",
                         d.images, d.width, d.height, d.seconds, with, corners, a.out.c_str());
}

// ------------------------------------------------------------ intrinsics
// --model: the lens models calib/lens_refit names, with Kalibr's spellings (pinhole-radtan,
// pinhole-equi, omni-radtan) and the distortion names data::parseDistortionModel knows as
// aliases; a pinhole without distortion has nothing to calibrate.
calib::LensModel parseIntrinsicsModel(const std::string& name) {
  std::string m = name;
  if (m.rfind("pinhole-", 0) == 0) m = m.substr(8);
  if (m == "omni-radtan") m = "omni";
  calib::LensModel lens;
  // The distortion names (radtan, equidistant and their spellings: equi, fisheye, ...) are pinhole.
  data::DistortionModel distortion;
  if (data::parseDistortionModel(m, distortion) && distortion != data::DistortionModel::kNone)
    return {data::ProjectionModel::kPinhole, distortion};
  if (m == "pinhole" || !calib::parseLensModel(m, lens))
    throw data::InputError(kCli, 0, "--model",
                           "unknown camera model '" + name +
                               "' (use radtan (default), equidistant, omni, omni-none, ds or eucm; "
                               "Kalibr's pinhole-radtan, pinhole-equi and omni-radtan are accepted)");
  return lens;
}

struct IntrinsicsArgs {
  std::string target;
  std::string images;
  std::string corners;
  std::string model;
  std::string resolution;
  std::string options;
  std::string reference;
  std::string out = "calib_out";
  int every = 1;
  int threads = 2;
  bool save_corners = false;
};

void runIntrinsics(const IntrinsicsArgs& a) {
  if (a.images.empty() == a.corners.empty())
    throw data::InputError(kCli, 0, "--images", "give exactly one of --images and --corners");
  LoadedOptions o = loadOptions(a.options, true);
  // Every input file is read before the detection and the solve: a typo is an error at once.
  data::CameraCalibration ref;
  if (!a.reference.empty()) ref = data::readEurocCameraYaml(a.reference);
  o.intrinsics.threads = a.threads;
  o.detector.threads = a.threads;
  if (!a.model.empty()) {
    const calib::LensModel lens = parseIntrinsicsModel(a.model);
    o.intrinsics.projection = lens.projection;
    o.intrinsics.model = lens.distortion;
  }
  calib::AprilGrid grid;
  Detected d;
  calib::ReportContext ctx;
  calib::Chessboard chessboard;
  const bool is_chessboard = a.target.rfind("chessboard", 0) == 0;
  if (is_chessboard && !calib::parseChessboardSpec(a.target, chessboard))
    throw data::InputError(kCli, 0, "--target",
                           "expected chessboard:COLSxROWS:SQUARE_M (inner corners), e.g. "
                           "chessboard:9x6:0.025");
  if (is_chessboard && a.images.empty())
    throw data::InputError(kCli, 0, "--target", "a chessboard needs --images");
  if (!a.images.empty()) {
    if (a.target.empty()) throw data::InputError(kCli, 0, "--target", "needed with --images");
    if (!is_chessboard) grid = calib::readAprilGridYaml(a.target);
    d = detectAll(grid, a.images, a.every, o.detector, true, is_chessboard ? &chessboard : nullptr);
    ctx.input = a.images;
    ctx.detect_seconds = d.seconds;
    ctx.images = d.images;
  } else {
    calib::AprilGrid from_yaml;
    const calib::AprilGrid* want = nullptr;
    if (!a.target.empty()) {
      from_yaml = calib::readAprilGridYaml(a.target);
      want = &from_yaml;
    }
    d.views = calib::readCornerCsvs(a.corners, want, &grid);
    ctx.input = a.corners;
  }
  if (!a.resolution.empty()) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(a.resolution.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || x != 'x' ||
        w <= 0 || h <= 0)
      throw data::InputError(kCli, 0, "--resolution", "expected WIDTHxHEIGHT, e.g. 752x480");
    if (d.width > 0 && (w != d.width || h != d.height))
      throw data::InputError(kCli, 0, "--resolution", "does not match the images' size");
    d.width = w;
    d.height = h;
  }
  if (d.width <= 0)
    throw data::InputError(kCli, 0, "--resolution",
                           "corner CSVs do not say the image size: give --resolution WxH");
  ctx.target = is_chessboard
                   ? strprintf("chessboard %dx%d inner corners, square %g m", chessboard.cols,
                               chessboard.rows, chessboard.square_m)
                   : strprintf("AprilGrid %dx%d, tag %g m, spacing %g", grid.tag_rows,
                               grid.tag_cols, grid.tag_size_m, grid.tag_spacing);

  o.intrinsics.progress = [](const std::string& what) {
    std::cerr << "\r  calibrating: " << what << std::string(20, ' ') << std::flush;
  };
  const calib::IntrinsicsResult r =
      calib::calibrateIntrinsics(d.views, d.width, d.height, o.intrinsics);
  std::cerr << "\r" << std::string(100, ' ') << "\r" << std::flush;
  if (!a.reference.empty()) {
    ctx.has_reference = true;
    ctx.reference_name = a.reference;
    ctx.reference = calib::fromCalibration(ref);
    ctx.reference_rms_px = calib::reprojectionRmsWithFixedIntrinsics(
        d.views, ctx.reference, o.intrinsics.min_corners_per_view);
    ctx.our_rms_all_px = calib::reprojectionRmsWithFixedIntrinsics(
        d.views, r.camera, o.intrinsics.min_corners_per_view);
  }

  const calib::IntrinsicsJudgement judgement = calib::judgeIntrinsics(r, o.intrinsics, o.verdict);
  const std::string report = calib::formatIntrinsicsReport(r, judgement, ctx);
  // The head of the report (summary, verdict, intrinsics, coverage, comparison) on stdout.
  const std::string head = report.substr(0, report.find("Per view"));
  const fs::path out(a.out);
  if (judgement.verdict.verdict == calib::Verdict::kFailed) {
    std::cout << head;
    failCalibration(judgement.verdict, (out / "camchain.yaml").string());
  }

  makeDir(a.out);
  const std::string comment = calib::verdictYamlComment(judgement.verdict);
  data::writeTextFileAtomically((out / "camchain.yaml").string(),
                                comment + calib::formatCamchainYaml(r.camera));
  // ViSP 3.5 has no unified, double-sphere or EUCM camera: camera.xml for pinhole cameras only.
  const bool xml = r.camera.projection == data::ProjectionModel::kPinhole;
  if (xml) calib::writeVispCameraXml((out / "camera.xml").string(), r.camera, "Camera", comment);
  data::writeTextFileAtomically((out / "report.txt").string(), report);
  data::writeImageFile((out / "residuals.png").string(), calib::renderResidualPlot(r));
  data::writeImageFile((out / "coverage.png").string(), calib::renderCoveragePlot(r, judgement));
  data::writeTextFileAtomically((out / "residuals.csv").string(), calib::formatResidualCsv(r));
  if (a.save_corners && !a.images.empty() && !is_chessboard) saveCorners((out / "corners").string(), grid, d);

  std::cout << head;
  std::cout << "Wrote " << (out / "camchain.yaml").string() << (xml ? ", camera.xml" : "")
            << ", report.txt, residuals.png, coverage.png, residuals.csv"
            << (xml ? "" : " (no camera.xml: ViSP has no " + r.camera.modelName() + " camera)") << "\n";
  if (judgement.verdict.verdict == calib::Verdict::kWeak)
    std::cout << "WARNING: verdict WEAK (see above): record again before relying on this calibration\n";
}

// ------------------------------------------------------------------- imu
struct ImuArgs {
  std::string imu;
  std::string options;
  std::string out = "imu_out";
  double rate_hz = 0;
  int points = 60;
};

void runImu(const ImuArgs& a) {
  calib::ImuNoiseVerdictOptions vo;
  if (!a.options.empty()) {
    auto reader = data::YamlOptionsReader::fromFile(a.options);
    auto v = reader.child("verdict");
    calib::readImuNoiseVerdictOptions(v, vo);
    v.finish();
    reader.finish();
  }
  const calib::ImuRecording rec = calib::readImuCsv(a.imu);
  calib::AllanOptions o;
  o.points = a.points;
  const auto t0 = std::chrono::steady_clock::now();
  const calib::ImuNoiseResult r = calib::estimateImuNoise(rec, o);
  const double seconds = secondsSince(t0);
  const calib::CalibrationVerdict verdict = calib::judgeImuNoise(r, vo);
  const std::string report =
      calib::formatImuNoiseReport(r, a.imu, seconds, calib::formatVerdict(verdict, "imu.yaml"));
  const fs::path out(a.out);
  if (verdict.verdict == calib::Verdict::kFailed) {
    std::cout << report;
    failCalibration(verdict, (out / "imu.yaml").string());
  }
  makeDir(a.out);
  calib::ImuNoiseFigures f = r.figures;
  if (a.rate_hz > 0) f.update_rate_hz = a.rate_hz;
  data::writeTextFileAtomically((out / "imu.yaml").string(),
                                calib::verdictYamlComment(verdict) + calib::formatImuYaml(f));
  data::writeTextFileAtomically((out / "report.txt").string(), report);
  data::writeImageFile((out / "allan.png").string(), calib::renderAllanPlot(r));
  std::cout << report << "Wrote " << (out / "imu.yaml").string() << ", report.txt, allan.png\n";
  if (verdict.verdict == calib::Verdict::kWeak)
    std::cout << "WARNING: verdict WEAK (see above): record again before relying on these figures\n";
}


// ------------------------------------------------------------ camera-imu
struct CameraImuArgs {
  std::string corners;
  std::string images;
  std::string target;
  std::string imu;
  std::string config;
  std::string camchain;
  std::string imu_yaml;
  std::string reference;
  std::string out = "camera_imu_out";
  std::string time_offset = "on";
  double knot_rate = 20;
  int every = 1;
  int threads = 2;
  bool verbose = false;
  std::string options;
  double max_translation = 0, max_accel_bias = 0, max_gyro_bias = 0;
  const CLI::App* cli = nullptr;  // which flags were given (they override --options)
  bool given(const char* flag) const { return cli && cli->count(flag) > 0; }
};

void runCameraImu(const CameraImuArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  if (a.corners.empty() == a.images.empty())
    throw data::InputError(kCli, 0, "--corners", "give exactly one of --corners and --images");
  if (a.config.empty() == a.camchain.empty())
    throw data::InputError(kCli, 0, "--config", "give exactly one of --config and --camchain");
  if (a.time_offset != "on" && a.time_offset != "off")
    throw data::InputError(kCli, 0, "--estimate-time-offset", "must be on or off");
  if (!(a.knot_rate >= 1 && a.knot_rate <= 200))
    throw data::InputError(kCli, 0, "--knot-rate", "must be 1..200 Hz");
  if (a.every < 1) throw data::InputError(kCli, 0, "--every", "must be >= 1");

  calib::CameraImuOptions o;
  calib::CameraImuVerdictOptions vo;
  if (!a.options.empty()) {
    auto r = data::YamlOptionsReader::fromFile(a.options);
    calib::readCameraImuOptions(r, o);
    auto v = r.child("verdict");
    calib::readCameraImuVerdictOptions(v, vo);
    v.finish();
    r.finish();
  }
  // Every input file is read before the detections and the solve: a typo is an error at once.
  Eigen::Isometry3d reference_T_I_C = Eigen::Isometry3d::Identity();
  if (!a.reference.empty()) reference_T_I_C = calib::readEurocCameraToImu(a.reference);

  // Intrinsics and IMU noise.
  calib::CameraImuSensors sensors;
  std::string intrinsics_input;
  if (!a.config.empty()) {
    sensors = calib::readYacCalibConfig(a.config);
    if (!sensors.has_camera) throw data::InputError(a.config, 0, "cam0", "missing");
    intrinsics_input = a.config;
  } else {
    sensors.camera = calib::readKalibrCamchain(a.camchain);
    sensors.has_camera = true;
    intrinsics_input = a.camchain;
  }
  std::string sensors_source = intrinsics_input;
  if (!a.imu_yaml.empty()) {
    sensors_source = a.imu_yaml;
    sensors.imu = calib::readKalibrImuYaml(a.imu_yaml);
    sensors.has_imu = true;
  }
  if (!sensors.has_imu)
    throw data::InputError(a.config.empty() ? a.camchain : a.config, 0, "imu0",
                           "no IMU noise figures: give --imu-yaml (Kalibr imu.yaml) or a config "
                           "with imu0");

  // Detections.
  std::vector<calib::TargetObservation> views;
  calib::AprilGrid grid;
  if (!a.corners.empty()) {
    if (!fs::exists(a.corners)) throw data::InputError(a.corners, 0, "--corners", "no such file or folder");
    views = calib::readCornerCsvs(a.corners, nullptr, &grid);
  } else {
    if (a.target.empty()) throw data::InputError(kCli, 0, "--target", "needed with --images");
    grid = calib::readAprilGridYaml(a.target);
    views = detectAll(grid, a.images, 1, calib::DetectorOptions{}, true).views;
  }
  if (!fs::exists(a.imu)) throw data::InputError(a.imu, 0, "--imu", "no such file");
  const calib::ImuRecording imu = calib::readImuCsv(a.imu);
  const double read_seconds = secondsSince(t0);

  if (a.given("--estimate-time-offset")) o.estimate_time_offset = a.time_offset == "on";
  if (a.given("--knot-rate")) o.knot_rate_hz = a.knot_rate;
  if (a.given("--every")) o.frame_step = a.every;
  o.threads = a.threads;
  o.verbose = a.verbose;
  o.gravity = sensors.gravity;
  auto bound = [&](const char* flag, double value, double& field) {
    if (!a.given(flag)) return;
    if (!(value > 0)) throw data::InputError(kCli, 0, flag, "must be positive");
    field = value;
  };
  bound("--max-translation", a.max_translation, vo.max_translation_m);
  bound("--max-accel-bias", a.max_accel_bias, vo.max_accel_bias);
  bound("--max-gyro-bias", a.max_gyro_bias, vo.max_gyro_bias);
  const calib::CameraImuResult r = calib::calibrateCameraImu(
      views, sensors.camera, imu, sensors.imu, o,
      {a.corners.empty() ? a.images : a.corners, a.imu, intrinsics_input});
  calib::CalibrationVerdict verdict = calib::judgeCameraImu(r, o, vo);
  calib::judgeCameraImuInputs(verdict, intrinsics_input, a.imu_yaml);

  calib::CameraImuReportContext ctx;
  ctx.corners_input = a.corners.empty() ? a.images : a.corners;
  ctx.imu_input = a.imu;
  ctx.intrinsics_input = intrinsics_input;
  if (!a.reference.empty()) {
    ctx.has_reference = true;
    ctx.reference_name = a.reference;
    ctx.reference_T_I_C = reference_T_I_C;
  }
  const fs::path out(a.out);
  std::string report = calib::formatCameraImuReport(r, o, verdict, ctx);
  report += strprintf("\nTotal time (reading %.2f s + calibration %.2f s): %.2f s\n", read_seconds,
                      r.seconds, secondsSince(t0));
  if (verdict.verdict == calib::Verdict::kFailed) {
    std::cout << report;
    failCalibration(verdict, (out / "camchain-imucam.yaml").string());
  }
  makeDir(a.out);
  data::writeTextFileAtomically((out / "camchain-imucam.yaml").string(),
                                calib::verdictYamlComment(verdict) +
                                    calib::formatCamchainImuCamYaml(sensors.camera, r));
  // formatImuYaml's header says the figures come from Allan deviation; here they are an input.
  std::string imu_yaml = calib::formatImuYaml(sensors.imu);
  imu_yaml = "# IMU noise figures used by adugs calib camera-imu (from " + sensors_source +
             "); continuous-time densities.\n" + imu_yaml.substr(imu_yaml.find('\n') + 1);
  data::writeTextFileAtomically((out / "imu.yaml").string(), imu_yaml);
  data::writeTextFileAtomically((out / "report.txt").string(), report);
  const double rate = sensors.imu.update_rate_hz;
  data::writeImageFile((out / "gyro_residuals.png").string(),
           calib::renderImuResidualPlot(r.gyro_residuals, "Gyroscope residuals (spline - measured)",
                                        "rad/s", sensors.imu.gyro_noise_density * std::sqrt(rate)));
  data::writeImageFile((out / "accel_residuals.png").string(),
           calib::renderImuResidualPlot(r.accel_residuals, "Accelerometer residuals (spline - measured)",
                                        "m/s^2", sensors.imu.accel_noise_density * std::sqrt(rate)));
  data::writeImageFile((out / "reprojection_histogram.png").string(),
           calib::renderReprojectionHistogram(r.corner_errors_px));
  std::cout << report << "Wrote " << (out / "camchain-imucam.yaml").string()
            << ", imu.yaml, report.txt, gyro_residuals.png, accel_residuals.png, "
               "reprojection_histogram.png\n";
  if (verdict.verdict == calib::Verdict::kWeak)
    std::cout << "WARNING: verdict WEAK (see above): record again before relying on this calibration\n";
}

}  // namespace

void registerCalibCommand(CLI::App& root) {
  CLI::App* calib = root.add_subcommand("calib", "Calibration: AprilGrid target, camera intrinsics, camera-IMU, IMU noise; other tools' calibration files (show, convert)");
  calib->require_subcommand(1);
  calib->footer(
      "Every calibration result carries a verdict: ok; weak (written, with a WARNING and what to "
      "record next); failed (nothing written). Exit codes: 0 written (ok or weak), 2 input error, "
      "3 verdict failed. How to record and how to read the verdicts: doc/calibration.md.");

  auto t = std::make_shared<TargetArgs>();
  CLI::App* target = calib->add_subcommand("target", "Render a printable AprilGrid (PNG + vector PDF + YAML)");
  target->add_option("--target", t->yaml, "Kalibr target YAML (target_type: aprilgrid)");
  target->add_option("--tag-rows", t->rows, "Tag rows (instead of --target)");
  target->add_option("--tag-cols", t->cols, "Tag columns");
  target->add_option("--tag-size", t->size, "Tag size (black square) [m]");
  target->add_option("--tag-spacing", t->spacing, "Gap between tags / tag size");
  target->add_option("--border-bits", t->border_bits, "Black border in bits: 2 = Kalibr (default), 1 = standard tag36h11");
  target->add_option("--out", t->out, "Output prefix: PREFIX.png, PREFIX.pdf, PREFIX.yaml")->capture_default_str();
  target->add_option("--dpi", t->dpi, "PNG resolution")->capture_default_str();
  target->add_option("--margin", t->margin_m, "White margin around the board [m]")->capture_default_str();
  target->callback([t] { runTarget(*t); });

  auto d = std::make_shared<DetectArgs>();
  CLI::App* detect = calib->add_subcommand("detect", "Detect the AprilGrid in images; write one corner CSV per image (yac/EuRoC format)");
  detect->add_option("--target", d->target, "Target YAML")->required();
  detect->add_option("--images", d->images, "EuRoC cam folder, image folder or video")->required();
  detect->add_option("--out", d->out, "Output folder for the CSVs")->required();
  detect->add_option("--options", d->options, "Options YAML (detector: ...)");
  detect->add_option("--every", d->every, "Use one image in N")->capture_default_str();
  detect->add_option("--threads", d->threads, "Threads")->capture_default_str();
  detect->callback([d] { runDetect(*d); });

  auto in = std::make_shared<IntrinsicsArgs>();
  CLI::App* intr = calib->add_subcommand("intrinsics", "Calibrate a camera's intrinsics (pinhole radtan or equidistant, omni, double sphere, EUCM) from AprilGrid views");
  intr->add_option("--target", in->target, "Target YAML (needed with --images; checked against the CSVs with --corners), or chessboard:COLSxROWS:SQUARE_M");
  intr->add_option("--images", in->images, "EuRoC cam folder, image folder or video");
  intr->add_option("--corners", in->corners, "Folder of corner CSVs (or one CSV) instead of images");
  intr->add_option("--model", in->model, "Camera model: radtan (pinhole-radtan, default), equidistant (pinhole-equi), omni (omni-radtan), omni-none, ds (double sphere) or eucm (extended unified)");
  intr->add_option("--resolution", in->resolution, "Image size WxH (needed with --corners)");
  intr->add_option("--options", in->options, "Options YAML (calibration keys + detector: ...)");
  intr->add_option("--reference", in->reference, "EuRoC sensor.yaml to compare the result with (report)");
  intr->add_option("--out", in->out, "Output folder")->capture_default_str();
  intr->add_option("--every", in->every, "Use one image in N")->capture_default_str();
  intr->add_option("--threads", in->threads, "Threads")->capture_default_str();
  intr->add_flag("--save-corners", in->save_corners, "Also write the detected corners to OUT/corners/");
  intr->callback([in] { runIntrinsics(*in); });

  auto im = std::make_shared<ImuArgs>();
  CLI::App* imu = calib->add_subcommand("imu", "IMU noise densities and random walks from a static recording (Allan deviation)");
  imu->add_option("--imu", im->imu, "IMU CSV: #timestamp [ns],wx,wy,wz,ax,ay,az (EuRoC imu0/data.csv)")->required();
  imu->add_option("--out", im->out, "Output folder")->capture_default_str();
  imu->add_option("--rate", im->rate_hz, "Rate written to imu.yaml [Hz] (default: from timestamps)");
  imu->add_option("--points", im->points, "Cluster times on the log-spaced axis")->capture_default_str();
  imu->add_option("--options", im->options, "Options YAML (verdict: ...)");
  imu->callback([im] { runImu(*im); });

  auto ci = std::make_shared<CameraImuArgs>();
  CLI::App* cimu = calib->add_subcommand("camera-imu", "Camera-IMU extrinsics T_cam_imu, time offset, gravity and IMU biases (continuous-time B-spline, Kalibr-compatible outputs)");
  cimu->add_option("--corners", ci->corners, "Folder of AprilGrid corner CSVs (yac/EuRoC format), one per image");
  cimu->add_option("--images", ci->images, "EuRoC cam folder or image folder instead of --corners (runs the detector; needs --target)");
  cimu->add_option("--target", ci->target, "Target YAML (with --images)");
  cimu->add_option("--imu", ci->imu, "IMU CSV: #timestamp [ns],wx,wy,wz,ax,ay,az (EuRoC imu0/data.csv)")->required();
  cimu->add_option("--config", ci->config, "yac/EuRoC calibration config.yaml (cam0 intrinsics + imu0 noise)");
  cimu->add_option("--camchain", ci->camchain, "Kalibr camchain.yaml with the cam0 intrinsics (then give --imu-yaml)");
  cimu->add_option("--imu-yaml", ci->imu_yaml, "Kalibr imu.yaml with the IMU noise figures");
  cimu->add_option("--reference", ci->reference, "EuRoC cam0/sensor.yaml whose T_BS the result is compared with");
  cimu->add_option("--out", ci->out, "Output folder")->capture_default_str();
  cimu->add_option("--estimate-time-offset", ci->time_offset, "on | off")->capture_default_str();
  cimu->add_option("--knot-rate", ci->knot_rate, "B-spline knots per second")->capture_default_str();
  cimu->add_option("--every", ci->every, "Use one frame in N")->capture_default_str();
  cimu->add_option("--threads", ci->threads, "Threads")->capture_default_str();
  cimu->add_flag("--verbose", ci->verbose, "Print the solver progress");
  cimu->add_option("--options", ci->options, "Options YAML (calibration keys + verdict: ...; flags override it)");
  cimu->add_option("--max-translation", ci->max_translation, "Verdict: camera-IMU distance above which the result fails [m] (default 0.5)");
  cimu->add_option("--max-accel-bias", ci->max_accel_bias, "Verdict: accelerometer bias above which the result fails [m/s^2] (default 1)");
  cimu->add_option("--max-gyro-bias", ci->max_gyro_bias, "Verdict: gyro bias above which the result fails [rad/s] (default 0.5)");
  ci->cli = cimu;
  cimu->callback([ci] { runCameraImu(*ci); });

  registerCalibFileCommands(calib);
}

}  // namespace adugs::app

// adugs calib show | convert: the calibration files users already have (Kalibr, OpenVINS, VINS,
// Basalt, EuRoC), as the project understands them, and the same calibration for the other tools.
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>

#include "app/commands.h"
#include "calib/lens_refit.h"
#include "data/formats/atomic_file.h"
#include "data/formats/calibration_files.h"
#include "data/formats/calibration_writers.h"
#include "data/input_error.h"

namespace adugs::app {
namespace {
namespace fs = std::filesystem;

struct CalibFilesArgs {
  std::vector<std::string> files;
  double imu_rate_hz = 0;
  std::string json_out;  // show
  std::string to, out;   // convert
  std::string model;     // convert: refit every camera to this model first
  double max_refit_rms_px = 0.5;
};

data::RigCalibration readRig(const CalibFilesArgs& a) {
  data::RigCalibration rig = data::readCalibrationFiles(a.files);
  if (a.imu_rate_hz > 0 && rig.has_imu) {
    if (rig.imu.noise.rate_hz > 0 && rig.imu.noise.rate_hz != a.imu_rate_hz)
      throw data::InputError("--imu-rate", 0, "imu_rate", "differs from the update rate in " + rig.imu.source);
    rig.imu.noise.rate_hz = a.imu_rate_hz;
    data::resolvePerSampleNoise(rig.imu, a.imu_rate_hz);
  }
  return rig;
}

void printMatrix(const Eigen::Matrix4d& m) {
  for (int r = 0; r < 4; ++r) {
    std::cout << "      [";
    for (int c = 0; c < 4; ++c) std::cout << (c ? ", " : "") << std::setw(11) << m(r, c);
    std::cout << "]\n";
  }
}

void printRig(const data::RigCalibration& rig) {
  std::cout << std::setprecision(9);
  for (size_t i = 0; i < rig.files.size(); ++i) std::cout << "file " << rig.files[i] << ": " << rig.formats[i] << "\n";
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    const data::RigCamera& cam = rig.cameras[i];
    const data::CameraCalibration& c = cam.camera;
    std::cout << "cam" << i << " (" << cam.source << ")\n"
              << "  model: " << data::toString(c.projection);
    for (double p : c.projection_params) std::cout << " " << p;
    std::cout << ", distortion " << data::toString(c.distortion_model);
    if (c.distortion_model != data::DistortionModel::kNone)
      for (double d : c.distortion) std::cout << " " << d;
    std::cout << "\n  fx fy cx cy: " << c.fx << " " << c.fy << " " << c.cx << " " << c.cy << "\n"
              << "  resolution: " << c.width << "x" << c.height << "\n";
    if (cam.has_T_imu_cam) {
      std::cout << "  T_imu_cam (camera -> IMU):\n";
      printMatrix(c.T_B_C.matrix());
    } else {
      std::cout << "  T_imu_cam: not given\n";
    }
    std::cout << "  time offset: " << cam.time_offset_s << " s (t_imu = t_cam + offset)\n";
  }
  if (rig.has_imu) {
    const data::ImuNoise& n = rig.imu.noise;
    std::cout << "imu (" << rig.imu.source << ")\n";
    const std::string unit = rig.imu.noise_per_sample ? " (per sample: give --imu-rate for densities)" : "";
    std::cout << "  accelerometer noise density: " << n.accel_noise_density << unit << "\n"
              << "  accelerometer random walk:   " << n.accel_random_walk << unit << "\n"
              << "  gyroscope noise density:     " << n.gyro_noise_density << unit << "\n"
              << "  gyroscope random walk:       " << n.gyro_random_walk << unit << "\n"
              << "  update rate: ";
    if (n.rate_hz > 0) std::cout << n.rate_hz << " Hz\n";
    else std::cout << "not given\n";
    std::cout
              << "  intrinsics (Tw, Ta, Tg): " << (rig.imu.intrinsics.isIdentity() ? "identity" : "applied to the samples") << "\n";
  } else {
    std::cout << "imu: none\n";
  }
  for (const std::string& key : rig.ignored_keys) std::cout << "ignored: " << key << "\n";
}

void runShow(const CalibFilesArgs& a) {
  const data::RigCalibration rig = readRig(a);
  printRig(rig);
  if (!a.json_out.empty()) {
    if (a.json_out == "-") std::cout << data::formatCalibrationJson(rig);
    else data::writeTextFileAtomically(a.json_out, data::formatCalibrationJson(rig));
  }
}

// Every camera's lens in the model a.model: what the user asked the other tool to get.
void refitCameras(const CalibFilesArgs& a, data::RigCalibration& rig) {
  calib::LensModel model;
  if (!calib::parseLensModel(a.model, model)) throw data::InputError("--model", 0, "model", "unknown camera model");
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    data::CameraCalibration& camera = rig.cameras[i].camera;
    const std::string from = calib::lensModelName(camera);
    const calib::LensRefit fit = calib::refitLens(camera, model);
    std::cout << "cam" << i << ": " << from << " -> " << a.model << ": RMS " << std::setprecision(3) << fit.rms_px
              << " px, max " << fit.max_px << " px over " << fit.pixels << " grid pixels\n" << std::setprecision(9);
    if (!(fit.rms_px <= a.max_refit_rms_px))
      throw data::InputError(rig.cameras[i].source, 0, "cam" + std::to_string(i) + ".camera_model",
                             "the " + a.model + " model cannot hold this " + from + " lens: its best fit is off by " +
                                 std::to_string(fit.rms_px) + " px RMS (--max-refit-rms " +
                                 std::to_string(a.max_refit_rms_px) + ")");
    camera = fit.camera;
  }
}

void runConvert(const CalibFilesArgs& a) {
  data::RigCalibration rig = readRig(a);
  if (!a.model.empty()) refitCameras(a, rig);
  const data::CalibrationFiles files = data::formatCalibration(rig, a.to);
  std::error_code ec;
  fs::create_directories(a.out, ec);
  if (ec) throw data::InputError(a.out, 0, "--out", "cannot create the folder: " + ec.message());
  for (const auto& [name, text] : files) {
    const std::string path = (fs::path(a.out) / name).string();
    data::writeTextFileAtomically(path, text);
    std::cout << "wrote " << path << "\n";
  }
}

}  // namespace

void registerCalibFileCommands(CLI::App* calib) {
  auto s = std::make_shared<CalibFilesArgs>();
  CLI::App* show = calib->add_subcommand(
      "show", "Read calibration files of Kalibr, OpenVINS, VINS-Mono/Fusion, Basalt or EuRoC and print the calibration "
              "as adugs understood it");
  show->add_option("files", s->files, "calibration files (one or several; recognised by content)")
      ->required()
      ->check(CLI::ExistingFile);
  show->add_option("--json", s->json_out, "also write it as JSON to this file ('-': standard output)");
  show->add_option("--imu-rate", s->imu_rate_hz, "IMU rate [Hz], for VINS' per-sample noise figures")
      ->check(CLI::Range(1.0, 1e5));
  show->callback([s] { runShow(*s); });

  auto c = std::make_shared<CalibFilesArgs>();
  CLI::App* convert = calib->add_subcommand(
      "convert", "Write calibration files for another tool (kalibr, openvins, vins, basalt) from any files adugs reads");
  convert->add_option("files", c->files, "calibration files (one or several; recognised by content)")
      ->required()
      ->check(CLI::ExistingFile);
  convert->add_option("--to", c->to, "the tool to write for")
      ->required()
      ->check(CLI::IsMember(data::calibrationWriterNames()));
  convert->add_option("--out", c->out, "output folder")->required();
  convert->add_option("--imu-rate", c->imu_rate_hz, "IMU rate [Hz], for VINS' per-sample noise figures")
      ->check(CLI::Range(1.0, 1e5));
  convert->add_option("--model", c->model,
                       "refit every camera's lens to this model first (the same lens for a tool that lacks its "
                       "model, e.g. Basalt and radtan)")
      ->check(CLI::IsMember(calib::lensModelNames()));
  convert->add_option("--max-refit-rms", c->max_refit_rms_px,
                      "--model: refuse a refit whose RMS pixel error is larger [px]")
      ->check(CLI::PositiveNumber);
  convert->callback([c] { runConvert(*c); });
}

}  // namespace adugs::app

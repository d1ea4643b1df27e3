#include "data/sim_sequence_writer.h"

#include <cstdio>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "data/atomic_file.h"
#include "data/input_error.h"

namespace adugs::data {

namespace fs = std::filesystem;

namespace {

void makeDir(const fs::path& p) {
  std::error_code ec;
  fs::create_directories(p, ec);
  if (ec) throw InputError(p.string(), 0, "", "cannot create folder: " + ec.message());
}

void openCsv(std::ofstream& out, const fs::path& p, const char* header) {
  out.open(p, std::ios::binary | std::ios::trunc);
  if (!out) throw InputError(p.string(), 0, "", "cannot open for writing");
  out << header << "\n";
  out.flush();
}

// Shortest round-trip text for a double (deterministic, exact).
std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  double back = 0;
  for (int prec = 6; prec < 17; ++prec) {  // prefer the shortest exact form
    char b2[40];
    std::snprintf(b2, sizeof b2, "%.*g", prec, v);
    if (std::sscanf(b2, "%lf", &back) == 1 && back == v) return b2;
  }
  return buf;
}

void writePng(const fs::path& final_path, const cv::Mat& image) {
  // imwrite picks the encoder from the extension, hence ".tmp.png".
  const fs::path tmp = final_path.parent_path() / (final_path.stem().string() + ".tmp.png");
  if (!cv::imwrite(tmp.string(), image)) throw InputError(tmp.string(), 0, "", "cannot write image");
  std::error_code ec;
  fs::rename(tmp, final_path, ec);
  if (ec) throw InputError(final_path.string(), 0, "", "cannot rename image: " + ec.message());
}

}  // namespace

std::string formatMotRow(int frame, const SimObjectBox& b) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%d,%d,%d,%d,%d,%d,1,%d,%.4f", frame, b.id, b.box.x + 1, b.box.y + 1,
                b.box.width, b.box.height, cocoClassId(b.cls), b.visibility());
  return buf;
}

SimSequenceWriter::SimSequenceWriter(const std::string& root, const CameraCalibration& camera,
                                     const ImuNoise& imu)
    : mav_((fs::path(root) / "mav0").string()) {
  const fs::path mav(mav_);
  for (const char* d : {"cam0/data", "mask0/data", "imu0", "state_groundtruth_estimate0", "objects0"})
    makeDir(mav / d);
  writeEurocCameraYaml((mav / "cam0/sensor.yaml").string(), camera);
  writeEurocImuYaml((mav / "imu0/sensor.yaml").string(), imu);
  openCsv(cam_csv_, mav / "cam0/data.csv", "#timestamp [ns],filename");
  openCsv(mask_csv_, mav / "mask0/data.csv", "#timestamp [ns],filename");
  openCsv(mot_, mav / "objects0/gt.txt",
          "# frame,id,bb_left,bb_top,bb_width,bb_height,conf,class,visibility");
}

void SimSequenceWriter::writeImu(const std::vector<ImuSample>& samples) {
  std::string s =
      "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
      "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n";
  for (const ImuSample& m : samples) {
    s += std::to_string(m.t_ns);
    for (int i = 0; i < 3; ++i) s += "," + num(m.gyro[i]);
    for (int i = 0; i < 3; ++i) s += "," + num(m.accel[i]);
    s += "\n";
  }
  writeTextFileAtomically((fs::path(mav_) / "imu0/data.csv").string(), s);
}

void SimSequenceWriter::writeGroundTruth(const std::vector<GroundTruthState>& states) {
  std::string s =
      "#timestamp,p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z [],"
      "v_RS_R_x [m s^-1],v_RS_R_y [m s^-1],v_RS_R_z [m s^-1],"
      "b_w_RS_S_x [rad s^-1],b_w_RS_S_y [rad s^-1],b_w_RS_S_z [rad s^-1],"
      "b_a_RS_S_x [m s^-2],b_a_RS_S_y [m s^-2],b_a_RS_S_z [m s^-2]\n";
  for (const GroundTruthState& g : states) {
    const Eigen::Quaterniond& q = g.pose.q_W_B;
    s += std::to_string(g.pose.t_ns);
    for (int i = 0; i < 3; ++i) s += "," + num(g.pose.p_W_B[i]);
    s += "," + num(q.w()) + "," + num(q.x()) + "," + num(q.y()) + "," + num(q.z());
    for (int i = 0; i < 3; ++i) s += "," + num(g.v_W[i]);
    for (int i = 0; i < 3; ++i) s += "," + num(g.gyro_bias[i]);
    for (int i = 0; i < 3; ++i) s += "," + num(g.accel_bias[i]);
    s += "\n";
  }
  writeTextFileAtomically((fs::path(mav_) / "state_groundtruth_estimate0/data.csv").string(), s);
}

void SimSequenceWriter::writeInfo(const std::string& yaml_text) {
  writeTextFileAtomically((fs::path(mav_) / "sim.yaml").string(), yaml_text);
}

void SimSequenceWriter::writeFrame(int64_t t_ns, const SimFrame& frame) {
  const std::string name = std::to_string(t_ns) + ".png";
  const fs::path mav(mav_);
  writePng(mav / "cam0/data" / name, frame.image);
  writePng(mav / "mask0/data" / name, frame.mask);
  ++frames_;
  cam_csv_ << t_ns << "," << name << "\n";
  mask_csv_ << t_ns << "," << name << "\n";
  for (const SimObjectBox& b : frame.boxes) mot_ << formatMotRow(frames_, b) << "\n";
  cam_csv_.flush();
  mask_csv_.flush();
  mot_.flush();
  if (!cam_csv_ || !mask_csv_ || !mot_) throw InputError(mav_, 0, "", "cannot write the CSV files");
}

}  // namespace adugs::data

#include "data/formats/asl_writer.h"

#include <cstdio>
#include <filesystem>


#include "data/formats/atomic_file.h"
#include "data/formats/csv_reader.h"
#include "data/formats/image_file.h"
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

}  // namespace

std::string exactNumber(double v) {
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

AslWriter::AslWriter(const std::string& root, const CameraCalibration& camera, const ImuNoise* imu, bool masks,
                     const std::string& camera_comment, const std::string& camera_first_comment)
    : mav_((fs::path(root) / "mav0").string()), masks_(masks) {
  const fs::path mav(mav_);
  makeDir(mav / "cam0/data");
  writeEurocCameraYaml((mav / "cam0/sensor.yaml").string(), camera, camera_comment, camera_first_comment);
  openCsv(cam_csv_, mav / "cam0/data.csv", "#timestamp [ns],filename");
  if (imu) {
    makeDir(mav / "imu0");
    writeEurocImuYaml((mav / "imu0/sensor.yaml").string(), *imu);
    openCsv(imu_csv_, mav / "imu0/data.csv",
            "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
            "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]");
  }
  if (masks_) {
    makeDir(mav / "mask0/data");
    openCsv(mask_csv_, mav / "mask0/data.csv", "#timestamp [ns],filename");
  }
}

void AslWriter::writeFrame(int64_t t_ns, const cv::Mat& image, const cv::Mat& mask) {
  if (t_ns <= last_frame_t_)
    throw InputError(mav_ + "/cam0/data.csv", 0, "timestamp", "frame stamps must increase (" + std::to_string(t_ns) +
                                                                  " after " + std::to_string(last_frame_t_) + ")");
  last_frame_t_ = t_ns;
  const std::string name = std::to_string(t_ns) + ".png";
  const fs::path mav(mav_);
  writeImageFile((mav / "cam0/data" / name).string(), image);
  if (masks_) writeImageFile((mav / "mask0/data" / name).string(), mask);
  ++frames_;
  cam_csv_ << t_ns << "," << name << "\n";
  cam_csv_.flush();
  if (masks_) {
    mask_csv_ << t_ns << "," << name << "\n";
    mask_csv_.flush();
  }
  if (imu_csv_.is_open()) imu_csv_.flush();
  if (!cam_csv_ || (masks_ && !mask_csv_) || (imu_csv_.is_open() && !imu_csv_))
    throw InputError(mav_, 0, "", "cannot write the CSV files");
}

void AslWriter::writeImu(const ImuSample& m) {
  if (!imu_csv_.is_open()) throw InputError(mav_ + "/imu0/data.csv", 0, "", "this writer has no IMU");
  if (m.t_ns <= last_imu_t_)
    throw InputError(mav_ + "/imu0/data.csv", 0, "timestamp", "IMU stamps must increase (" + std::to_string(m.t_ns) +
                                                                  " after " + std::to_string(last_imu_t_) + ")");
  last_imu_t_ = m.t_ns;
  std::string row = std::to_string(m.t_ns);
  for (int i = 0; i < 3; ++i) row += "," + exactNumber(m.gyro[i]);
  for (int i = 0; i < 3; ++i) row += "," + exactNumber(m.accel[i]);
  imu_csv_ << row << "\n";
  ++imu_rows_;
}

void AslWriter::writeGroundTruth(const std::vector<GroundTruthState>& states) {
  std::string s =
      "#timestamp,p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z [],"
      "v_RS_R_x [m s^-1],v_RS_R_y [m s^-1],v_RS_R_z [m s^-1],"
      "b_w_RS_S_x [rad s^-1],b_w_RS_S_y [rad s^-1],b_w_RS_S_z [rad s^-1],"
      "b_a_RS_S_x [m s^-2],b_a_RS_S_y [m s^-2],b_a_RS_S_z [m s^-2]\n";
  for (const GroundTruthState& g : states) {
    const Eigen::Quaterniond& q = g.pose.q_W_B;
    s += std::to_string(g.pose.t_ns);
    for (int i = 0; i < 3; ++i) s += "," + exactNumber(g.pose.p_W_B[i]);
    s += "," + exactNumber(q.w()) + "," + exactNumber(q.x()) + "," + exactNumber(q.y()) + "," + exactNumber(q.z());
    for (int i = 0; i < 3; ++i) s += "," + exactNumber(g.v_W[i]);
    for (int i = 0; i < 3; ++i) s += "," + exactNumber(g.gyro_bias[i]);
    for (int i = 0; i < 3; ++i) s += "," + exactNumber(g.accel_bias[i]);
    s += "\n";
  }
  const fs::path dir = fs::path(mav_) / "state_groundtruth_estimate0";
  makeDir(dir);
  writeTextFileAtomically((dir / "data.csv").string(), s);
}

void AslWriter::flush() {
  if (imu_csv_.is_open()) {
    imu_csv_.flush();
    if (!imu_csv_) throw InputError(mav_ + "/imu0/data.csv", 0, "", "cannot write");
  }
}

AslFolderCounts countAslFolder(const std::string& root) {
  const fs::path mav = fs::path(root) / "mav0";
  auto csvRows = [](const fs::path& path) -> size_t {
    if (!fs::exists(path)) return 0;
    CsvReader r(path.string());
    size_t rows = 0;
    while (r.next()) ++rows;
    return rows;
  };
  AslFolderCounts c;
  c.camera_rows = csvRows(mav / "cam0/data.csv");
  c.imu_rows = csvRows(mav / "imu0/data.csv");
  if (fs::is_directory(mav / "cam0/data"))
    for (const auto& e : fs::directory_iterator(mav / "cam0/data"))
      c.image_files += e.is_regular_file() && e.path().extension() == ".png";
  return c;
}

}  // namespace adugs::data

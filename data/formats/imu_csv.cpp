#include "data/formats/imu_csv.h"

#include "data/formats/csv_reader.h"
#include "data/input_error.h"

namespace adugs::data {

std::vector<ImuSample> readEurocImuCsv(const std::string& path) {
  CsvReader csv(path);
  csv.setColumnNames({"timestamp [ns]", "w_x", "w_y", "w_z", "a_x", "a_y", "a_z"});
  std::vector<ImuSample> out;
  while (csv.next()) {
    csv.requireColumns(7);
    ImuSample s;
    s.t_ns = csv.int64At(0);
    for (int i = 0; i < 3; ++i) {
      s.gyro[i] = csv.doubleAt(static_cast<size_t>(1 + i));
      s.accel[i] = csv.doubleAt(static_cast<size_t>(4 + i));
    }
    if (!out.empty() && s.t_ns <= out.back().t_ns) csv.fail(0, "timestamps must strictly increase");
    out.push_back(s);
  }
  if (out.empty()) throw InputError(path, 0, "", "no IMU samples");
  return out;
}

}  // namespace adugs::data

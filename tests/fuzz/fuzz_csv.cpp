// libFuzzer target: arbitrary bytes as a CSV file, read by CsvReader (both separators, every
// converter) and by EurocReader as imu0/data.csv or as cam0/data.csv (with skip_bad_frames).
// InputError is the expected outcome for bad input; any other exception, a crash or a sanitizer
// report is a bug.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <unistd.h>

#include "data/formats/csv_reader.h"
#include "data/formats/euroc_sensor_yaml.h"
#include "data/input_error.h"
#include "data/sources/euroc_reader.h"

namespace {
namespace fs = std::filesystem;
using namespace adugs::data;

const char* kImuCsv = "#timestamp,w_x,w_y,w_z,a_x,a_y,a_z\n1000,0,0,0,0,0,9.8\n2000,0,0,0,0,0,9.8\n";
const char* kCamCsv = "#timestamp,filename\n1500,a.png\n";

// Unlink first: truncating a file that has data makes ext4 flush it on close (auto_da_alloc),
// which costs milliseconds per input.
void writeFile(const fs::path& path, const uint8_t* data, size_t size) {
  std::error_code ec;
  fs::remove(path, ec);
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

void writeFile(const fs::path& path, const std::string& text) {
  writeFile(path, reinterpret_cast<const uint8_t*>(text.data()), text.size());
}

// A scratch EuRoC sequence (one per process) whose CSVs get replaced by the input.
struct Scratch {
  fs::path root;
  Scratch() : root(fs::temp_directory_path() / ("adugs_fuzz_csv_" + std::to_string(getpid()))) {
    fs::create_directories(root / "mav0" / "cam0" / "data");
    fs::create_directories(root / "mav0" / "imu0");
    CameraCalibration cam;
    cam.width = 4;
    cam.height = 4;
    cam.fx = cam.fy = 10;
    cam.distortion = {0, 0, 0, 0};
    cam.rate_hz = 20;
    writeEurocCameraYaml((root / "mav0" / "cam0" / "sensor.yaml").string(), cam);
    ImuNoise imu;
    imu.rate_hz = imu.gyro_noise_density = imu.gyro_random_walk = 1;
    imu.accel_noise_density = imu.accel_random_walk = 1;
    writeEurocImuYaml((root / "mav0" / "imu0" / "sensor.yaml").string(), imu);
    writeFile(root / "mav0" / "cam0" / "data" / "a.png", "");  // existence is enough (no decoding)
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(root, ec);
  }
  fs::path cam() const { return root / "mav0" / "cam0" / "data.csv"; }
  fs::path imu() const { return root / "mav0" / "imu0" / "data.csv"; }
};

Scratch& scratch() {
  static Scratch s;
  return s;
}

// Every accessor on every row; errors are InputError.
void readRows(const std::string& path, CsvReader::Separator sep) {
  CsvReader csv(path, sep);
  csv.setColumnNames({"timestamp", "value"});
  while (csv.next()) {
    for (size_t i = 0; i <= csv.size(); ++i) {
      try {
        (void)csv.field(i);
        (void)csv.int64At(i);
      } catch (const InputError&) {
      }
      try {
        (void)csv.doubleAt(i);
      } catch (const InputError&) {
      }
    }
    try {
      csv.requireColumns(2, 7);
    } catch (const InputError&) {
    }
  }
}

void readSequence(EurocReaderOptions options) {
  EurocReader reader(scratch().root.string(), options);
  Measurement m;
  int64_t last = INT64_MIN;
  while (reader.next(m)) {
    if (m.timeNs() < last) {
      std::fprintf(stderr, "BUG: EurocReader went back in time: %lld after %lld\n",
                   static_cast<long long>(m.timeNs()), static_cast<long long>(last));
      std::abort();
    }
    last = m.timeNs();
  }
}

template <typename F>
void expectOnlyInputError(const char* what, F&& f) {
  try {
    f();
  } catch (const InputError&) {
    // expected for bad input
  } catch (const std::exception& e) {
    std::fprintf(stderr, "BUG: %s threw a non-InputError exception: %s\n", what, e.what());
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  static std::ofstream devnull("/dev/null");
  std::cerr.rdbuf(devnull.rdbuf());  // EurocReader's skip warnings; sanitizers write to fd 2 directly
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const Scratch& s = scratch();
  fs::path generic = s.root / "generic.csv";
  writeFile(generic, data, size);
  expectOnlyInputError("CsvReader(comma)", [&] { readRows(generic.string(), CsvReader::Separator::kComma); });
  expectOnlyInputError("CsvReader(whitespace)", [&] { readRows(generic.string(), CsvReader::Separator::kWhitespace); });

  // One EurocReader run per input (opening a sequence parses two sensor.yaml files): the lowest
  // bit of the last byte picks which CSV the input replaces.
  if (size == 0 || (data[size - 1] & 1) == 0) {
    writeFile(s.cam(), kCamCsv);
    writeFile(s.imu(), data, size);
    expectOnlyInputError("EurocReader(imu0/data.csv)", [] { readSequence({false, false}); });
  } else {
    writeFile(s.imu(), kImuCsv);
    writeFile(s.cam(), data, size);
    expectOnlyInputError("EurocReader(cam0/data.csv)", [] { readSequence({true, false}); });
  }
  return 0;
}

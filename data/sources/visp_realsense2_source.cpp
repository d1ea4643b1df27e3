#include "data/sources/visp_realsense2_source.h"

#include "data/input_error.h"

#if defined(ADUGS_WITH_VISP_REALSENSE2)

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <ctime>
#include <deque>
#include <iostream>
#include <mutex>

#include <librealsense2/rs.hpp>
#include <visp3/sensor/vpRealSense2.h>

#include "data/device/host_clock.h"
#include "data/device/pixel_formats.h"
#include "data/sources/imu_unifier.h"
#include "data/sources/time_ordered_merge.h"

namespace adugs::data {
namespace {

class VispRealSense2Source : public data::SequenceSource {
 public:
  VispRealSense2Source(const D435iOptions& options, int64_t image_time_shift_ns)
      : options_(options), image_time_shift_ns_(image_time_shift_ns) {
    // librealsense stamps in the global time domain: the host's system clock (realtime), in ms.
    realtime_minus_monotonic_ns_ = clockMinusMonotonicNs(CLOCK_REALTIME);
    rs2::config config;
    if (!options.serial.empty()) config.enable_device(options.serial);
    if (options.stream == "infrared")
      config.enable_stream(RS2_STREAM_INFRARED, 1, options.width, options.height, RS2_FORMAT_Y8, static_cast<int>(options.fps));
    else
      config.enable_stream(RS2_STREAM_COLOR, options.width, options.height, RS2_FORMAT_YUYV, static_cast<int>(options.fps));
    if (options.imu) {
      config.enable_stream(RS2_STREAM_ACCEL, RS2_FORMAT_MOTION_XYZ32F, static_cast<int>(options.accel_hz));
      config.enable_stream(RS2_STREAM_GYRO, RS2_FORMAT_MOTION_XYZ32F, static_cast<int>(options.gyro_hz));
    }
    frame_stream_ = merge_.addStream(options.frame_latency_s);
    if (options.imu) imu_stream_ = merge_.addStream(options.imu_latency_s);
    callback_ = [this](rs2::frame f) { onFrame(f); };
    try {
      if (!camera_.open(config, callback_))
        throw data::InputError("librealsense", 0, "d435i.backend", "vpRealSense2::open failed");
      rs2::depth_sensor depth = camera_.getPipelineProfile().get_device().first<rs2::depth_sensor>();
      if (options.emitter != "keep" && depth.supports(RS2_OPTION_EMITTER_ENABLED))
        depth.set_option(RS2_OPTION_EMITTER_ENABLED, options.emitter == "on" ? 1.f : 0.f);
      if (depth.supports(RS2_OPTION_ENABLE_AUTO_EXPOSURE))
        depth.set_option(RS2_OPTION_ENABLE_AUTO_EXPOSURE, options.exposure_us > 0 ? 0.f : 1.f);
      if (options.exposure_us > 0 && depth.supports(RS2_OPTION_EXPOSURE))
        depth.set_option(RS2_OPTION_EXPOSURE, static_cast<float>(options.exposure_us));
      if (options.gain > 0 && depth.supports(RS2_OPTION_GAIN)) depth.set_option(RS2_OPTION_GAIN, static_cast<float>(options.gain));
    } catch (const rs2::error& e) {
      throw data::InputError("librealsense", 0, "d435i.backend", std::string(e.get_failed_function()) + ": " + e.what());
    }
    description_ = "RealSense through librealsense (vpRealSense2): " + options.stream + " " + std::to_string(options.width) +
                   "x" + std::to_string(options.height) + " at " + std::to_string(static_cast<int>(options.fps)) + " Hz" +
                   (options.imu ? ", accel + gyro united" : "");
  }

  ~VispRealSense2Source() override {
    stop();
    camera_.close();
  }

  bool next(data::Measurement& m) override {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      if (merge_.pop(monotonicNs(), &m, stopped_)) return true;
      if (stopped_) return false;
      const int64_t deadline = merge_.releaseDeadlineNs();
      const int64_t wait_ms =
          deadline == INT64_MAX ? 100 : std::clamp<int64_t>((deadline - monotonicNs()) / 1'000'000 + 1, 0, 100);
      if (!arrived_.wait_for(lock, std::chrono::milliseconds(wait_ms), [this] { return fresh_ || stopped_; }) &&
          monotonicNs() - last_arrival_ns_ > static_cast<int64_t>(options_.stall_timeout_s * 1e9)) {
        stopped_ = true;
        reason_ = "no data from librealsense for " + std::to_string(options_.stall_timeout_s) + " s (camera unplugged?)";
      }
      fresh_ = false;
    }
  }

  data::SourceCounts counts() const override {
    std::lock_guard<std::mutex> lock(mutex_);
    data::SourceCounts c;
    c.late_dropped = merge_.late(frame_stream_) + (imu_stream_ >= 0 ? merge_.late(imu_stream_) : 0);
    c.imu_dropped = imu_stream_ >= 0 ? merge_.outOfOrder(imu_stream_) : 0;
    c.unmatched_gyro = unifier_.unmatched();
    return c;
  }
  std::string description() const override { return description_; }
  bool isLive() const override { return true; }
  void stop() override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!stopped_) reason_ = "stopped on request";
    stopped_ = true;
    arrived_.notify_all();
  }
  std::string stopReason() const override {
    std::lock_guard<std::mutex> lock(mutex_);
    return reason_;
  }

 private:
  // Called on librealsense's threads.
  void onFrame(const rs2::frame& f) {
    if (const rs2::frameset set = f.as<rs2::frameset>()) {
      for (const rs2::frame& part : set) onFrame(part);
      return;
    }
    if (f.get_frame_timestamp_domain() != RS2_TIMESTAMP_DOMAIN_GLOBAL_TIME) {
      warnOnce("librealsense does not give global-time stamps (RS2_OPTION_GLOBAL_TIME_ENABLED off?)");
      return;
    }
    int64_t t = static_cast<int64_t>(f.get_timestamp() * 1e6) - realtime_minus_monotonic_ns_;
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopped_) return;
    last_arrival_ns_ = monotonicNs();
    const rs2_stream type = f.get_profile().stream_type();
    if (const rs2::motion_frame motion = f.as<rs2::motion_frame>()) {
      const rs2_vector v = motion.get_motion_data();
      const Eigen::Vector3d value(v.x, v.y, v.z);
      if (type == RS2_STREAM_ACCEL) unifier_.addAccel(t, value);
      else if (type == RS2_STREAM_GYRO) unifier_.addGyro(t, value);
      data::ImuSample s;
      while (unifier_.pop(&s)) {
        data::Measurement m;
        m.type = data::Measurement::Type::kImu;
        m.imu = s;
        merge_.push(imu_stream_, std::move(m));
      }
    } else if (const rs2::video_frame video = f.as<rs2::video_frame>()) {
      // The middle of the exposure: the frame timestamp is the readout start on the device clock.
      if (f.supports_frame_metadata(RS2_FRAME_METADATA_SENSOR_TIMESTAMP) &&
          f.supports_frame_metadata(RS2_FRAME_METADATA_FRAME_TIMESTAMP))
        t -= 1000 * (f.get_frame_metadata(RS2_FRAME_METADATA_FRAME_TIMESTAMP) -
                     f.get_frame_metadata(RS2_FRAME_METADATA_SENSOR_TIMESTAMP));
      cv::Mat image, colour;
      const data::PixelFormat format = type == RS2_STREAM_COLOR ? data::PixelFormat::kYuyv : data::PixelFormat::kGrey;
      const uint8_t* bytes = static_cast<const uint8_t*>(video.get_data());
      const size_t size = static_cast<size_t>(video.get_data_size());
      if (!data::decodeGrey(format, bytes, size, video.get_width(), video.get_height(), video.get_stride_in_bytes(), &image))
        return;
      if (format == data::PixelFormat::kYuyv &&
          !data::decodeYuyvToBgr(bytes, size, video.get_width(), video.get_height(), video.get_stride_in_bytes(), &colour))
        return;
      data::Measurement m;
      m.type = data::Measurement::Type::kFrame;
      m.frame.t_ns = t + image_time_shift_ns_;
      m.frame.image = image;
      m.frame.colour = colour;
      merge_.push(frame_stream_, std::move(m));
    }
    fresh_ = true;
    arrived_.notify_all();
  }

  void warnOnce(const std::string& what) {
    static std::once_flag once;
    std::call_once(once, [&] { std::cerr << "warning: d435i: " << what << "\n"; });
  }

  D435iOptions options_;
  int64_t image_time_shift_ns_;
  int64_t realtime_minus_monotonic_ns_ = 0;
  std::string description_;
  vpRealSense2 camera_;
  std::function<void(rs2::frame)> callback_;
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  bool fresh_ = false, stopped_ = false;
  int64_t last_arrival_ns_ = monotonicNs();
  std::string reason_;
  data::ImuUnifier unifier_;
  TimeOrderedMerge merge_;
  int frame_stream_ = -1, imu_stream_ = -1;
};

}  // namespace

bool vispRealSense2Available() { return true; }

std::unique_ptr<data::SequenceSource> openVispRealSense2(const D435iOptions& options, int64_t image_time_shift_ns) {
  return std::make_unique<VispRealSense2Source>(options, image_time_shift_ns);
}

}  // namespace adugs::data

#else  // this build's ViSP has no librealsense2 (Debian's)

namespace adugs::data {

bool vispRealSense2Available() { return false; }

std::unique_ptr<data::SequenceSource> openVispRealSense2(const D435iOptions&, int64_t) {
  throw data::InputError("d435i", 0, "d435i.backend",
                         "librealsense: this build's ViSP has no librealsense2 (VISP_HAVE_REALSENSE2 undefined, as in "
                         "Debian's libvisp-dev); use backend: kernel");
}

}  // namespace adugs::data

#endif

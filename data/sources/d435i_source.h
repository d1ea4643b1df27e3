#pragma once
// A RealSense D435i as a live SequenceSource, without librealsense: the infrared (or colour)
// images through V4L2, the device-clock stamps of each frame from the UVC metadata node, the
// emitter and exposure through the camera's UVC extension unit, the IMU through the kernel's
// HID IIO devices (accel_3d, gyro_3d), all on one clock. next() blocks until the next measurement
// and hands them out in time order:
//
//   frames   grey image (the colour stream: also Frame::colour, BGR);
//            stamp = the middle of the exposure (D4xx capture-timing metadata), device clock
//            mapped to the host's CLOCK_MONOTONIC (data/device/device_clock.h), plus the
//            calibration's timeshift_cam_imu; without a metadata node: the driver's host stamp
//   IMU      accelerometer interpolated onto the gyro stamps (data/sources/imu_unifier.h), in the
//            camera-aligned IMU frame (data/device/realsense_imu.h), SI units, same clock
//
// The first clock_warmup_s of measurements only fit the clock. A measurement is released once every stream has passed its stamp, or has been silent for its
// latency bound (options frame_latency_s / imu_latency_s): the order is exact as long as no frame
// arrives later than frame_latency_s after its mid-exposure (late ones are dropped and counted).
// next() returns false when the camera or IMU goes away (unplugged: the driver returns ENODEV or
// the device file closes), when a stream stalls for stall_timeout_s, or after stop(); the
// measurements already read are handed out first, and stopReason() says what happened.
//
// Call next() from a thread that does little else: the driver keeps `buffers` frames and the IIO
// FIFO `iio_buffer_records` samples while it is not called, then drops frames (counted).
#include <atomic>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "data/device/d4xx_controls.h"
#include "data/device/device_clock.h"
#include "data/device/iio_sensor.h"
#include "data/device/pixel_formats.h"
#include "data/device/uvc_metadata.h"
#include "data/device/v4l2_io.h"
#include "data/device/v4l2_stream.h"
#include "data/sources/d435i_options.h"
#include "data/sources/dataset_preset.h"
#include "data/sources/imu_unifier.h"
#include "data/sources/sequence_source.h"
#include "data/sources/time_ordered_merge.h"

namespace adugs::data {

struct D435iStats {
  size_t frames = 0;                   // handed out
  size_t frames_lost_by_driver = 0;    // gaps in the driver's frame counter (no free buffer)
  size_t frames_without_metadata = 0;  // their metadata never came: no device stamp
  size_t frames_bad = 0;               // flagged as erroneous or shorter than the image
  size_t frames_late = 0;              // came after measurements stamped later were handed out
  size_t imu_samples = 0;              // united samples handed out
  size_t accel_samples = 0, gyro_samples = 0;  // read from the devices
  size_t imu_late = 0;
  size_t imu_out_of_order = 0;         // a stamp not after the previous one of its stream
  size_t gyro_unmatched = 0;           // gyro samples with no accelerometer sample around them
  size_t warmup_discarded = 0;         // measurements of the clock warm-up, not handed out
  double clock_drift_ppm = 0;          // the fitted rate error of the camera clock
  bool device_clock = false;           // frames stamped by the device clock (metadata found)
  bool imu_device_stamps = false;      // IIO records carried the device's timestamps
};

class D435iSource : public data::SequenceSource {
 public:
  // Finds the camera and opens its streams; InputError when it cannot (no camera, permissions,
  // unsupported format, ...). `image_time_shift_ns` is added to frame stamps (Kalibr's
  // timeshift_cam_imu).
  D435iSource(const D435iOptions& options, V4l2Io& io, int64_t image_time_shift_ns = 0);
  ~D435iSource() override;

  bool next(data::Measurement& m) override;
  data::SourceCounts counts() const override;
  std::string description() const override { return description_; }
  bool isLive() const override { return true; }
  void stop() override;
  std::string stopReason() const override { return stop_reason_; }
  D435iStats stats() const;

 private:
  struct WaitingFrame {
    cv::Mat image, colour;  // colour: BGR from the colour stream, else empty
    int64_t host_ns = 0;
  };
  void openCamera(const UsbCamera& camera, V4l2Io& io);
  void openImu(const UsbCamera& camera);
  void applyControls(V4l2Io& io);
  void startStreaming(V4l2Io& io);  // controls, then streams (controls put back if that fails)
  void restoreControls();
  void pump(int timeout_ms);
  void onVideo();
  void onMetadata();
  void stopUsingMetadata();
  void onImu(IioSensor& sensor, bool accel);
  void frameWithMetadata(const cv::Mat& image, const cv::Mat& colour, const data::UvcFrameMetadata& meta);
  void queueFrame(int64_t t_ns, const cv::Mat& image, const cv::Mat& colour);
  void queueUnitedImu();
  bool inWarmup(int64_t t_ns);
  void end(const std::string& reason);

  D435iOptions options_;
  int64_t image_time_shift_ns_ = 0;
  std::string description_;
  std::unique_ptr<V4l2Stream> video_, meta_;
  std::unique_ptr<D4xxControls> controls_;
  data::PixelFormat format_ = data::PixelFormat::kGrey;
  int restore_emitter_ = -1;  // emitter mode to put back on close, -1: untouched
  std::unique_ptr<IioSensor> accel_, gyro_;
  double gyro_lsb_deg_s_ = 0;
  int imu_stamp_kind_ = 0;          // 0 unknown, 1 device counter, 2 host clock
  int64_t imu_host_offset_ns_ = 0;  // host-clock IIO stamps: their clock minus CLOCK_MONOTONIC
  data::CounterUnwrapper unwrapper_;
  data::DeviceClockMapper clock_;
  data::ImuUnifier unifier_;
  int64_t last_accel_t_ = INT64_MIN, last_gyro_t_ = INT64_MIN;
  bool warned_pts_ = false;
  std::map<uint32_t, WaitingFrame> frames_waiting_;             // by the driver's frame counter
  std::map<uint32_t, data::UvcFrameMetadata> metadata_waiting_;
  static constexpr int kMetadataGiveUp = 30;  // frames in a row without metadata: use host stamps
  int frames_unmatched_in_a_row_ = 0;
  bool have_sequence_ = false;
  uint32_t last_sequence_ = 0;
  TimeOrderedMerge merge_;
  int frame_stream_ = -1, imu_stream_ = -1;
  int64_t warmup_until_ = INT64_MIN;  // stamps before this are the clock's warm-up
  int64_t last_frame_arrival_ = 0, last_imu_arrival_ = 0;
  int stop_fd_ = -1;  // eventfd: stop() wakes a blocked next()
  std::atomic<bool> stop_requested_{false};
  bool ended_ = false;
  std::string stop_reason_;
  D435iStats stats_;
};

// The source with the calibration it needs: the Kalibr files when given (camchain's cam0 and
// imu.yaml; their resolution must be the stream's), else the config's d435i.cam0 / imu0 (a
// placeholder camera: calibrate). InputError for every mismatch.
data::OpenedSequence openD435i(const D435iOptions& options, const std::vector<std::string>& calibration = {},
                               V4l2Io& io = systemV4l2Io());

}  // namespace adugs::data

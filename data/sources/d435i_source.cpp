#include "data/sources/d435i_source.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <ctime>
#include <iostream>
#include <sstream>

#include <cstring>

#include <linux/videodev2.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include "data/device/camera_nodes.h"
#include "data/device/host_clock.h"
#include "data/device/realsense_imu.h"
#include "data/device/usb_device_tree.h"
#include "data/formats/calibration_files.h"
#include "data/input_error.h"
#include "data/sources/imu_correction.h"
#include "data/sources/visp_realsense2_source.h"

namespace adugs::data {
namespace {

std::string sizesText(const V4l2FormatInfo& f) {
  std::ostringstream s;
  for (size_t i = 0; i < f.sizes.size(); ++i) {
    const V4l2FrameSize& z = f.sizes[i];
    s << (i ? ", " : "") << z.width << "x" << z.height;
    if (!z.rates_hz.empty()) {
      s << " (";
      for (size_t k = 0; k < z.rates_hz.size(); ++k) s << (k ? "/" : "") << z.rates_hz[k];
      s << " Hz)";
    }
  }
  return s.str();
}

// Whether `format` is offered at width x height (and fps, when the node lists rates).
bool offers(const V4l2FormatInfo& f, int width, int height, double fps) {
  for (const V4l2FrameSize& z : f.sizes) {
    if (z.width != width || z.height != height) continue;
    if (z.rates_hz.empty()) return true;
    for (double r : z.rates_hz)
      if (std::abs(r - fps) < 0.5) return true;
  }
  return f.sizes.empty();  // a node that lists no sizes: let S_FMT decide
}

const char* kGuide = " (README, \"Live on a D435i\")";

// Metadata formats (older kernel headers lack the D4XX one).
constexpr uint32_t kMetaFormatD4xx = 0x58583444;  // v4l2_fourcc('D', '4', 'X', 'X')
constexpr uint32_t kMetaFormatUvc = 0x48435655;   // v4l2_fourcc('U', 'V', 'C', 'H')

}  // namespace

D435iSource::D435iSource(const D435iOptions& options, V4l2Io& io, int64_t image_time_shift_ns)
    : options_(options), image_time_shift_ns_(image_time_shift_ns) {
  const std::vector<UsbCamera> cameras = findUsbCameras(options.sys_root, options.dev_root, options.usb_id);
  const UsbCamera* camera = nullptr;
  for (const UsbCamera& c : cameras)
    if (options.serial.empty() || c.serial == options.serial) {
      camera = &c;
      break;
    }
  if (!camera) {
    std::string what = "no USB camera " + options.usb_id;
    if (!options.serial.empty()) what += " with serial " + options.serial;
    what += " with a V4L2 node";
    if (!cameras.empty()) {
      what += " (found serial";
      for (const UsbCamera& c : cameras) what += " " + (c.serial.empty() ? std::string("?") : c.serial);
      what += ")";
    }
    throw data::InputError(options.sys_root + "/class/video4linux", 0, "d435i.usb_id",
                           what + "; is it plugged in (lsusb), on a USB 3 port? `adugs d435i info` lists what is there" + kGuide);
  }
  if (!camera->speed.empty() && std::atof(camera->speed.c_str()) < 5000)
    std::cerr << "warning: d435i: the camera runs at USB " << camera->speed
              << " Mb/s (USB 2): few modes, frames may be dropped; use a USB 3 port and cable\n";
  // Everything that may refuse first; the camera's controls change only once nothing can.
  openCamera(*camera, io);
  frame_stream_ = merge_.addStream(options.frame_latency_s);
  if (options.imu) {
    openImu(*camera);
    imu_stream_ = merge_.addStream(options.imu_latency_s);
  }
  startStreaming(io);
  stop_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  std::ostringstream d;
  d << "RealSense " << (camera->product.empty() ? options.usb_id : camera->product) << " serial "
    << (camera->serial.empty() ? "?" : camera->serial) << " (USB " << camera->bus_port << "): " << video_->path()
    << " " << options.width << "x" << options.height << " " << data::toString(format_) << " " << options.fps << " Hz";
  if (meta_) d << " + metadata " << meta_->path();
  if (accel_) d << ", accel " << accel_->devPath() << " " << accel_->rateHz() << " Hz";
  if (gyro_) d << ", gyro " << gyro_->devPath() << " " << gyro_->rateHz() << " Hz";
  description_ = d.str();
  last_frame_arrival_ = last_imu_arrival_ = monotonicNs();
}

void D435iSource::openCamera(const UsbCamera& camera, V4l2Io& io) {
  const std::vector<VideoNodeInfo> nodes = inspectVideoNodes(io, camera);
  const D4xxNodes chosen = selectD4xxNodes(nodes, options_.stream);
  if (chosen.video < 0) {
    std::string what = "no " + options_.stream + " node (";
    what += options_.stream == "infrared" ? "GREY or Y8I" : "YUYV";
    what += ") among the camera's V4L2 nodes:";
    for (const VideoNodeInfo& n : nodes) what += " " + n.node.dev_path + (n.opened ? "" : " [" + n.error + "]");
    throw data::InputError(camera.usb_dir, 0, "d435i.stream", what + kGuide);
  }
  const VideoNodeInfo& node = nodes[static_cast<size_t>(chosen.video)];
  // The pixel format: the one asked for, or (auto) GREY, else Y8I, at the size and rate asked for.
  std::vector<data::PixelFormat> candidates;
  if (options_.format == "grey") candidates = {data::PixelFormat::kGrey};
  else if (options_.format == "y8i") candidates = {data::PixelFormat::kY8i};
  else if (options_.format == "yuyv" || options_.stream == "color") candidates = {data::PixelFormat::kYuyv};
  else candidates = {data::PixelFormat::kGrey, data::PixelFormat::kY8i};
  bool found = false;
  std::string offered;
  for (data::PixelFormat f : candidates) {
    for (const V4l2FormatInfo& info : node.formats) {
      if (info.fourcc != data::fourcc(f)) continue;
      offered += (offered.empty() ? "" : "; ") + data::toString(f) + ": " + sizesText(info);
      if (!found && offers(info, options_.width, options_.height, options_.fps)) {
        format_ = f;
        found = true;
      }
    }
  }
  if (!found)
    throw data::InputError(node.node.dev_path, 0, "d435i.width/height/fps",
                           std::to_string(options_.width) + "x" + std::to_string(options_.height) + " at " +
                               std::to_string(static_cast<int>(options_.fps)) + " Hz is not offered in " +
                               options_.format + " format; the node offers " + (offered.empty() ? "none of them" : offered));
  video_ = std::make_unique<V4l2Stream>(io, node.node.dev_path);
  if (!video_->setVideoFormat(data::fourcc(format_), options_.width, options_.height))
    throw data::InputError(node.node.dev_path, 0, "d435i.format",
                           "the driver refused " + data::toString(format_) + " " + std::to_string(options_.width) + "x" +
                               std::to_string(options_.height));
  const double rate = video_->setFrameRate(options_.fps);
  if (rate > 0 && std::abs(rate - options_.fps) > 0.5)
    std::cerr << "warning: d435i: " << node.node.dev_path << " runs at " << rate << " Hz, not " << options_.fps << "\n";
  if (options_.stream == "color")
    std::cerr << "warning: d435i: the colour camera has a rolling shutter: rows are exposed over ~"
              << "a frame's readout, which the VIO models as one instant; use the infrared stream for accuracy\n";
  if (options_.metadata && chosen.meta >= 0) {
    meta_ = std::make_unique<V4l2Stream>(io, nodes[static_cast<size_t>(chosen.meta)].node.dev_path);
    if (!meta_->setMetaFormat(kMetaFormatD4xx) && !meta_->setMetaFormat(kMetaFormatUvc)) {
      std::cerr << "warning: d435i: " << meta_->path() << " accepts neither the D4XX nor the UVCH metadata format\n";
      meta_.reset();
    }
  }
  if (!meta_)
    std::cerr << "warning: d435i: no metadata node" << (options_.metadata ? "" : " (metadata: false)")
              << ": frames are stamped by the host when they arrive, after exposure and readout, and the IMU by the "
                 "camera: keep estimator.estimate_time_offset on\n";
  stats_.device_clock = meta_ != nullptr;
}

void D435iSource::startStreaming(V4l2Io& io) {
  applyControls(io);
  try {
    if (meta_) meta_->start(options_.buffers + 2);  // metadata first, so no frame misses its buffer
    video_->start(options_.buffers);
  } catch (...) {
    restoreControls();
    throw;
  }
}

void D435iSource::restoreControls() {
  if (restore_emitter_ >= 0 && controls_) controls_->setEmitter(static_cast<uint8_t>(restore_emitter_));
  restore_emitter_ = -1;
}

void D435iSource::applyControls(V4l2Io& io) {
  controls_ = std::make_unique<D4xxControls>(io, video_->fd(), video_->path());
  D4xxControls& c = *controls_;
  if (options_.stream == "infrared") {
    uint8_t mode = 0;
    const bool known = c.readEmitter(&mode);
    if (options_.emitter != "keep") {
      const uint8_t want = options_.emitter == "off" ? 0 : 1;
      if (!c.setEmitter(want))
        std::cerr << "warning: d435i: could not turn the emitter " << options_.emitter << ": " << c.error()
                  << (want == 0 ? "; its dot pattern will be on the infrared images" : "") << "\n";
      else if (known && mode != want)
        restore_emitter_ = mode;
    }
    if (options_.exposure_us > 0) {
      if (!c.setAutoExposure(false) || !c.setExposureUs(static_cast<uint32_t>(options_.exposure_us)))
        std::cerr << "warning: d435i: manual exposure " << options_.exposure_us << " us: " << c.error() << "\n";
      if (options_.gain > 0 && !c.setGain(options_.gain)) std::cerr << "warning: d435i: " << c.error() << "\n";
    } else if (!c.setAutoExposure(true)) {
      std::cerr << "warning: d435i: auto exposure: " << c.error() << "\n";
    }
  } else if (std::string error; !setUvcExposure(io, video_->fd(), options_.exposure_us, options_.gain, &error)) {
    std::cerr << "warning: d435i: " << video_->path() << ": " << error << "\n";
  }
}

void D435iSource::openImu(const UsbCamera& camera) {
  const UsbIioDevice* accel = nullptr;
  const UsbIioDevice* gyro = nullptr;
  for (const UsbIioDevice& d : camera.iio) {
    if (d.name == "accel_3d" && !accel) accel = &d;
    if (d.name == "gyro_3d" && !gyro) gyro = &d;
  }
  if (!accel || !gyro)
    throw data::InputError(camera.usb_dir, 0, "d435i.imu",
                           std::string("the camera has no ") + (!accel ? "accel_3d" : "gyro_3d") +
                               " IIO device (a D435 without IMU? a kernel without hid-sensor-accel-3d / "
                               "hid-sensor-gyro-3d?); set d435i.imu: false for images only" + kGuide);
  accel_ = std::make_unique<IioSensor>(*accel, "accel", options_.accel_hz, options_.iio_buffer_records);
  gyro_ = std::make_unique<IioSensor>(*gyro, "anglvel", options_.gyro_hz, options_.iio_buffer_records);
  gyro_lsb_deg_s_ = options_.gyro_lsb_deg_s > 0 ? options_.gyro_lsb_deg_s : data::realsenseGyroLsbDegPerSec(gyro_->axisRealBits());
  if (gyro_lsb_deg_s_ <= 0)
    throw data::InputError(gyro->sys_dir + "/scan_elements/in_anglvel_x_type", 0, "d435i.gyro_lsb_deg_s",
                           "the gyro sends " + std::to_string(gyro_->axisRealBits()) +
                               "-bit values, a firmware this program does not know: set d435i.gyro_lsb_deg_s");
  for (const IioSensor* s : {accel_.get(), gyro_.get()}) {
    const double want = s == accel_.get() ? options_.accel_hz : options_.gyro_hz;
    if (s->rateHz() > 0 && std::abs(s->rateHz() - want) > 0.5)
      std::cerr << "warning: d435i: " << s->devPath() << " runs at " << s->rateHz() << " Hz, not " << want << "\n";
  }
}

D435iSource::~D435iSource() {
  restoreControls();
  controls_.reset();
  meta_.reset();
  video_.reset();
  if (stop_fd_ >= 0) ::close(stop_fd_);
}

void D435iSource::stop() {
  stop_requested_ = true;
  const uint64_t one = 1;
  if (stop_fd_ >= 0 && ::write(stop_fd_, &one, sizeof(one)) < 0) {
    // nothing to do: the flag is seen at the next poll timeout
  }
}

void D435iSource::end(const std::string& reason) {
  if (ended_) return;
  ended_ = true;
  stop_reason_ = reason;
}

bool D435iSource::next(data::Measurement& m) {
  for (;;) {
    if (merge_.pop(monotonicNs(), &m, ended_)) {
      if (m.isFrame()) ++stats_.frames;
      else ++stats_.imu_samples;
      return true;
    }
    if (ended_) return false;
    // Wait for data, at most until the earliest pending measurement's latency bounds have passed.
    const int64_t deadline = merge_.releaseDeadlineNs();
    const int64_t wait_ms = deadline == INT64_MAX ? 100 : (deadline - monotonicNs()) / 1'000'000 + 1;
    pump(static_cast<int>(std::clamp<int64_t>(wait_ms, 0, 100)));
  }
}

void D435iSource::pump(int timeout_ms) {
  if (ended_) return;
  if (stop_requested_) {
    end("stopped on request");
    return;
  }
  std::vector<pollfd> fds;
  fds.push_back({stop_fd_, POLLIN, 0});
  fds.push_back({video_->fd(), POLLIN, 0});
  if (meta_) fds.push_back({meta_->fd(), POLLIN, 0});
  const size_t imu_at = fds.size();
  if (accel_) {
    fds.push_back({accel_->fd(), POLLIN, 0});
    fds.push_back({gyro_->fd(), POLLIN, 0});
  }
  const int r = ::poll(fds.data(), fds.size(), timeout_ms);
  if (r < 0 && errno != EINTR) {
    end(std::string("poll: ") + std::strerror(errno));
    return;
  }
  if (stop_requested_) {
    end("stopped on request");
    return;
  }
  const short ready = POLLIN | POLLERR | POLLHUP;
  // Metadata before video, so a frame finds its metadata when both came in the same wake-up.
  if (meta_ && (fds[2].revents & ready)) onMetadata();
  if (fds[1].revents & ready) onVideo();
  if (accel_ && (fds[imu_at].revents & ready)) onImu(*accel_, true);
  if (accel_ && (fds[imu_at + 1].revents & ready)) onImu(*gyro_, false);
  if (video_->gone()) end(video_->message());
  if (meta_ && meta_->gone()) end(meta_->message());
  if (accel_ && accel_->gone()) end(accel_->message());
  if (gyro_ && gyro_->gone()) end(gyro_->message());
  const int64_t now = monotonicNs();
  const int64_t stall = data::secToNs(options_.stall_timeout_s);
  if (now - last_frame_arrival_ > stall)
    end("no frame from " + video_->path() + " for " + std::to_string(options_.stall_timeout_s) +
        " s (USB bandwidth? try a USB 3 port, a lower resolution or rate)");
  if (gyro_ && now - last_imu_arrival_ > stall)
    end("no IMU sample from " + gyro_->devPath() + " or " + accel_->devPath() + " for " +
        std::to_string(options_.stall_timeout_s) + " s");
}

void D435iSource::onVideo() {
  V4l2Buffer buf;
  while (video_->dequeue(&buf)) {
    last_frame_arrival_ = monotonicNs();
    if (have_sequence_ && buf.sequence > last_sequence_ + 1) stats_.frames_lost_by_driver += buf.sequence - last_sequence_ - 1;
    have_sequence_ = true;
    last_sequence_ = buf.sequence;
    cv::Mat image, colour;
    bool ok = !buf.error && data::decodeGrey(format_, buf.data, buf.bytes, options_.width, options_.height,
                                             video_->bytesPerLine(), &image);
    if (ok && format_ == data::PixelFormat::kYuyv)
      ok = data::decodeYuyvToBgr(buf.data, buf.bytes, options_.width, options_.height, video_->bytesPerLine(), &colour);
    const int64_t host_ns = buf.timestamp_ns;
    const uint32_t sequence = buf.sequence;
    video_->requeue(buf);
    if (!ok) {
      ++stats_.frames_bad;
      metadata_waiting_.erase(sequence);
      continue;
    }
    if (!meta_) {
      queueFrame(host_ns + image_time_shift_ns_, image, colour);
      continue;
    }
    const auto m = metadata_waiting_.find(sequence);
    if (m != metadata_waiting_.end()) {
      frames_unmatched_in_a_row_ = 0;
      frameWithMetadata(image, colour, m->second);
      metadata_waiting_.erase(metadata_waiting_.begin(), std::next(m));  // older ones lost their frame
    } else {
      frames_waiting_[sequence] = {image, colour, host_ns};
    }
  }
  // Frames older than the newest metadata can no longer be matched; keep at most a few waiting.
  while (!frames_waiting_.empty() &&
         ((!metadata_waiting_.empty() && frames_waiting_.begin()->first < metadata_waiting_.rbegin()->first) ||
          frames_waiting_.size() > 3)) {
    frames_waiting_.erase(frames_waiting_.begin());
    ++stats_.frames_without_metadata;
    if (++frames_unmatched_in_a_row_ >= kMetadataGiveUp) stopUsingMetadata();
  }
}

void D435iSource::stopUsingMetadata() {
  // A metadata node that streams nothing the frames can be matched with (its frame counter is not
  // the video node's, or it delivers nothing) must not silence the camera: the driver's stamps then.
  std::cerr << "warning: d435i: " << kMetadataGiveUp << " frames in a row found no metadata on " << meta_->path()
            << ": stamping frames on arrival from now on (keep estimator.estimate_time_offset on)\n";
  meta_.reset();
  stats_.device_clock = false;
  for (auto& [sequence, frame] : frames_waiting_) queueFrame(frame.host_ns + image_time_shift_ns_, frame.image, frame.colour);
  frames_waiting_.clear();
  metadata_waiting_.clear();
}

void D435iSource::onMetadata() {
  V4l2Buffer buf;
  while (meta_->dequeue(&buf)) {
    data::UvcFrameMetadata meta;
    const bool ok = data::parseUvcMetadata(buf.data, buf.bytes, &meta);
    const uint32_t sequence = buf.sequence;
    meta_->requeue(buf);
    if (!ok) continue;  // its frame will wait, then be counted without metadata
    if (meta.has_pts) clock_.addPair(unwrapper_.unwrap(meta.pts_us), meta.host_ns);  // readout start vs arrival
    const auto f = frames_waiting_.find(sequence);
    if (f != frames_waiting_.end()) {
      frames_unmatched_in_a_row_ = 0;
      frameWithMetadata(f->second.image, f->second.colour, meta);
      stats_.frames_without_metadata += static_cast<size_t>(std::distance(frames_waiting_.begin(), f));
      frames_waiting_.erase(frames_waiting_.begin(), std::next(f));
    } else {
      metadata_waiting_[sequence] = meta;
      while (metadata_waiting_.size() > 4) metadata_waiting_.erase(metadata_waiting_.begin());
    }
  }
}

void D435iSource::frameWithMetadata(const cv::Mat& image, const cv::Mat& colour, const data::UvcFrameMetadata& meta) {
  uint32_t device_us = 0;
  if (meta.has_sensor_timestamp) {
    device_us = meta.sensor_timestamp_us;
  } else if (meta.has_pts) {
    if (!warned_pts_)
      std::cerr << "warning: d435i: no mid-exposure stamp in the metadata (plain UVCH format?): frames are stamped "
                   "at readout start; keep estimator.estimate_time_offset on\n";
    warned_pts_ = true;
    device_us = meta.pts_us;
  } else {
    ++stats_.frames_without_metadata;
    return;
  }
  const int64_t device = unwrapper_.unwrap(device_us);
  if (!meta.has_pts) clock_.addPair(device, meta.host_ns);  // no readout stamp to pair with the arrival
  queueFrame(clock_.toHostNs(device) + image_time_shift_ns_, image, colour);
}

bool D435iSource::inWarmup(int64_t t_ns) {
  if (warmup_until_ == INT64_MIN) warmup_until_ = t_ns + data::secToNs(options_.clock_warmup_s);
  if (t_ns >= warmup_until_) return false;
  ++stats_.warmup_discarded;
  return true;
}

void D435iSource::queueFrame(int64_t t_ns, const cv::Mat& image, const cv::Mat& colour) {
  if (inWarmup(t_ns)) return;
  data::Measurement m;
  m.type = data::Measurement::Type::kFrame;
  m.frame.t_ns = t_ns;
  m.frame.image = image;
  m.frame.colour = colour;
  merge_.push(frame_stream_, std::move(m));
}

void D435iSource::onImu(IioSensor& sensor, bool accel) {
  std::vector<IioSample> samples;
  sensor.read(&samples);
  if (samples.empty()) return;
  const int64_t now = monotonicNs();
  last_imu_arrival_ = now;
  if (imu_stamp_kind_ == 0) {
    // Kernels whose hid-sensor drivers take the HID timestamp give the device's microsecond
    // counter (in ns); older ones stamp records with the host clock named in sysfs.
    const std::string& name = sensor.hostStampClock();
    const clockid_t id = name == "monotonic" ? CLOCK_MONOTONIC
                         : name == "monotonic_raw" ? CLOCK_MONOTONIC_RAW
                         : name == "boottime" ? CLOCK_BOOTTIME
                                              : CLOCK_REALTIME;
    const int64_t host_minus_monotonic = clockMinusMonotonicNs(id);
    if (std::llabs(samples.front().timestamp_ns - (now + host_minus_monotonic)) < 10'000'000'000) {
      imu_stamp_kind_ = 2;
      imu_host_offset_ns_ = host_minus_monotonic;
      std::cerr << "warning: d435i: the IIO records carry host stamps (" << name
                << "), not the camera's (a kernel whose hid-sensor drivers ignore the HID timestamp): IMU and frames "
                   "are on different clocks; keep estimator.estimate_time_offset on\n";
    } else {
      imu_stamp_kind_ = 1;
    }
    stats_.imu_device_stamps = imu_stamp_kind_ == 1;
  }
  int64_t newest_device = 0;
  for (const IioSample& s : samples) {
    int64_t t;
    if (imu_stamp_kind_ == 1) {
      newest_device = unwrapper_.unwrap(static_cast<uint64_t>(s.timestamp_ns / 1000));
      t = newest_device * 1000;  // device time, ns; mapped once united
    } else {
      t = s.timestamp_ns - imu_host_offset_ns_;
    }
    int64_t& last = accel ? last_accel_t_ : last_gyro_t_;
    if (t <= last) {
      ++stats_.imu_out_of_order;
      continue;
    }
    last = t;
    if (accel) {
      ++stats_.accel_samples;
      unifier_.addAccel(t, data::realsenseAccelToBody(s.counts));
    } else {
      ++stats_.gyro_samples;
      unifier_.addGyro(t, data::realsenseGyroToBody(s.counts, gyro_lsb_deg_s_));
    }
  }
  if (imu_stamp_kind_ == 1) clock_.addPair(newest_device, now);  // the newest sample just arrived
  queueUnitedImu();
}

void D435iSource::queueUnitedImu() {
  data::ImuSample s;
  while (unifier_.pop(&s)) {
    if (imu_stamp_kind_ == 1) s.t_ns = clock_.toHostNs(s.t_ns / 1000) + (s.t_ns % 1000);
    if (inWarmup(s.t_ns)) continue;
    data::Measurement m;
    m.type = data::Measurement::Type::kImu;
    m.imu = s;
    merge_.push(imu_stream_, std::move(m));
  }
}

data::SourceCounts D435iSource::counts() const {
  const D435iStats s = stats();
  data::SourceCounts c;
  c.frames_lost = s.frames_bad + s.frames_without_metadata + s.frames_lost_by_driver;  // taken, never whole here
  c.late_dropped = s.frames_late + s.imu_late;
  c.imu_dropped = s.imu_out_of_order;
  c.unmatched_gyro = s.gyro_unmatched;
  return c;
}

D435iStats D435iSource::stats() const {
  D435iStats s = stats_;
  s.clock_drift_ppm = clock_.driftPpm();
  s.gyro_unmatched = unifier_.unmatched();
  s.frames_late = merge_.late(frame_stream_) + merge_.outOfOrder(frame_stream_);
  if (imu_stream_ >= 0) {
    s.imu_late = merge_.late(imu_stream_);
    s.imu_out_of_order += merge_.outOfOrder(imu_stream_);
  }
  return s;
}

data::OpenedSequence openD435i(const D435iOptions& options, const std::vector<std::string>& calibration, V4l2Io& io) {
  data::OpenedSequence out;
  data::RigCamera camera = options.camera;
  data::RigImu imu;
  imu.noise = options.imu_noise;
  std::string camera_from = "the run config's d435i.cam0 (placeholder intrinsics: calibrate your unit)";
  std::string imu_from = "the run config's d435i.imu0";
  if (!calibration.empty()) {
    data::RigCalibration rig = data::readCalibrationFiles(calibration);
    data::reportIgnoredKeys(rig, std::cerr);
    if (!rig.cameras.empty()) {
      camera = rig.cameras.front();
      camera_from = camera.source;
    }
    if (rig.has_imu) {
      imu = rig.imu;
      imu_from = imu.source;
      data::resolvePerSampleNoise(imu, options.gyro_hz);  // VINS' figures, at the gyro's rate
    }
    out.calibration_files = rig.files;
  }
  if (camera.camera.width != options.width || camera.camera.height != options.height)
    throw data::InputError(calibration.empty() ? std::string("d435i.cam0") : camera.source, 0, "resolution",
                           std::to_string(camera.camera.width) + "x" + std::to_string(camera.camera.height) +
                               " does not match the stream's " + std::to_string(options.width) + "x" +
                               std::to_string(options.height) + " (d435i.width/height)");
  out.camera = camera.camera;
  out.camera.rate_hz = options.fps;
  out.imu_noise = imu.noise;
  out.calibration_from = "camera: " + camera_from + "; IMU: " + imu_from;
  const int64_t shift_ns = data::secToNs(camera.time_offset_s);
  if (options.backend == "librealsense") out.source = openVispRealSense2(options, shift_ns);
  else out.source = std::make_unique<D435iSource>(options, io, shift_ns);
  out.source = data::correctImu(std::move(out.source), imu.intrinsics);
  if (calibration.empty() || camera_from.rfind("the run config", 0) == 0)  // once the camera is there
    std::cerr << "warning: d435i: camera intrinsics from " << camera_from << "\n";
  return out;
}

}  // namespace adugs::data

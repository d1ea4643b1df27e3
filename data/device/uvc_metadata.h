#pragma once
// The per-frame metadata a UVC camera's metadata node (/dev/videoN+1, V4L2_BUF_TYPE_META_CAPTURE,
// formats "UVCH" and, for RealSense D4xx, "D4XX") delivers next to each video buffer. Pure
// decoding of one metadata buffer.
//
// The buffer holds one or more blocks, each the kernel's struct uvc_meta_buf (little-endian,
// packed):
//   u64 ns      host CLOCK_MONOTONIC time [ns] at which the payload's first packet arrived
//   u16 sof     USB frame number
//   u8  length  bHeaderLength of the UVC payload header (counted from this byte)
//   u8  flags   bmHeaderInfo (0x04: PTS present, 0x08: SCR present, 0x80: end of header)
//   ... the rest of the payload header: PTS (u32) if flagged, SCR (u32 + u16) if flagged, then
//       vendor data. A D4xx sends PTS = its 32-bit microsecond counter when the readout started
//       ("frame timestamp") and then records of {u32 type, u32 size (with this 8-byte header)}:
//       the first, type 0x80000001 "capture timing", is
//         u32 version, u32 flags (bit 0 frame counter, 1 sensor timestamp, 2 readout time,
//         3 exposure, 4 frame interval, 5 pipe latency valid), u32 frame_counter,
//         u32 sensor_timestamp (middle of the exposure, same microsecond counter),
//         u32 readout_time, u32 exposure_time, u32 frame_interval, u32 pipe_latency (us)
// (layout as librealsense's src/metadata.h and the kernel's Documentation/.../metafmt-d4xx.rst).
#include <cstddef>
#include <cstdint>

namespace adugs::data {

// Device counter values are the raw 32-bit microsecond counter (wraps every 71.6 min).
struct UvcFrameMetadata {
  int64_t host_ns = 0;      // block's ns
  uint16_t sof = 0;
  uint8_t header_flags = 0;
  bool has_pts = false;
  uint32_t pts_us = 0;      // readout start, device clock
  bool has_capture_timing = false;  // the D4xx capture-timing record was found
  bool has_frame_counter = false;
  uint32_t frame_counter = 0;
  bool has_sensor_timestamp = false;
  uint32_t sensor_timestamp_us = 0;  // middle of the exposure, device clock
  bool has_exposure = false;
  uint32_t exposure_us = 0;
  uint32_t readout_us = 0, frame_interval_us = 0, pipe_latency_us = 0;  // 0 when not flagged
};

constexpr uint8_t kUvcHeaderPts = 0x04;
constexpr uint8_t kUvcHeaderScr = 0x08;
constexpr uint32_t kD4xxCaptureTimingId = 0x80000001u;
constexpr size_t kUvcMetaBlockHeaderBytes = 10;  // ns + sof, before `length`
constexpr size_t kD4xxCaptureTimingBytes = 40;   // the record with its 8-byte header

// Decodes the first block, taking the capture-timing record from the first block that has one.
// False when the buffer does not even hold one complete block header (nothing usable).
bool parseUvcMetadata(const uint8_t* data, size_t bytes, UvcFrameMetadata* out);

}  // namespace adugs::data

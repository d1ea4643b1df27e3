#pragma once
// Byte buffers as RealSense devices send them, built by the tests of the device decoders and by
// the fake device layer of the live-source tests (little-endian, packed, as on the wire).
#include <cstdint>
#include <cstring>
#include <vector>

namespace adugs::test {

inline void putLe(std::vector<uint8_t>* out, uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out->push_back(static_cast<uint8_t>((value >> (8 * i)) & 0xff));
}

struct D4xxMetadataFields {
  uint64_t host_ns = 0;
  uint16_t sof = 0;
  uint32_t pts_us = 0;
  bool capture_timing = true;  // append the D4xx capture-timing record
  uint32_t valid_flags = 0x3f;
  uint32_t frame_counter = 0;
  uint32_t sensor_timestamp_us = 0;
  uint32_t readout_us = 0, exposure_us = 0, frame_interval_us = 0, pipe_latency_us = 0;
};

// One uvc_meta_buf block: ns, sof, then the payload header (length, flags 0x8e = EOH|SCR|PTS|EOF,
// PTS, SCR) and the capture-timing record (type 0x80000001, size 40).
inline std::vector<uint8_t> d4xxMetadataBlock(const D4xxMetadataFields& f) {
  std::vector<uint8_t> b;
  putLe(&b, f.host_ns, 8);
  putLe(&b, f.sof, 2);
  const uint8_t length = static_cast<uint8_t>(12 + (f.capture_timing ? 40 : 0));
  b.push_back(length);
  b.push_back(0x8e);
  putLe(&b, f.pts_us, 4);
  putLe(&b, 0x12345678, 4);  // SCR source clock
  putLe(&b, 0x0102, 2);      // SCR SOF
  if (f.capture_timing) {
    putLe(&b, 0x80000001u, 4);
    putLe(&b, 40, 4);
    putLe(&b, 1, 4);  // version
    putLe(&b, f.valid_flags, 4);
    putLe(&b, f.frame_counter, 4);
    putLe(&b, f.sensor_timestamp_us, 4);
    putLe(&b, f.readout_us, 4);
    putLe(&b, f.exposure_us, 4);
    putLe(&b, f.frame_interval_us, 4);
    putLe(&b, f.pipe_latency_us, 4);
  }
  return b;
}

// One IIO record of a RealSense HID sensor: x, y, z stored in 32 bits (the low `real_bytes` bytes
// meaningful: 2 for old firmware, 4 for 5.16+), 4 bytes of padding, the 64-bit timestamp [ns].
inline std::vector<uint8_t> hidImuRecord(int32_t x, int32_t y, int32_t z, int64_t timestamp_ns, int real_bytes) {
  std::vector<uint8_t> r;
  for (int32_t v : {x, y, z}) {
    const uint32_t stored = real_bytes == 2 ? (static_cast<uint32_t>(v) & 0xffffu) | 0xabcd0000u  // junk above
                                            : static_cast<uint32_t>(v);
    putLe(&r, stored, 4);
  }
  putLe(&r, 0, 4);
  putLe(&r, static_cast<uint64_t>(timestamp_ns), 8);
  return r;
}

}  // namespace adugs::test

#include "data/device/uvc_metadata.h"

namespace adugs::data {
namespace {

uint16_t le16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
uint32_t le32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) | (static_cast<uint32_t>(p[2]) << 16) |
         (static_cast<uint32_t>(p[3]) << 24);
}
uint64_t le64(const uint8_t* p) { return static_cast<uint64_t>(le32(p)) | (static_cast<uint64_t>(le32(p + 4)) << 32); }

// The vendor records after the standard header of one block [header, header + length).
bool findCaptureTiming(const uint8_t* header, size_t length, UvcFrameMetadata* out) {
  const uint8_t flags = header[1];
  size_t offset = 2 + ((flags & kUvcHeaderPts) ? 4 : 0) + ((flags & kUvcHeaderScr) ? 6 : 0);
  while (offset + 8 <= length) {
    const uint8_t* record = header + offset;
    const uint32_t type = le32(record);
    const uint32_t size = le32(record + 4);
    if (size < 8 || offset + size > length) return false;  // not a record chain we understand
    if (type == kD4xxCaptureTimingId && size >= kD4xxCaptureTimingBytes) {
      const uint32_t valid = le32(record + 12);
      out->has_capture_timing = true;
      out->has_frame_counter = valid & (1u << 0);
      out->frame_counter = le32(record + 16);
      out->has_sensor_timestamp = valid & (1u << 1);
      out->sensor_timestamp_us = le32(record + 20);
      out->readout_us = (valid & (1u << 2)) ? le32(record + 24) : 0;
      out->has_exposure = valid & (1u << 3);
      out->exposure_us = le32(record + 28);
      out->frame_interval_us = (valid & (1u << 4)) ? le32(record + 32) : 0;
      out->pipe_latency_us = (valid & (1u << 5)) ? le32(record + 36) : 0;
      return true;
    }
    offset += size;
  }
  return false;
}

}  // namespace

bool parseUvcMetadata(const uint8_t* data, size_t bytes, UvcFrameMetadata* out) {
  if (!data || bytes < kUvcMetaBlockHeaderBytes + 2) return false;
  UvcFrameMetadata m;
  size_t block = 0;
  bool first = true;
  while (block + kUvcMetaBlockHeaderBytes + 2 <= bytes) {
    const uint8_t* header = data + block + kUvcMetaBlockHeaderBytes;  // starts at `length`
    const size_t length = header[0];
    if (length < 2 || block + kUvcMetaBlockHeaderBytes + length > bytes) break;  // cut block
    if (first) {
      m.host_ns = static_cast<int64_t>(le64(data + block));
      m.sof = le16(data + block + 8);
      m.header_flags = header[1];
      m.has_pts = (header[1] & kUvcHeaderPts) && length >= 6;
      if (m.has_pts) m.pts_us = le32(header + 2);
      first = false;
    }
    if (findCaptureTiming(header, length, &m)) break;
    block += kUvcMetaBlockHeaderBytes + length;
  }
  if (first) return false;
  *out = m;
  return true;
}

}  // namespace adugs::data

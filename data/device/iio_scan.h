#pragma once
// The record layout of a Linux IIO buffer (/dev/iio:deviceN) and the decoding of one record.
// Pure functions: the scan elements are read from sysfs by the caller.
//
// Each enabled scan element (scan_elements/in_NAME_en = 1) has
//   in_NAME_index  its position in the record (records hold enabled elements by rising index)
//   in_NAME_type   "[be|le]:[s|u]REAL/STORAGE[XREPEAT]>>SHIFT", e.g. "le:s16/32>>0": a signed
//                  16-bit value stored in 32 bits, little-endian, not shifted
// In the record every element starts at a multiple of its own storage size and the record is
// padded to a multiple of its largest element (the kernel's iio_compute_scan_bytes): e.g.
// x, y, z as le:s32/32 and timestamp as le:s64/64 give 3 x 4 bytes, 4 padding, 8 = 24 bytes.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace adugs::data {

struct IioScanType {
  bool big_endian = false;
  bool is_signed = false;
  int real_bits = 0;     // meaningful bits, 1..64
  int storage_bits = 0;  // 8, 16, 32 or 64
  int shift = 0;         // right shift before masking to real_bits
  int repeat = 1;        // X3: three values of storage_bits in a row
};

// Parses the text of an in_NAME_type file (trailing newline allowed). Throws InputError naming
// `file` (the sysfs path, for the message) on anything else.
IioScanType parseIioScanType(const std::string& text, const std::string& file);

struct IioChannel {
  std::string name;  // "accel_x", "timestamp" (the NAME of in_NAME_*)
  int index = 0;
  IioScanType type;
  size_t offset = 0;  // byte offset in the record, set by layoutIioRecord
};

// Sorts the ENABLED channels by index, sets their offsets and returns the record size in bytes.
// Duplicate indices are an InputError naming `device`.
size_t layoutIioRecord(std::vector<IioChannel>* channels, const std::string& device);

// The channel's value in a record (shifted, masked, sign-extended). repeat > 1: element `element`.
int64_t decodeIioValue(const uint8_t* record, const IioChannel& channel, int element = 0);

}  // namespace adugs::data

#include "data/device/iio_scan.h"

#include <algorithm>
#include <cstdio>

#include "data/input_error.h"

namespace adugs::data {
namespace {

size_t elementBytes(const IioScanType& t) { return static_cast<size_t>(t.storage_bits / 8); }

}  // namespace

IioScanType parseIioScanType(const std::string& text_in, const std::string& file) {
  std::string text = text_in;
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  auto fail = [&](const std::string& what) -> IioScanType {
    throw InputError(file, 0, "type", "'" + text + "': " + what +
                                          " (expected e.g. le:s16/32>>0: endianness, sign, real/storage bits, shift)");
  };
  // sscanf's %u takes "-1" as 4294967295, which would wrap the bit checks below.
  if (text.find_first_of("-+ ") != std::string::npos) return fail("not an IIO scan type");
  IioScanType t;
  char endian[3] = {0, 0, 0};
  char sign = 0;
  unsigned real = 0, storage = 0, repeat = 1, shift = 0;
  int used = 0;
  // With a repeat count ("le:s16/16X3>>0") or without; %n checks that nothing follows.
  const bool with_repeat = std::sscanf(text.c_str(), "%2[bl]e:%c%u/%uX%u>>%u%n", endian, &sign, &real, &storage,
                                       &repeat, &shift, &used) == 6 && static_cast<size_t>(used) == text.size();
  if (!with_repeat) {
    repeat = 1;
    used = 0;
    const bool plain = std::sscanf(text.c_str(), "%2[bl]e:%c%u/%u>>%u%n", endian, &sign, &real, &storage, &shift,
                                   &used) == 5 && static_cast<size_t>(used) == text.size();
    if (!plain) return fail("not an IIO scan type");
  }
  if (endian[1] != 0 || (endian[0] != 'b' && endian[0] != 'l')) return fail("endianness must be le or be");
  if (sign != 's' && sign != 'u') return fail("sign must be s or u");
  if (storage != 8 && storage != 16 && storage != 32 && storage != 64) return fail("storage bits must be 8, 16, 32 or 64");
  if (real == 0 || real > storage) return fail("real bits must be 1..storage bits");
  if (shift > storage - real) return fail("shift + real bits exceed the storage bits");
  if (repeat == 0 || repeat > 64) return fail("repeat must be 1..64");
  t.big_endian = endian[0] == 'b';
  t.is_signed = sign == 's';
  t.real_bits = static_cast<int>(real);
  t.storage_bits = static_cast<int>(storage);
  t.shift = static_cast<int>(shift);
  t.repeat = static_cast<int>(repeat);
  return t;
}

size_t layoutIioRecord(std::vector<IioChannel>* channels, const std::string& device) {
  std::sort(channels->begin(), channels->end(), [](const IioChannel& a, const IioChannel& b) { return a.index < b.index; });
  size_t bytes = 0, largest = 1;
  for (size_t i = 0; i < channels->size(); ++i) {
    IioChannel& c = (*channels)[i];
    if (i > 0 && (*channels)[i - 1].index == c.index)
      throw InputError(device, 0, "scan_elements", "channels '" + (*channels)[i - 1].name + "' and '" + c.name +
                                                       "' share index " + std::to_string(c.index));
    const size_t align = elementBytes(c.type);  // storage sizes are powers of two
    bytes = (bytes + align - 1) / align * align;
    c.offset = bytes;
    bytes += align * static_cast<size_t>(c.type.repeat);
    largest = std::max(largest, align);
  }
  return (bytes + largest - 1) / largest * largest;
}

int64_t decodeIioValue(const uint8_t* record, const IioChannel& channel, int element) {
  const IioScanType& t = channel.type;
  const size_t n = elementBytes(t);
  const uint8_t* p = record + channel.offset + n * static_cast<size_t>(element);
  uint64_t raw = 0;
  for (size_t i = 0; i < n; ++i) {
    const uint64_t byte = t.big_endian ? p[i] : p[n - 1 - i];
    raw = (raw << 8) | byte;
  }
  raw >>= t.shift;
  if (t.real_bits < 64) {
    raw &= (uint64_t{1} << t.real_bits) - 1;
    if (t.is_signed && (raw >> (t.real_bits - 1)) & 1) raw |= ~uint64_t{0} << t.real_bits;  // sign-extend
  }
  return static_cast<int64_t>(raw);
}

}  // namespace adugs::data

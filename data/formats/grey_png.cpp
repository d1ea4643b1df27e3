#include "data/formats/grey_png.h"

#include <libdeflate.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

namespace adugs::data {
namespace {

constexpr uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

uint32_t bigEndian32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}

struct Header {
  uint32_t width = 0, height = 0;
  int bytes_per_pixel = 0;  // 1 or 2
};

// The IHDR chunk's fields (PNG spec 11.2.2) when they describe the shape decoded here.
bool readHeader(const uint8_t* head, size_t size, Header* h) {
  if (size < kGreyPngHeadBytes || std::memcmp(head, kSignature, 8) != 0) return false;
  const uint8_t* ihdr = head + 8;
  if (bigEndian32(ihdr) != 13 || std::memcmp(ihdr + 4, "IHDR", 4) != 0) return false;
  const uint8_t* f = ihdr + 8;
  h->width = bigEndian32(f);
  h->height = bigEndian32(f + 4);
  const uint8_t depth = f[8], colour = f[9], compression = f[10], filter = f[11], interlace = f[12];
  if (colour != 0 || (depth != 8 && depth != 16) || compression != 0 || filter != 0 || interlace != 0)
    return false;
  h->bytes_per_pixel = depth / 8;
  const uint64_t bytes = uint64_t{h->width} * h->height * static_cast<uint64_t>(h->bytes_per_pixel);
  return h->width > 0 && h->height > 0 && h->width < (1u << 31) && h->height < (1u << 31) &&
         bytes <= kMaxImageBytes;
}

// The Paeth predictor (PNG spec 9.4): of left a, up b and up-left c, the one closest to a + b - c.
inline int paeth(int a, int b, int c) {
  const int pa = std::abs(b - c), pb = std::abs(a - c), pc = std::abs(a + b - 2 * c);
  return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

// Undoes one row's filter in place (PNG spec 9.2). `prior` is the row above, already unfiltered,
// or null for the first row, where it reads as zeros: Up is then None, Paeth is Sub. The first
// `bpp` bytes have no left neighbour (zero): Average adds half the byte above, Paeth the byte above.
// The 8-bit loops carry the left neighbour in a register: read back from the row just written, it
// waited on the store every byte (the decoder ran slower than libpng on EuRoC's Paeth rows).
bool unfilterRow(int type, uint8_t* row, const uint8_t* prior, size_t n, size_t bpp) {
  if (!prior && type == 2) type = 0;
  if (!prior && type == 4) type = 1;
  switch (type) {
    case 0:
      return true;
    case 1:
      if (bpp == 1) {
        uint8_t left = row[0];
        for (size_t i = 1; i < n; ++i) row[i] = left = static_cast<uint8_t>(row[i] + left);
        return true;
      }
      for (size_t i = bpp; i < n; ++i) row[i] = static_cast<uint8_t>(row[i] + row[i - bpp]);
      return true;
    case 2:
      for (size_t i = 0; i < n; ++i) row[i] = static_cast<uint8_t>(row[i] + prior[i]);
      return true;
    case 3:
      if (!prior) {
        for (size_t i = bpp; i < n; ++i) row[i] = static_cast<uint8_t>(row[i] + (row[i - bpp] >> 1));
        return true;
      }
      for (size_t i = 0; i < bpp; ++i) row[i] = static_cast<uint8_t>(row[i] + (prior[i] >> 1));
      if (bpp == 1) {
        int left = row[0];
        for (size_t i = 1; i < n; ++i) row[i] = static_cast<uint8_t>(left = static_cast<uint8_t>(row[i] + ((left + prior[i]) >> 1)));
        return true;
      }
      for (size_t i = bpp; i < n; ++i)
        row[i] = static_cast<uint8_t>(row[i] + ((row[i - bpp] + prior[i]) >> 1));
      return true;
    case 4:
      for (size_t i = 0; i < bpp; ++i) row[i] = static_cast<uint8_t>(row[i] + prior[i]);
      if (bpp == 1) {
        int left = row[0], up_left = prior[0];
        for (size_t i = 1; i < n; ++i) {
          const int up = prior[i];
          left = static_cast<uint8_t>(row[i] + paeth(left, up, up_left));
          row[i] = static_cast<uint8_t>(left);
          up_left = up;
        }
        return true;
      }
      for (size_t i = bpp; i < n; ++i)
        row[i] = static_cast<uint8_t>(row[i] + paeth(row[i - bpp], prior[i], prior[i - bpp]));
      return true;
    default:
      return false;
  }
}

// Buffers kept per thread: a frame's zlib stream and its inflated rows (~0.4 MB each for EuRoC),
// which would otherwise be mapped and unmapped for every frame.
struct Scratch {
  std::unique_ptr<libdeflate_decompressor, void (*)(libdeflate_decompressor*)> inflater{
      libdeflate_alloc_decompressor(), libdeflate_free_decompressor};
  std::vector<uint8_t> stream, rows;
};

// The unfiltered rows (each after its filter byte) as the image cv::imread gives.
void writeOut(const uint8_t* rows, size_t stride, const Header& h, ImageRead mode, cv::Mat& out) {
  const size_t row_bytes = size_t{h.width} * static_cast<size_t>(h.bytes_per_pixel);
  const bool sixteen = h.bytes_per_pixel == 2 && mode == ImageRead::kUnchanged;
  out.create(static_cast<int>(h.height), static_cast<int>(h.width), sixteen ? CV_16UC1 : CV_8UC1);
  for (int y = 0; y < out.rows; ++y) {
    const uint8_t* row = rows + static_cast<size_t>(y) * stride + 1;
    if (h.bytes_per_pixel == 1) {
      std::memcpy(out.ptr<uint8_t>(y), row, row_bytes);
    } else if (sixteen) {  // PNG stores 16-bit samples big-endian
      uint16_t* o = out.ptr<uint16_t>(y);
      for (int x = 0; x < out.cols; ++x) o[x] = static_cast<uint16_t>((row[2 * x] << 8) | row[2 * x + 1]);
    } else {  // the high byte, as libpng's strip_16 and cv::imread
      uint8_t* o = out.ptr<uint8_t>(y);
      for (int x = 0; x < out.cols; ++x) o[x] = row[2 * x];
    }
  }
}

bool decode(const uint8_t* bytes, size_t size, ImageRead mode, cv::Mat& out, Scratch& scratch) {
  Header h;
  if (!readHeader(bytes, size, &h) || !scratch.inflater) return false;
  // Chunks: length, type, data, CRC over type and data. IDATs must be consecutive; IEND ends.
  scratch.stream.clear();
  bool idat_seen = false, idat_done = false, end_seen = false;
  size_t pos = 8;
  while (!end_seen) {
    if (size - pos < 12) return false;  // truncated
    const uint32_t length = bigEndian32(bytes + pos);
    if (length > (1u << 31) || size - pos - 12 < length) return false;
    const uint8_t* type = bytes + pos + 4;
    const uint8_t* data = type + 4;
    if (libdeflate_crc32(0, type, length + 4) != bigEndian32(data + length)) return false;
    const bool is_idat = std::memcmp(type, "IDAT", 4) == 0;
    if (is_idat) {
      if (idat_done) return false;
      idat_seen = true;
      scratch.stream.insert(scratch.stream.end(), data, data + length);
    } else {
      idat_done = idat_seen;
      if (std::memcmp(type, "IEND", 4) == 0)
        end_seen = true;
      else if (pos > 8 && !(type[0] & 0x20))  // another critical chunk (PLTE, a second IHDR)
        return false;
    }
    pos += 12 + length;
  }
  if (!idat_seen) return false;

  const size_t row_bytes = size_t{h.width} * static_cast<size_t>(h.bytes_per_pixel);
  const size_t stride = row_bytes + 1;  // each row starts with its filter type
  scratch.rows.resize(stride * h.height);
  // Without an actual-size pointer libdeflate requires exactly this many bytes, and checks the
  // stream's Adler-32.
  if (libdeflate_zlib_decompress(scratch.inflater.get(), scratch.stream.data(), scratch.stream.size(),
                                 scratch.rows.data(), scratch.rows.size(), nullptr) != LIBDEFLATE_SUCCESS)
    return false;
  const uint8_t* prior = nullptr;
  for (uint32_t y = 0; y < h.height; ++y) {
    uint8_t* row = scratch.rows.data() + y * stride;
    if (!unfilterRow(row[0], row + 1, prior, row_bytes, static_cast<size_t>(h.bytes_per_pixel))) return false;
    prior = row + 1;
  }
  writeOut(scratch.rows.data(), stride, h, mode, out);
  return true;
}

}  // namespace

bool isGreyPng(const uint8_t* head, size_t size) {
  Header h;
  return readHeader(head, size, &h);
}

bool decodeGreyPng(const uint8_t* bytes, size_t size, ImageRead mode, cv::Mat& out) {
  thread_local Scratch scratch;
  const bool decoded = decode(bytes, size, mode, out, scratch);
  for (std::vector<uint8_t>* buffer : {&scratch.stream, &scratch.rows})
    if (buffer->capacity() > kKeptBufferBytes) std::vector<uint8_t>().swap(*buffer);
  return decoded;
}

}  // namespace adugs::data

#pragma once
// The datasets' camera frames, grey non-interlaced PNGs of 8 or 16 bits (EuRoC, TUM-VI, what
// `adugs sim` and `adugs record` write), decoded with libdeflate instead of libpng + zlib. zlib's
// inflate was 11 % of a whole `adugs run` on the simulator's frames (its byte-at-a-time copies of
// run-length matches); libdeflate inflates the same stream ~3x faster (doc/results.md, "PNG
// decoding"). Only this one shape is decoded here: every other PNG, and any file in which
// something does not check out, is left to libpng (image_file.cpp), which decodes it or says what
// is wrong with it.
#include <cstddef>
#include <cstdint>

#include <opencv2/core.hpp>

#include "data/media/media_module.h"

namespace adugs::data {

// The bytes a caller needs to see to know whether a PNG has that shape: signature and IHDR.
constexpr size_t kGreyPngHeadBytes = 33;

// Larger than any camera's frame (an 8K 16-bit colour image is 200 MB); a corrupt header asking
// for more is refused before allocating (image_file.cpp), or left to libpng, which refuses it by
// name (grey_png.cpp).
constexpr uint64_t kMaxImageBytes = uint64_t{512} << 20;

// Callers keep their per-thread read buffers below this (a frame is well under 1 MB; one huge
// image should not stay in a thread's memory).
constexpr size_t kKeptBufferBytes = size_t{16} << 20;

// True when `head` (the first bytes of a file) is a PNG signature followed by the IHDR of a grey,
// non-interlaced, 8- or 16-bit image: a file worth reading whole for decodeGreyPng.
bool isGreyPng(const uint8_t* head, size_t size);

// Decodes a whole PNG file held in memory when it has that shape and every chunk's CRC, the zlib
// stream, its checksum and every row's filter check out: kGrey gives CV_8UC1 (of 16 bits the high
// byte, as cv::imread), kUnchanged CV_8UC1 or CV_16UC1. Returns false, `out` untouched, otherwise.
// Ancillary chunks are skipped: none of them changes a grey image's pixels as adugs reads them.
bool decodeGreyPng(const uint8_t* bytes, size_t size, ImageRead mode, cv::Mat& out);

}  // namespace adugs::data

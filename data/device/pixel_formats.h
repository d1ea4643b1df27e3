#pragma once
// Decoding the V4L2 pixel formats a RealSense D4xx (or any UVC camera) delivers into the 8-bit
// grey image the front-end tracks. Pure functions on the bytes of one captured buffer.
//
//   GREY  8 bits per pixel (the D4xx's left infrared imager, "Y8")
//   Y8I   16 bits per pixel: the left infrared pixel in the low (first) byte, the right one in the
//         high (second) byte of each little-endian pair (both imagers of one exposure)
//   YUYV  4:2:2, Y0 U Y1 V per two pixels: the luma bytes are the grey image (the D4xx colour
//         camera, a rolling shutter)
//
// `bytes_per_line` is V4L2's v4l2_pix_format.bytesperline (rows may be padded; 0 = packed).
// Each returns false, leaving the outputs alone, when the buffer holds fewer bytes than the image
// needs (a truncated or erroneous buffer): the caller drops the frame and counts it.
#include <cstddef>
#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

namespace adugs::data {

enum class PixelFormat { kGrey, kY8i, kYuyv };

// The V4L2 fourcc of each format ("GREY", "Y8I ", "YUYV") and back; fromFourcc returns false for
// any other code.
uint32_t fourcc(PixelFormat format);
bool pixelFormatFromFourcc(uint32_t code, PixelFormat* format);
// "GREY", "Y8I", "YUYV" for messages; fourccText prints any code ("Z16 " -> "Z16").
std::string toString(PixelFormat format);
std::string fourccText(uint32_t code);

// Bytes per pixel of the format (GREY 1, Y8I 2, YUYV 2).
int bytesPerPixel(PixelFormat format);

// The left (or only) image as CV_8UC1 (a copy: the buffer may be reused at once).
bool decodeGrey(PixelFormat format, const uint8_t* data, size_t bytes, int width, int height,
                int bytes_per_line, cv::Mat* grey);
// YUYV only: the colour image as CV_8UC3 BGR (for detectors and views).
bool decodeYuyvToBgr(const uint8_t* data, size_t bytes, int width, int height, int bytes_per_line, cv::Mat* bgr);
// Y8I only: both infrared images.
bool splitY8i(const uint8_t* data, size_t bytes, int width, int height, int bytes_per_line,
              cv::Mat* left, cv::Mat* right);

}  // namespace adugs::data

#pragma once
// Image files. PNG and JPEG, the formats of the datasets (EuRoC, TUM-VI, OpenLORIS), of bags'
// compressed images and of what adugs writes, are read and written here with libpng and libjpeg
// directly, giving the pixels cv::imread/cv::imwrite give (same transforms: 16-bit PNG to 8 by
// dropping the low byte, colour to grey with 0.299/0.587/0.114, BGR(A) order). Any other format
// goes through OpenCV's imgcodecs in libadugs_media.so (data/media/media_module.h), loaded only
// then: imgcodecs brings GDAL and ~36 MB into a process. EXIF orientation is not applied (camera
// frames are stored as the sensor saw them). Grey non-interlaced PNGs, the datasets' frames, are
// inflated with libdeflate (data/formats/grey_png.h), the same pixels ~2.5x faster.
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "data/media/media_module.h"

namespace adugs::data {

// kGrey: CV_8UC1 whatever the file holds. kUnchanged: as stored, like cv::IMREAD_UNCHANGED
// (8 or 16 bit; 1, 3 (BGR) or 4 (BGRA) channels; a palette or grey+alpha PNG with transparency
// gives BGRA). Throws InputError naming the file and what is wrong with it.
cv::Mat readImageFile(const std::string& path, ImageRead mode);

// The same for bytes in memory (a bag's sensor_msgs/CompressedImage). Returns an empty image
// and sets *why when they do not decode.
cv::Mat decodeImage(const std::vector<uint8_t>& bytes, ImageRead mode, std::string* why);

// Encodes by extension (".png", ".jpg"/".jpeg" at quality 95; others through the media module);
// 8-bit 1/3/4 channels, and 16-bit for PNG. Throws InputError naming `path_for_errors`.
std::vector<uint8_t> encodeImage(const std::string& extension, const cv::Mat& image,
                                 const std::string& path_for_errors);

// Encodes by path's extension and writes path + ".tmp" then renames it over path (a reader or
// a killed run never sees half an image). Throws InputError naming the file.
void writeImageFile(const std::string& path, const cv::Mat& image);

}  // namespace adugs::data

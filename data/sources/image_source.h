#pragma once
// Images for calibration, from
//   - an EuRoC/ASL camera folder (data.csv with "#timestamp [ns],filename" + data/),
//   - a folder of images (png, jpg, jpeg, pgm, ppm, bmp, tif, tiff; sorted by name; a name that
//     is all digits is taken as the timestamp in ns, otherwise frames are 1 s apart),
//   - a video file (any format OpenCV reads, through libadugs_media.so: data/media/media_module.h;
//     timestamps from the stream position).
// Frames come out as 8-bit gray, and as read in 8 bits (BGR or grey, for detectors). Missing or
// unreadable inputs are InputError.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace adugs::data {

class VideoInput;

struct ImageFrame {
  int64_t t_ns = 0;
  std::string name;  // file path, or "video.mp4#frame"
  cv::Mat gray;
  cv::Mat image;  // 8-bit BGR or grey (alpha dropped, 16 bits scaled as for gray)
};

class ImageSource {
 public:
  // every: keep one frame in N (N >= 1).
  explicit ImageSource(const std::string& path, int every = 1);
  ~ImageSource();
  // False at the end. An unreadable image file is an InputError.
  bool next(ImageFrame& frame);
  // Number of frames that will come out (videos: estimate from the frame count).
  size_t sizeHint() const;
  const std::string& kind() const { return kind_; }  // "euroc", "folder" or "video"

 private:
  std::string path_;
  std::string kind_;
  int every_ = 1;
  std::vector<std::pair<int64_t, std::string>> files_;
  size_t index_ = 0;
  std::unique_ptr<VideoInput> video_;
  long video_frame_ = 0;
};

}  // namespace adugs::data

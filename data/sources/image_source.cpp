#include "data/sources/image_source.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>  // the cv::CAP_PROP_* constants only

#include "data/formats/csv_reader.h"
#include "data/formats/image_file.h"
#include "data/input_error.h"
#include "data/media/media_loader.h"

namespace adugs::data {
namespace fs = std::filesystem;
namespace {

bool isImageFile(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  static const char* kExts[] = {".png", ".jpg", ".jpeg", ".pgm", ".ppm", ".bmp", ".tif", ".tiff"};
  return std::any_of(std::begin(kExts), std::end(kExts), [&](const char* e) { return ext == e; });
}

// 8 bits, BGR or grey: alpha dropped, other depths stretched from their min-max range.
cv::Mat toEightBit(const cv::Mat& image) {
  cv::Mat out = image;
  if (image.channels() == 4) cv::cvtColor(image, out, cv::COLOR_BGRA2BGR);
  if (out.depth() != CV_8U) {
    double lo, hi;
    cv::minMaxLoc(out.reshape(1), &lo, &hi);
    out.convertTo(out, CV_8U, hi > lo ? 255.0 / (hi - lo) : 1.0, hi > lo ? -lo * 255.0 / (hi - lo) : 0);
  }
  return out;
}

void setImages(const cv::Mat& read, ImageFrame& frame) {
  frame.image = toEightBit(read);
  frame.gray = frame.image;
  if (frame.image.channels() == 3) cv::cvtColor(frame.image, frame.gray, cv::COLOR_BGR2GRAY);
}

}  // namespace

ImageSource::ImageSource(const std::string& path, int every) : path_(path), every_(every) {
  if (every_ < 1) throw data::InputError(path, 0, "every", "must be >= 1");
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    const fs::path csv = fs::path(path) / "data.csv";
    if (fs::is_regular_file(csv) && fs::is_directory(fs::path(path) / "data")) {
      kind_ = "euroc";
      data::CsvReader r(csv.string());
      r.setColumnNames({"timestamp [ns]", "filename"});
      while (r.next()) {
        r.requireColumns(2);
        files_.emplace_back(r.int64At(0), (fs::path(path) / "data" / r.field(1)).string());
      }
    } else {
      kind_ = "folder";
      std::vector<fs::path> names;
      for (const auto& e : fs::directory_iterator(path))
        if (e.is_regular_file() && isImageFile(e.path())) names.push_back(e.path());
      std::sort(names.begin(), names.end());
      int64_t i = 0;
      for (const auto& p : names) {
        // A trailing run of >= 9 digits is a timestamp in ns ("1403709395937837056.png",
        // "cam0_1403709395937837056.png"); otherwise frames are 1 s apart.
        const std::string stem = p.stem().string();
        size_t start = stem.size();
        while (start > 0 && std::isdigit(static_cast<unsigned char>(stem[start - 1]))) --start;
        int64_t ts = 0;
        if (stem.size() - start < 9 || !data::parseInt64(stem.substr(start), ts))
          ts = i * 1000000000LL;
        files_.emplace_back(ts, p.string());
        ++i;
      }
    }
    if (files_.empty()) throw data::InputError(path, 0, "", "no images found in this folder");
  } else if (fs::is_regular_file(path, ec)) {
    kind_ = "video";
    video_.reset(requireMediaModule(path, "", "video files").open_video_file(path));
    if (!video_) throw data::InputError(path, 0, "", "cannot open as a video");
  } else {
    throw data::InputError(path, 0, "", "no such image folder or video file");
  }
}

ImageSource::~ImageSource() = default;

bool ImageSource::next(ImageFrame& frame) {
  if (kind_ == "video") {
    cv::Mat image;
    while (true) {
      if (!video_->read(image) || image.empty()) return false;
      const double ms = video_->get(cv::CAP_PROP_POS_MSEC);  // of the frame just read
      const long n = video_frame_++;
      if (n % every_ != 0) continue;
      frame.t_ns = static_cast<int64_t>(ms * 1e6);
      frame.name = path_ + "#" + std::to_string(n);
      setImages(image, frame);
      return true;
    }
  }
  while (index_ < files_.size()) {
    const size_t i = index_++;
    if (i % static_cast<size_t>(every_) != 0) continue;
    frame.t_ns = files_[i].first;
    frame.name = files_[i].second;
    const cv::Mat image = readImageFile(frame.name, ImageRead::kUnchanged);
    setImages(image, frame);
    return true;
  }
  return false;
}

size_t ImageSource::sizeHint() const {
  if (kind_ == "video") {
    const double n = video_->get(cv::CAP_PROP_FRAME_COUNT);
    return n > 0 ? static_cast<size_t>(n) / static_cast<size_t>(every_) : 0;
  }
  return (files_.size() + static_cast<size_t>(every_) - 1) / static_cast<size_t>(every_);
}

}  // namespace adugs::data

#include "data/device/camera_nodes.h"

#include "data/device/pixel_formats.h"
#include "data/input_error.h"

namespace adugs::data {

bool VideoNodeInfo::lists(uint32_t fourcc) const {
  for (const V4l2FormatInfo& f : formats)
    if (f.fourcc == fourcc) return true;
  return false;
}

std::vector<VideoNodeInfo> inspectVideoNodes(V4l2Io& io, const UsbCamera& camera) {
  std::vector<VideoNodeInfo> out;
  for (const UsbVideoNode& node : camera.video) {
    VideoNodeInfo info;
    info.node = node;
    try {
      V4l2Stream s(io, node.dev_path);
      info.opened = true;
      info.driver = s.driver();
      info.card = s.card();
      info.video = s.isVideoCapture();
      info.meta = s.isMetaCapture();
      info.formats = s.formats();
    } catch (const data::InputError& e) {
      info.error = e.what();
    }
    out.push_back(info);
  }
  return out;
}

D4xxNodes selectD4xxNodes(const std::vector<VideoNodeInfo>& nodes, const std::string& stream) {
  using data::PixelFormat;
  D4xxNodes out;
  for (size_t i = 0; i < nodes.size() && out.video < 0; ++i) {
    const VideoNodeInfo& n = nodes[i];
    if (!n.video) continue;
    const bool infrared = n.lists(data::fourcc(PixelFormat::kGrey)) || n.lists(data::fourcc(PixelFormat::kY8i));
    const bool color = n.lists(data::fourcc(PixelFormat::kYuyv)) && !infrared;
    if ((stream == "infrared" && infrared) || (stream == "color" && color)) out.video = static_cast<int>(i);
  }
  if (out.video < 0) return out;
  const VideoNodeInfo& v = nodes[static_cast<size_t>(out.video)];
  for (size_t i = 0; i < nodes.size(); ++i) {
    const VideoNodeInfo& n = nodes[i];
    if (!n.meta) continue;
    // The same USB interface; without sysfs interface links, the node right after the video node.
    const bool same = !v.node.interface.empty() ? n.node.interface == v.node.interface
                                                : static_cast<int>(i) == out.video + 1;
    if (same) {
      out.meta = static_cast<int>(i);
      break;
    }
  }
  return out;
}

}  // namespace adugs::data

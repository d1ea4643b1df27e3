#pragma once
// What each V4L2 node of a USB camera offers (opened briefly, capabilities and formats read), and
// the choice of the nodes a RealSense D4xx stream needs: the infrared (depth module) node lists
// GREY / Y8I (next to Z16), the colour node YUYV, and each has a metadata node on the same USB
// interface.
#include <string>
#include <vector>

#include "data/device/usb_device_tree.h"
#include "data/device/v4l2_io.h"
#include "data/device/v4l2_stream.h"

namespace adugs::data {

struct VideoNodeInfo {
  UsbVideoNode node;
  bool opened = false;
  std::string error;  // why it could not be opened
  std::string driver, card;
  bool video = false, meta = false;
  std::vector<V4l2FormatInfo> formats;
  bool lists(uint32_t fourcc) const;
};

std::vector<VideoNodeInfo> inspectVideoNodes(V4l2Io& io, const UsbCamera& camera);

// The D4xx node of `stream` ("infrared" or "color") and its metadata node; index -1 when absent.
struct D4xxNodes {
  int video = -1;
  int meta = -1;
};
D4xxNodes selectD4xxNodes(const std::vector<VideoNodeInfo>& nodes, const std::string& stream);

}  // namespace adugs::data

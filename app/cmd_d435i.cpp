// `adugs d435i info`: what the kernel shows of a RealSense D435i (nodes, formats, controls, IIO
// devices, scales, permissions) and, with --stream-seconds, a short streaming check with the
// config's options (rates, drops, clock): the first thing to run when `adugs live --d435i` does not
// start. See doc/d435i.md.
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.h"
#include "app/run_config.h"
#include "data/sources/d435i_probe.h"

namespace adugs::app {

void registerD435iCommand(CLI::App& root) {
  CLI::App* cmd = root.add_subcommand("d435i", "RealSense D435i without librealsense: inspect the camera");
  cmd->require_subcommand(1);
  struct Args {
    std::string config, sys_root, dev_root, usb_id, serial;
    double stream_seconds = 0;
  };
  auto a = std::make_shared<Args>();
  CLI::App* info = cmd->add_subcommand("info", "Nodes, formats, controls, IIO devices, scales, permissions; optionally stream");
  info->add_option("--config", a->config, "run config whose d435i: map is used (e.g. data/config/d435i.yaml)");
  info->add_option("--sys-root", a->sys_root, "sysfs root (default /sys)");
  info->add_option("--dev-root", a->dev_root, "device root (default /dev)");
  info->add_option("--usb-id", a->usb_id, "vendor:product (default 8086:0b3a)");
  info->add_option("--serial", a->serial, "the camera's USB serial number, when several are plugged in");
  info->add_option("--stream-seconds", a->stream_seconds, "then stream this long and report rates, drops, clock")
      ->check(CLI::Range(0.0, 3600.0));
  info->callback([a] {
    data::D435iOptions o = loadRunConfig(a->config).d435i;
    if (!a->sys_root.empty()) o.sys_root = a->sys_root;
    if (!a->dev_root.empty()) o.dev_root = a->dev_root;
    if (!a->usb_id.empty()) o.usb_id = a->usb_id;
    if (!a->serial.empty()) o.serial = a->serial;
    data::printD435iInfo(std::cout, o, data::systemV4l2Io());
    if (a->stream_seconds > 0) data::printD435iStreamCheck(std::cout, o, a->stream_seconds, data::systemV4l2Io());
  });
}

}  // namespace adugs::app

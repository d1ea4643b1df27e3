// `adugs bag info BAG`: the topics, types, message counts, rates, time span and compression of a
// ROS1 bag (what `rosbag info` prints), to find the topic names `adugs run` needs.
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.h"
#include "data/sources/rosbag_info.h"

namespace adugs::app {

void registerBagCommand(CLI::App& root) {
  CLI::App* bag = root.add_subcommand("bag", "Inspect ROS1 bags");
  bag->require_subcommand(1);
  auto path = std::make_shared<std::string>();
  CLI::App* info = bag->add_subcommand("info", "Topics, types, counts, rates, time span, compression");
  info->add_option("bag", *path, "ROS1 bag file")->required();
  info->callback([path] { std::cout << data::formatBagInfo(data::readBagInfo(*path)); });
}

}  // namespace adugs::app

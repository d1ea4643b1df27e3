#include "tracking/detect/ultralytics_output.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <iostream>

#include "data/input_error.h"

namespace adugs::tracking {
namespace {

constexpr int kMaskCoefficients = 32;

YAML::Node parseEntry(const std::map<std::string, std::string>& entries, const std::string& key,
                      const std::string& path) {
  const auto it = entries.find(key);
  if (it == entries.end()) return YAML::Node(YAML::NodeType::Null);  // absent
  try {
    return YAML::Load(it->second);
  } catch (const YAML::Exception& e) {
    throw data::InputError(path, 0, key, "unreadable model metadata '" + it->second + "': " + e.what());
  }
}

}  // namespace

UltralyticsModelInfo parseUltralyticsMetadata(const std::map<std::string, std::string>& entries,
                                              const std::string& path) {
  UltralyticsModelInfo info;
  try {
    if (const YAML::Node imgsz = parseEntry(entries, "imgsz", path); !imgsz.IsNull()) {
      // One number (square) or [height, width].
      const int h = imgsz.IsSequence() ? imgsz[0].as<int>() : imgsz.as<int>();
      const int w = imgsz.IsSequence() ? imgsz[imgsz.size() > 1 ? 1 : 0].as<int>() : h;
      if (h <= 0 || w <= 0) throw YAML::Exception(YAML::Mark::null_mark(), "not positive");
      info.input_size = {w, h};
    }
  } catch (const YAML::Exception& e) {
    throw data::InputError(path, 0, "imgsz", std::string("the model's input size is not [height, width]: ") + e.what());
  }
  try {
    if (const YAML::Node names = parseEntry(entries, "names", path); !names.IsNull()) {
      if (names.IsSequence()) {
        for (const YAML::Node& n : names) info.names.push_back(n.as<std::string>());
      } else if (names.IsMap()) {  // {0: 'person', 1: 'bicycle', ...}: ids 0..C-1
        info.names.resize(names.size());
        for (const auto& kv : names) {
          const int id = kv.first.as<int>();
          if (id < 0 || id >= static_cast<int>(names.size()))
            throw YAML::Exception(YAML::Mark::null_mark(), "class ids are not 0.." + std::to_string(names.size() - 1));
          info.names[id] = kv.second.as<std::string>();
        }
      } else {
        throw YAML::Exception(YAML::Mark::null_mark(), "neither a list nor a map");
      }
    }
  } catch (const YAML::Exception& e) {
    throw data::InputError(path, 0, "names", std::string("the model's class names are unreadable: ") + e.what());
  }
  if (const YAML::Node task = parseEntry(entries, "task", path); !task.IsNull()) info.task = task.as<std::string>("");
  return info;
}

std::set<int> keptClasses(const UltralyticsModelInfo& info, const std::set<int>& fallback, const std::string& path) {
  if (info.names.empty()) return fallback;
  std::set<int> kept = dynamicClassIds(info.names);
  if (!kept.empty()) return kept;
  std::cerr << "warning: " << path << ": none of the model's " << info.names.size()
            << " class names is a dynamic class (person, car, bus, ...): every detection is masked\n";
  for (int i = 0; i < static_cast<int>(info.names.size()); ++i) kept.insert(i);
  return kept;
}

int ultralyticsClassCount(int rows, const UltralyticsModelInfo& info, const std::string& path) {
  if (info.names.empty()) {
    if (rows < 5) throw data::InputError(path, 0, "output", "fewer than 5 rows: not a YOLO detect head");
    return rows - 4;
  }
  const int classes = static_cast<int>(info.names.size());
  const bool segment = info.task == "segment";
  const int expected = 4 + classes + (segment ? kMaskCoefficients : 0);
  if (rows != expected)
    throw data::InputError(path, 0, "names",
                           "the model names " + std::to_string(classes) + " classes (task '" + info.task +
                               "'), so its output should have " + std::to_string(expected) + " rows, but it has " +
                               std::to_string(rows));
  return classes;
}

std::vector<Detection> decodeUltralyticsOutput(const cv::Mat& output, int num_classes,
                                               const Letterbox& input, const DetectorOptions& options) {
  std::vector<Detection> out;
  // Rows are channels: walk anchors column by column on the transposed copy (contiguous scores).
  cv::Mat anchors;
  cv::transpose(output.rowRange(0, 4 + num_classes), anchors);
  for (int n = 0; n < anchors.rows; ++n) {
    const float* a = anchors.ptr<float>(n);
    const float* cls = a + 4;
    const int best = static_cast<int>(std::max_element(cls, cls + num_classes) - cls);
    if (cls[best] < options.score_threshold || !options.keep_classes.count(best)) continue;
    Detection d;
    d.box = input.toImage({a[0], a[1], a[2], a[3]});
    d.class_id = best;
    d.score = cls[best];
    out.push_back(d);
  }
  return out;
}

}  // namespace adugs::tracking

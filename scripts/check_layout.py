#!/usr/bin/env python3
"""Checks the include directions of doc/architecture.md ("Layout") on the source tree.

  scripts/check_layout.py [REPO_ROOT]

Exit 1 with one line per offending include (file:line: include, and the rule it breaks):
  - modules: data <- tracking, vio, calib <- app; tracking, vio and calib do not include each other;
  - inside a module, a sub-folder includes only the sub-folders before it in the pipeline
    (the lists below), and the module's top-level files that are not named as its top;
  - nothing outside data/ includes a device's or a dataset's interfaces (V4L2, IIO, ioctl, rosbag).
Run by ctest (test `layout_includes`); uses only the standard library.
"""
import os
import re
import sys

MODULE_FLOOR = {"data": 0, "tracking": 1, "vio": 1, "calib": 1, "app": 2}

# Sub-folders of each module in pipeline order: a folder may include those before it, not after.
# "." is the module's own top level: `base` files every sub-folder may include, the rest (the
# module's top) may include every sub-folder but no sub-folder includes them.
ORDER = {
    "data": (["media", "formats", "device", "sim", "sources"],
             {"types.h", "input_error.h", "calibration.h", "camera_model.h", "builtin_config.h", "elapsed_time.h",
              "plugin_module.h"}),
    "tracking": (["detect", "sort", "segment", "eval"],
                 {"box.h", "torchscript_module.h", "torch_plugin.h", "torch_plugin_loader.h"}),
    "vio": (["imu", "frontend", "init", "estimator", "eval"], set()),
    "calib": (["target", "intrinsics", "imu_noise", "camera_imu"],
              {"calibration_verdict.h", "calib_camera.h", "kalibr_yaml.h", "solver_outcome.h",
               "text_format.h"}),
    "app": (["pipeline"], set()),
}
# Exceptions, each with its reason: (including folder, included file).
ALLOWED = {
    # The estimator depends on the front-end's output type, not on the tracker.
    ("vio/estimator", "vio/frontend/frame_features.h"),
    ("vio/init", "vio/frontend/frame_features.h"),
}
DEVICE_HEADERS = re.compile(r"#include <(linux/videodev2\.h|linux/usb/video\.h|sys/ioctl\.h|sys/mman\.h|rosbag/)")
INCLUDE = re.compile(r'^\s*#include "([^"]+)"')


def folder_of(path):
    parts = path.split("/")
    return parts[0], (parts[1] if len(parts) > 2 else ".")


def check(root):
    problems = []
    for module in MODULE_FLOOR:
        for dirpath, _, files in os.walk(os.path.join(root, module)):
            for name in files:
                if not name.endswith((".h", ".cpp")):
                    continue
                path = os.path.relpath(os.path.join(dirpath, name), root)
                mod, sub = folder_of(path)
                with open(os.path.join(root, path), encoding="utf-8") as f:
                    lines = f.read().split("\n")
                for number, line in enumerate(lines, 1):
                    where = f"{path}:{number}: {line.strip()}"
                    if mod != "data" and DEVICE_HEADERS.search(line):
                        problems.append(f"{where}: device and dataset interfaces belong in data/")
                    m = INCLUDE.match(line)
                    if not m:
                        continue
                    target = m.group(1)
                    tmod, tsub = folder_of(target)
                    if tmod not in MODULE_FLOOR:
                        continue
                    if tmod != mod:
                        if MODULE_FLOOR[tmod] >= MODULE_FLOOR[mod]:
                            problems.append(f"{where}: {mod}/ must not include {tmod}/ (modules: data <- tracking, vio, calib <- app)")
                        continue
                    if (os.path.dirname(path), target) in ALLOWED:
                        continue
                    order, base = ORDER[mod]
                    if sub == tsub:
                        continue
                    if tsub == ".":
                        if sub != "." and os.path.basename(target) not in base:
                            problems.append(f"{where}: {mod}/{sub}/ must not include the module's top ({target})")
                        continue
                    if sub == ".":
                        if os.path.basename(path) in base:
                            problems.append(f"{where}: {path} is a base file of {mod}/ and must not include a sub-folder")
                        continue
                    if order.index(tsub) > order.index(sub):
                        problems.append(f"{where}: {mod}/{sub}/ must not include {mod}/{tsub}/ (order: {' <- '.join(order)})")
    return problems


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    problems = check(root)
    for p in problems:
        print(p)
    print(f"check_layout: {len(problems)} include(s) against the layout")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Writes tiny models with the interface of ultralytics YOLO11 / YOLOv8 exports (TorchScript with
its config.txt metadata; ONNX with metadata_props) whose output is known in closed form, so the
project's loaders and decoder can be checked against hand-worked boxes. (The real architectures
with random weights were checked separately: doc/results.md.)

Input: images [1, 3, 192, 256] (imgsz [192, 256] = height, width), RGB / 255.
Output: [1, 4 + 80, 1008] (1008 anchors of the stride 8/16/32 grids of 192 x 256), all zero but:
    anchor 5:   box (100, 80, 40, 60) (cx, cy, w, h input px), person (0) score = R of the
                input's centre pixel, i.e. 1.0 for a red image, 0.0 for a blue one
    anchor 6:   box (102, 81, 40, 60), person 0.5: overlaps anchor 5, removed by NMS
    anchor 700: box (200, 100, 50, 30), car (2) score = B of the centre pixel
    anchor 900: box (30, 150, 20, 20), dining table (60) score 0.95: not a dynamic class
Files:
    detect.torchscript         the model, config.txt as ultralytics writes it (JSON)
    detect.onnx                the same as an ONNX graph OpenCV 4.6 runs (centre pixel -> Gemm ->
                               Reshape), with ultralytics' metadata_props
    detect_no_metadata.onnx    without metadata_props
    names_mismatch.torchscript config.txt names 3 classes, the output has 80
    segment.torchscript        task 'segment': returns (1 x 116 x 1008 with 32 mask coefficients, protos)
    two_inputs.torchscript     forward(images, scale): the wrong interface
Usage: make_ultralytics_like_models.py OUT_DIR
"""
import json
import os
import sys
import warnings

import numpy as np
import onnx
import torch
from onnx import TensorProto, helper, numpy_helper

HEIGHT, WIDTH = 192, 256
ANCHORS = sum((HEIGHT // s) * (WIDTH // s) for s in (8, 16, 32))
COCO = ["person", "bicycle", "car", "motorcycle", "airplane", "bus", "train", "truck", "boat",
        "traffic light", "fire hydrant", "stop sign", "parking meter", "bench", "bird", "cat", "dog",
        "horse", "sheep", "cow", "elephant", "bear", "zebra", "giraffe", "backpack", "umbrella",
        "handbag", "tie", "suitcase", "frisbee", "skis", "snowboard", "sports ball", "kite",
        "baseball bat", "baseball glove", "skateboard", "surfboard", "tennis racket", "bottle",
        "wine glass", "cup", "fork", "knife", "spoon", "bowl", "banana", "apple", "sandwich",
        "orange", "broccoli", "carrot", "hot dog", "pizza", "donut", "cake", "chair", "couch",
        "potted plant", "bed", "dining table", "toilet", "tv", "laptop", "mouse", "remote", "keyboard", "cell phone", "microwave",
        "oven", "toaster", "sink", "refrigerator", "book", "clock", "vase", "scissors",
        "teddy bear", "hair drier", "toothbrush"]
assert len(COCO) == 80


def fixed_output(extra_rows=0):
    out = torch.zeros(1, 4 + 80 + extra_rows, ANCHORS)
    out[0, :4, 6] = torch.tensor([102.0, 81.0, 40.0, 60.0])
    out[0, 4 + 0, 6] = 0.5
    out[0, :4, 5] = torch.tensor([100.0, 80.0, 40.0, 60.0])
    out[0, :4, 700] = torch.tensor([200.0, 100.0, 50.0, 30.0])
    out[0, :4, 900] = torch.tensor([30.0, 150.0, 20.0, 20.0])
    out[0, 4 + 60, 900] = 0.95
    return out


class Detect(torch.nn.Module):
    def __init__(self, extra_rows=0):
        super().__init__()
        self.register_buffer("fixed", fixed_output(extra_rows))
        person = torch.zeros(1, 4 + 80 + extra_rows, ANCHORS)
        person[0, 4 + 0, 5] = 1.0
        car = torch.zeros_like(person)
        car[0, 4 + 2, 700] = 1.0
        self.register_buffer("person", person)
        self.register_buffer("car", car)

    def forward(self, images):
        centre = images[0, :, HEIGHT // 2, WIDTH // 2]
        return self.fixed + centre[0] * self.person + centre[2] * self.car


class Segment(Detect):
    def __init__(self):
        super().__init__(extra_rows=32)

    def forward(self, images):
        return super().forward(images), torch.zeros(1, 32, HEIGHT // 4, WIDTH // 4)


class TwoInputs(Detect):
    def forward(self, images, scale):
        return super().forward(images) * scale


def metadata(names, task="detect"):
    # What ultralytics' exporter writes (engine/exporter.py: self.metadata).
    return {"description": "Ultralytics YOLO11n model (test double)", "author": "Ultralytics",
            "date": "2026-11-25", "version": "8.3.0", "license": "AGPL-3.0", "docs": "https://docs.ultralytics.com",
            "stride": 32, "task": task, "batch": 1, "imgsz": [HEIGHT, WIDTH],
            "names": {i: n for i, n in enumerate(names)}, "args": {"batch": 1, "half": False}}


def save_torchscript(module, example, path, meta):
    traced = torch.jit.trace(module, example, strict=False)
    torch.jit.save(traced, path, _extra_files={"config.txt": json.dumps(meta)})


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    warnings.filterwarnings("ignore")
    images = torch.zeros(1, 3, HEIGHT, WIDTH)
    save_torchscript(Detect(), images, os.path.join(out, "detect.torchscript"), metadata(COCO))
    save_torchscript(Detect(), images, os.path.join(out, "names_mismatch.torchscript"), metadata(COCO[:3]))
    save_torchscript(Segment(), images, os.path.join(out, "segment.torchscript"), metadata(COCO, "segment"))
    save_torchscript(TwoInputs(), (images, torch.ones(1)), os.path.join(out, "two_inputs.torchscript"),
                     metadata(COCO))

    model = detect_onnx()
    onnx.save(model, os.path.join(out, "detect_no_metadata.onnx"))
    for key, value in metadata(COCO).items():  # ultralytics stores str(value): Python literals
        entry = model.metadata_props.add()
        entry.key, entry.value = key, str(value)
    onnx.save(model, os.path.join(out, "detect.onnx"))


def detect_onnx():
    """Detect() as ops OpenCV 4.6 imports: output = centre pixel (1 x 3) x W + fixed."""
    d = Detect()
    rows = 4 + 80
    weights = torch.stack([d.person.flatten(), torch.zeros(rows * ANCHORS), d.car.flatten()]).numpy()
    starts = np.array([0, 0, HEIGHT // 2, WIDTH // 2], np.int64)
    nodes = [
        helper.make_node("Slice", ["images", "starts", "ends"], ["centre"]),
        helper.make_node("Flatten", ["centre"], ["pixel"], axis=1),
        helper.make_node("Gemm", ["pixel", "weights", "bias"], ["flat"], transB=1),
        helper.make_node("Reshape", ["flat", "shape"], ["output0"]),
    ]
    inits = [numpy_helper.from_array(starts, "starts"),
             numpy_helper.from_array(starts + np.array([1, 3, 1, 1], np.int64), "ends"),
             numpy_helper.from_array(weights.T.astype(np.float32).copy(), "weights"),
             numpy_helper.from_array(d.fixed.flatten().numpy().astype(np.float32), "bias"),
             numpy_helper.from_array(np.array([1, rows, ANCHORS], np.int64), "shape")]
    graph = helper.make_graph(
        nodes, "ultralytics_like", [helper.make_tensor_value_info("images", TensorProto.FLOAT, [1, 3, HEIGHT, WIDTH])],
        [helper.make_tensor_value_info("output0", TensorProto.FLOAT, [1, rows, ANCHORS])], inits)
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 12)])
    model.ir_version = 7
    onnx.checker.check_model(model)
    return model


if __name__ == "__main__":
    main()

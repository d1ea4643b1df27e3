#!/usr/bin/python3
"""Exports a tiny detector built like ultralytics YOLO11 / YOLOv8 (Conv+BN+SiLU, C2f, C2PSA, Detect
with DFL) with torch.onnx.export exactly as ultralytics' exporter calls it, so that CI can check
scripts/prepare_onnx_for_opencv.py on the graph patterns of real exports without ultralytics (not a
Debian package). The modules are written here in ultralytics' style, with small channel counts.

What each construct reproduces, and what OpenCV 4.6.0 dnn does with it in the unprepared export
(checked by applying all of the script's rewrites but the one for that construct):
  - Detect box-branch biases all 1.0 (ultralytics' bias_init): torch dedups the equal initializers
    into Identity nodes -> readNetFromONNX fails: "Node [Identity@ai.onnx]:(onnx_node!Identity_0)
    parse error: (-215:Assertion failed) inputs.size() in function 'getMemoryShapes'". This is the
    error both unprepared exports (opset 12 and 13) give, as real YOLOv8n / YOLO11n exports do.
  - dist2bbox's distance.chunk(2, 1) exports as Shape -> Gather -> Add -> Div -> Mul -> Slice ->
    import fails: "Node [Add@ai.onnx]:(onnx_node!/detect/Add) ... (-215) blob_0.size ==
    blob_1.size in function 'parseBias'".
  - dbox * strides, strides a [1, N] constant against [1, 4, N]: imports, then forward() fails:
    "(-215) start <= (int)shape.size() && end <= (int)shape.size() && start <= end in function 'total'".
  - Split with unequal sizes, at opset 13 given as an input, which OpenCV 4.6 ignores (it splits
    equally): C2PSA's q, k, v [16, 16, 32] -> import fails: "Node [Split@ai.onnx]:(onnx_node!/p5/
    p5.1/m/m.0/attn/Split) ... (-215) splits > 0 && inpShape[axis_rw] % splits == 0"; Detect's
    x_cat.split((4 * 16, nc), 1) = (64, 3) alone gives the same error in /detect/Split. (Opset 12
    keeps the sizes as an attribute, which OpenCV reads: no error there.)
  - C2PSA attention (q^T k) * key_dim ** -0.5 (MatMul then Mul 0.25): OpenCV fuses the Mul into the
    MatMul layer and drops it -> runs, output silently wrong (boxes off by 12 px, scores by 0.15).
  The equal-size C2f splits, the DFL (softmax over 16 bins, 1x1 conv with weights 0..15), the anchor
  constants and the class sigmoid are there because real exports have them; OpenCV 4.6 runs them.

Weights: torch.manual_seed(0); BatchNorm running statistics estimated on smooth test patterns
(train-mode pass, momentum None), class biases drawn N(0, 1) and class weights x4, so that scores
spread over 0.002..0.995 and boxes vary per anchor (untrained ultralytics models give near-constant
outputs). BatchNorm is then fused into the convolutions, as model.fuse() does before export.

Input images [1, 3, 128, 160] (imgsz [128, 160] = height, width); output0 [1, 4 + 3, 420]: cx, cy, w,
h in input pixels and 3 class scores (person, car, chair) for the 16x20 + 8x10 + 4x5 anchors of
strides 8, 16, 32.
Files written to OUT_DIR:
  export_opset12.onnx, export_opset13.onnx  torch.onnx.export (do_constant_folding, no simplify),
                                            with ultralytics' metadata_props (Python str() values)
  input.f32    the [1, 3, 128, 160] float32 input (smooth pattern in 0..1), raw little-endian
  output.f32   the traced (TorchScript) model's output0 for it, [1, 7, 420] float32
Usage: make_ultralytics_like_onnx_export.py OUT_DIR
"""
import os
import sys
import warnings

import onnx
import torch
from torch import nn

HEIGHT, WIDTH = 128, 160
NAMES = {0: "person", 1: "car", 2: "chair"}


class Conv(nn.Module):
    """Conv2d + BatchNorm2d + SiLU (ultralytics.nn.modules.conv.Conv)."""

    def __init__(self, c1, c2, k=1, s=1, g=1, act=True):
        super().__init__()
        self.conv = nn.Conv2d(c1, c2, k, s, k // 2, groups=g, bias=False)
        self.bn = nn.BatchNorm2d(c2)
        self.act = nn.SiLU() if act else nn.Identity()

    def forward(self, x):
        return self.act(self.bn(self.conv(x)))

    def fuse(self):
        """BatchNorm folded into the convolution (ultralytics.utils.torch_utils.fuse_conv_and_bn)."""
        c, bn = self.conv, self.bn
        fused = nn.Conv2d(c.in_channels, c.out_channels, c.kernel_size, c.stride, c.padding, groups=c.groups)
        scale = bn.weight / torch.sqrt(bn.running_var + bn.eps)
        fused.weight.data = c.weight * scale.view(-1, 1, 1, 1)
        fused.bias.data = bn.bias - bn.running_mean * scale
        self.conv = fused
        del self.bn
        self.forward = lambda x: self.act(self.conv(x))


class Bottleneck(nn.Module):
    def __init__(self, c1, c2, shortcut=True):
        super().__init__()
        self.cv1, self.cv2 = Conv(c1, c2, 3), Conv(c2, c2, 3)
        self.add = shortcut and c1 == c2

    def forward(self, x):
        return x + self.cv2(self.cv1(x)) if self.add else self.cv2(self.cv1(x))


class C2f(nn.Module):
    """CSP bottleneck; forward_split as the exporter uses it: an equal-size Split."""

    def __init__(self, c1, c2, n=1):
        super().__init__()
        self.c = c2 // 2
        self.cv1 = Conv(c1, 2 * self.c, 1)
        self.cv2 = Conv((2 + n) * self.c, c2, 1)
        self.m = nn.ModuleList(Bottleneck(self.c, self.c) for _ in range(n))

    def forward(self, x):
        y = list(self.cv1(x).split((self.c, self.c), 1))
        y.extend(m(y[-1]) for m in self.m)
        return self.cv2(torch.cat(y, 1))


class Attention(nn.Module):
    """ultralytics.nn.modules.block.Attention: q, k, v of unequal sizes, (q^T k) * scale."""

    def __init__(self, dim, num_heads, attn_ratio=0.5):
        super().__init__()
        self.num_heads = num_heads
        self.head_dim = dim // num_heads
        self.key_dim = int(self.head_dim * attn_ratio)
        self.scale = self.key_dim ** -0.5
        self.qkv = Conv(dim, dim + 2 * self.key_dim * num_heads, 1, act=False)
        self.proj = Conv(dim, dim, 1, act=False)
        self.pe = Conv(dim, dim, 3, g=dim, act=False)

    def forward(self, x):
        B, C, H, W = x.shape
        N = H * W
        q, k, v = self.qkv(x).view(B, self.num_heads, self.key_dim * 2 + self.head_dim, N).split(
            [self.key_dim, self.key_dim, self.head_dim], dim=2)
        attn = (q.transpose(-2, -1) @ k) * self.scale
        attn = attn.softmax(dim=-1)
        x = (v @ attn.transpose(-2, -1)).view(B, C, H, W) + self.pe(v.reshape(B, C, H, W))
        return self.proj(x)


class PSABlock(nn.Module):
    def __init__(self, c, num_heads):
        super().__init__()
        self.attn = Attention(c, num_heads)
        self.ffn = nn.Sequential(Conv(c, c * 2, 1), Conv(c * 2, c, 1, act=False))

    def forward(self, x):
        x = x + self.attn(x)
        return x + self.ffn(x)


class C2PSA(nn.Module):
    """YOLO11's C2PSA; one head (ultralytics uses c // 64 heads, i.e. needs c >= 64)."""

    def __init__(self, c1, c2):
        super().__init__()
        self.c = c1 // 2
        self.cv1 = Conv(c1, 2 * self.c, 1)
        self.cv2 = Conv(2 * self.c, c2, 1)
        self.m = nn.Sequential(PSABlock(self.c, num_heads=1))

    def forward(self, x):
        a, b = self.cv1(x).split((self.c, self.c), dim=1)
        return self.cv2(torch.cat((a, self.m(b)), 1))


class DFL(nn.Module):
    """Distribution focal loss integral: softmax over 16 bins, then a 1x1 conv with weights 0..15."""

    def __init__(self, c1=16):
        super().__init__()
        self.conv = nn.Conv2d(c1, 1, 1, bias=False).requires_grad_(False)
        self.conv.weight.data[:] = torch.arange(c1, dtype=torch.float).view(1, c1, 1, 1)
        self.c1 = c1

    def forward(self, x):
        b, _, a = x.shape
        return self.conv(x.view(b, 4, self.c1, a).transpose(2, 1).softmax(1)).view(b, 4, a)


def make_anchors(feats, strides, offset=0.5):
    points, stride_tensor = [], []
    for f, s in zip(feats, strides):
        h, w = f.shape[2:]
        sy, sx = torch.meshgrid(torch.arange(h) + offset, torch.arange(w) + offset, indexing="ij")
        points.append(torch.stack((sx, sy), -1).view(-1, 2))
        stride_tensor.append(torch.full((h * w, 1), float(s)))
    return torch.cat(points), torch.cat(stride_tensor)


def dist2bbox(distance, anchor_points, dim=1):
    lt, rb = distance.chunk(2, dim)  # exports as the Shape -> Gather -> Add -> Div -> Slice chain
    x1y1, x2y2 = anchor_points - lt, anchor_points + rb
    return torch.cat(((x1y1 + x2y2) / 2, x2y2 - x1y1), dim)


class Detect(nn.Module):
    """ultralytics' Detect head (YOLOv8 layout) in export mode: returns the decoded [1, 4 + nc, N]."""

    def __init__(self, nc, ch, strides):
        super().__init__()
        self.nc, self.reg_max = nc, 16
        self.no = nc + 4 * self.reg_max
        self.stride = torch.tensor(strides, dtype=torch.float)
        c2, c3 = max(16, ch[0] // 4, 4 * self.reg_max), max(ch[0], min(nc, 100))
        self.cv2 = nn.ModuleList(nn.Sequential(Conv(x, c2, 3), Conv(c2, c2, 3), nn.Conv2d(c2, 4 * self.reg_max, 1))
                                 for x in ch)
        self.cv3 = nn.ModuleList(nn.Sequential(Conv(x, c3, 3), Conv(c3, c3, 3), nn.Conv2d(c3, nc, 1)) for x in ch)
        self.dfl = DFL(self.reg_max)
        self.shape = None

    def bias_init(self):
        for a in self.cv2:
            a[-1].bias.data[:] = 1.0  # equal box biases: torch dedups them into Identity nodes
        for b in self.cv3:  # not ultralytics' -11.5 prior, and larger weights: scores spread over 0..1
            b[-1].bias.data = torch.randn(self.nc)
            b[-1].weight.data *= 4

    def forward(self, x):
        x = [torch.cat((self.cv2[i](xi), self.cv3[i](xi)), 1) for i, xi in enumerate(x)]
        shape = x[0].shape
        x_cat = torch.cat([xi.view(shape[0], self.no, -1) for xi in x], 2)
        if self.shape != shape:  # computed in the exporter's dry run: constants in the graph
            self.anchors, self.strides = (t.transpose(0, 1) for t in make_anchors(x, self.stride))
            self.shape = shape
        box, cls = x_cat.split((4 * self.reg_max, self.nc), 1)
        dbox = dist2bbox(self.dfl(box), self.anchors.unsqueeze(0)) * self.strides  # [1, N] * [1, 4, N]
        return torch.cat((dbox, cls.sigmoid()), 1)


class TinyYolo(nn.Module):
    def __init__(self, nc=len(NAMES)):
        super().__init__()
        self.stem = nn.Sequential(Conv(3, 8, 3, 2), Conv(8, 16, 3, 2), C2f(16, 16))  # stride 4
        self.p3 = Conv(16, 32, 3, 2)
        self.p4 = nn.Sequential(Conv(32, 32, 3, 2), C2f(32, 32))
        self.p5 = nn.Sequential(Conv(32, 64, 3, 2), C2PSA(64, 64))
        self.detect = Detect(nc, (32, 32, 64), (8, 16, 32))

    def forward(self, images):
        p3 = self.p3(self.stem(images))
        p4 = self.p4(p3)
        return self.detect([p3, p4, self.p5(p4)])


def pattern(phase):
    """A smooth [1, 3, H, W] image in 0..1, different per channel and phase."""
    y = torch.linspace(0, 1, HEIGHT).view(HEIGHT, 1)
    x = torch.linspace(0, 1, WIDTH).view(1, WIDTH)
    channels = [0.5 + 0.5 * torch.sin((3 + c + phase) * x * 3.1416 + (2 + phase) * y * (c + 1) + phase + c)
                * torch.cos(4 * y * (1 + 0.3 * phase) - x) for c in range(3)]
    return torch.stack(channels).unsqueeze(0)


def build_model():
    torch.manual_seed(0)
    model = TinyYolo()
    model.detect.bias_init()
    # BatchNorm statistics of the data instead of the init's (0, 1), which make activations vanish.
    for m in model.modules():
        if isinstance(m, nn.BatchNorm2d):
            m.reset_running_stats()
            m.momentum = None
    model.train()
    with torch.no_grad():
        model(torch.cat([pattern(p) for p in (0.3, 1.1, 1.7, 2.5)]))
    model.eval()
    for m in model.modules():
        if isinstance(m, Conv):
            m.fuse()
    for p in model.parameters():
        p.requires_grad_(False)
    return model


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    warnings.filterwarnings("ignore")
    torch.set_num_threads(1)
    model = build_model()
    images = pattern(0.0)
    model(images)  # the exporter's dry run: Detect caches its anchors and strides
    traced = torch.jit.trace(model, images, strict=False)  # format=torchscript
    with torch.no_grad():
        reference = traced(images)
    assert reference.shape == (1, 4 + len(NAMES), sum((HEIGHT // s) * (WIDTH // s) for s in (8, 16, 32)))
    images.numpy().astype("<f4").tofile(os.path.join(out, "input.f32"))
    reference.numpy().astype("<f4").tofile(os.path.join(out, "output.f32"))

    metadata = {"description": "Ultralytics-like test export", "author": "Ultralytics", "version": "8.3.40",
                "stride": 32, "task": "detect", "batch": 1, "imgsz": [HEIGHT, WIDTH], "names": NAMES}
    for opset in (12, 13):
        path = os.path.join(out, f"export_opset{opset}.onnx")
        torch.onnx.export(model, images, path, verbose=False, opset_version=opset, do_constant_folding=True,
                          input_names=["images"], output_names=["output0"], dynamic_axes=None)
        exported = onnx.load(path)
        onnx.checker.check_model(exported)
        for key, value in metadata.items():  # ultralytics stores str(value): Python literals
            entry = exported.metadata_props.add()
            entry.key, entry.value = key, str(value)
        onnx.save(exported, path)


if __name__ == "__main__":
    main()

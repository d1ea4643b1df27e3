#!/usr/bin/python3
"""Writes tiny TorchScript modules with the interface of scripts/export_mobilesam.py's files (no
MobileSAM weights exist on the build machines) whose output is known in closed form, so
test_mobilesam_segmenter can check the real MobileSamSegmenter path (libtorch loading, SAM
pre-processing, box prompt, post-processing) against hand-worked masks.

encoder.pt  forward(image [1,3,1024,1024]) -> embeddings [1,256,64,64]
    channel c = mean of input channel (c % 3) over each 16x16 block (channel 0 = normalised red
    when the caller feeds RGB).
decoder.pt  forward(image_embeddings [1,256,64,64], point_coords [1,2,2], point_labels [1,2])
    -> (low_res_masks [1,1,256,256], iou_predictions [1,1]). For a box (x0, y0, x1, y1) in the
    1024 frame with labels (2, 3), the logit of low-res cell (i, j), at X = 4 j + 2, Y = 4 i + 2:
        min(X - x0, x1 - X, Y - y0, y1 - Y, 4 * e0(X, Y))
    with e0 = embedding channel 0 upsampled x4 (bilinear): positive inside the box on red pixels.
    Labels other than (2, 3) make every logit -1000 (shows the labels are SAM's).
encoder_wrong_shape.pt  returns [1,256,32,32].
decoder_two_inputs.pt   forward(image_embeddings, point_coords): the wrong interface.
decoder_wrong_shape.pt  returns low_res_masks [1,1,128,128].

Usage: make_sam_like_torchscript.py OUT_DIR
"""
import os
import sys
import warnings

import torch
import torch.nn.functional as F

LOW_RES = 256


class Encoder(torch.nn.Module):
    def __init__(self, pool=16):
        super().__init__()
        self.pool = pool
        weights = torch.zeros(256, 3, 1, 1)
        for c in range(256):
            weights[c, c % 3, 0, 0] = 1.0
        self.register_buffer("weights", weights)

    def forward(self, image):
        return F.conv2d(F.avg_pool2d(image, self.pool), self.weights)


def low_res_logits(image_embeddings, point_coords, point_labels, size=LOW_RES):
    centres = torch.arange(size, dtype=torch.float32) * (1024.0 / size) + 2.0
    x = centres.view(1, size)
    y = centres.view(size, 1)
    x0, y0 = point_coords[0, 0, 0], point_coords[0, 0, 1]
    x1, y1 = point_coords[0, 1, 0], point_coords[0, 1, 1]
    red = 4.0 * F.interpolate(image_embeddings[:, 0:1], scale_factor=4.0, mode="bilinear",
                              align_corners=False)[0, 0]
    if size != LOW_RES:
        red = F.interpolate(red[None, None], size=(size, size), mode="bilinear", align_corners=False)[0, 0]
    inside = torch.minimum(torch.minimum(x - x0, x1 - x), torch.minimum(y - y0, y1 - y))
    logits = torch.minimum(inside, red)
    wrong_labels = (point_labels[0, 0] - 2.0).abs() + (point_labels[0, 1] - 3.0).abs()
    logits = logits - 1000.0 * (wrong_labels > 0).float()
    return logits.view(1, 1, size, size), torch.ones(1, 1)


class Decoder(torch.nn.Module):
    def forward(self, image_embeddings, point_coords, point_labels):
        return low_res_logits(image_embeddings, point_coords, point_labels)


class DecoderWrongShape(torch.nn.Module):
    def forward(self, image_embeddings, point_coords, point_labels):
        return low_res_logits(image_embeddings, point_coords, point_labels, size=128)


class DecoderTwoInputs(torch.nn.Module):
    def forward(self, image_embeddings, point_coords):
        labels = torch.tensor([[2.0, 3.0]])
        return low_res_logits(image_embeddings, point_coords, labels)


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    warnings.filterwarnings("ignore", category=torch.jit.TracerWarning)
    image = torch.zeros(1, 3, 1024, 1024)
    embeddings = torch.zeros(1, 256, 64, 64)
    coords = torch.tensor([[[10.0, 10.0], [100.0, 100.0]]])
    labels = torch.tensor([[2.0, 3.0]])
    torch.jit.trace(Encoder(), image).save(os.path.join(out, "encoder.pt"))
    torch.jit.trace(Encoder(pool=32), image).save(os.path.join(out, "encoder_wrong_shape.pt"))
    torch.jit.trace(Decoder(), (embeddings, coords, labels)).save(os.path.join(out, "decoder.pt"))
    torch.jit.trace(DecoderWrongShape(), (embeddings, coords, labels)).save(
        os.path.join(out, "decoder_wrong_shape.pt"))
    torch.jit.trace(DecoderTwoInputs(), (embeddings, coords)).save(os.path.join(out, "decoder_two_inputs.pt"))


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Writes two tiny ONNX graphs with the input/output signature of the MobileSAM / SAM ONNX exports
(no weights are available on the build machines), built only from ops that OpenCV 4.6 dnn runs,
so test_mobilesam_segmenter can drive the real MobileSamSegmenter code path.

encoder.onnx  x [1,3,1024,1024] -> image_embeddings [1,256,64,64]
    embedding channel c = mean of the normalised input channel (c % 3) over each 16x16 block
    (so channel 0 is the normalised red channel when the caller feeds RGB).
decoder.onnx  image_embeddings, point_coords [1,N,2], point_labels [1,N], mask_input
    [1,1,256,256], has_mask_input [1], orig_im_size [2] -> masks [1,1,H,W], iou_predictions [1,1],
    low_res_masks [1,1,256,256].  Only box prompts (N = 2: top-left, bottom-right in the 1024
    frame) are supported. The low-resolution logit at 1024-frame point (X, Y) (the centre of
    low-res cell (i, j): X = 4 j + 2, Y = 4 i + 2) is
        min(X - x0, x1 - X, Y - y0, y1 - Y, 4 * e0(X, Y))
    where e0 is embedding channel 0 upsampled x4 (bilinear): positive inside the box on red pixels.
    'masks' is SAM's post-processing baked for one image size H x W (bilinear x4 to 1024, crop
    to the resized image, bilinear to H x W): the real export computes that size at run time
    from orig_im_size, which OpenCV 4.6 cannot do.
decoder_wrong_names.onnx  the same decoder with 'point_coords' renamed 'coords'.
decoder_layer_norm.onnx  the same decoder (opset 17) with one LayerNormalization node, the op a
    real SAM decoder exported at opset 17 contains and OpenCV 4.6 cannot import.
decoder_inverted_low_res.onnx  the same decoder with negated low_res_masks ('masks' unchanged):
    shows which output the segmenter used.

Usage: make_sam_like_onnx.py OUT_DIR HEIGHT WIDTH
"""
import os
import sys

import numpy as np
import onnx
from onnx import TensorProto, helper, numpy_helper

LOW_RES = 256
EMBED = 64
IMG = 1024
EMBED_GAIN = 4.0


def const(name, array):
    return numpy_helper.from_array(np.asarray(array), name)


def save(graph, path, opset=11):
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", opset)])
    model.ir_version = 6 if opset < 17 else 8
    onnx.checker.check_model(model)
    onnx.save(model, path)


def make_encoder(path):
    weights = np.zeros((256, 3, 1, 1), np.float32)
    for c in range(256):
        weights[c, c % 3, 0, 0] = 1.0
    nodes = [
        helper.make_node("AveragePool", ["x"], ["pooled"], kernel_shape=[16, 16], strides=[16, 16]),
        helper.make_node("Conv", ["pooled", "w"], ["image_embeddings"], kernel_shape=[1, 1]),
    ]
    graph = helper.make_graph(
        nodes, "sam_like_encoder",
        [helper.make_tensor_value_info("x", TensorProto.FLOAT, [1, 3, IMG, IMG])],
        [helper.make_tensor_value_info("image_embeddings", TensorProto.FLOAT,
                                       [1, 256, EMBED, EMBED])],
        [const("w", weights)])
    save(graph, path)


def make_decoder(path, height, width, coords_name="point_coords", layer_norm=False,
                 invert_low_res=False):
    cells = LOW_RES * LOW_RES
    centres = np.arange(LOW_RES, dtype=np.float32) * 4 + 2
    # Negated box terms from box_vec = [x0, y0, x1, y1]: per column j, x0 - X_j and X_j - x1;
    # per row i, y0 - Y_i and Y_i - y1. Each is box_vec @ w + bias (stored transposed for
    # OpenCV's Gemm), then broadcast over the other axis by a nearest-neighbour Resize.
    wx, bx = np.zeros((4, 2 * LOW_RES), np.float32), np.zeros(2 * LOW_RES, np.float32)
    wx[0, :LOW_RES], bx[:LOW_RES] = 1.0, -centres
    wx[2, LOW_RES:], bx[LOW_RES:] = -1.0, centres
    wy, by = np.zeros_like(wx), bx.copy()
    wy[1], wy[3] = wx[0], wx[2]
    scale = IMG / max(height, width)
    resized_h, resized_w = int(height * scale + 0.5), int(width * scale + 0.5)
    low = "low_res_logits" if invert_low_res else "low_res_masks"
    nodes = [
        helper.make_node("Reshape", [coords_name, "shape_box"], ["box_vec"]),
        helper.make_node("Gemm", ["box_vec", "wx", "bx"], ["x_terms"], transB=1),
        helper.make_node("Reshape", ["x_terms", "shape_x"], ["x_row"]),
        helper.make_node("Resize", ["x_row", "roi", "spread_rows"], ["x_maps"], mode="nearest"),
        helper.make_node("Gemm", ["box_vec", "wy", "by"], ["y_terms"], transB=1),
        helper.make_node("Reshape", ["y_terms", "shape_y"], ["y_col"]),
        helper.make_node("Resize", ["y_col", "roi", "spread_cols"], ["y_maps"], mode="nearest"),
        helper.make_node("Slice", ["image_embeddings", "ch_start", "ch_end", "ch_axes"], ["e0"]),
        helper.make_node("Resize", ["e0", "roi", "scales4"], ["e0_up"], mode="linear",
                         coordinate_transformation_mode="half_pixel"),
        helper.make_node("Mul", ["e0_up", "neg_gain"], ["neg_e0"]),
        # min over the 5 terms = -max of the negated ones, as a MaxPool over the last axis.
        helper.make_node("Concat", ["x_maps", "y_maps", "neg_e0"], ["neg_terms"], axis=1),
        helper.make_node("Transpose", ["neg_terms"], ["terms_last"], perm=[0, 2, 3, 1]),
        helper.make_node("Reshape", ["terms_last", "shape_cells"], ["neg_terms_cells"]),
        helper.make_node("MaxPool", ["neg_terms_cells"], ["neg_min"], kernel_shape=[1, 5],
                         strides=[1, 5]),
        helper.make_node("Reshape", ["neg_min", "shape_low"], ["neg_low"]),
        helper.make_node("Mul", ["neg_low", "minus_one"], ["low_res_box"]),
        # OpenCV needs every graph input consumed: mask_input and the remaining prompt inputs
        # enter with zero weight (the real decoder uses them; these tests never set a mask).
        helper.make_node("Mul", ["mask_input", "zero"], ["mask_term"]),
        helper.make_node("Add", ["low_res_box", "mask_term"], [low]),
        helper.make_node("Reshape", ["point_labels", "shape_row2"], ["labels_row"]),
        helper.make_node("Reshape", ["orig_im_size", "shape_row2"], ["size_row"]),
        helper.make_node("Reshape", ["has_mask_input", "shape_row1"], ["has_mask_row"]),
        helper.make_node("Concat", ["labels_row", "size_row", "has_mask_row"], ["aux"], axis=1),
        helper.make_node("LayerNormalization", ["aux", "ln_scale", "ln_bias"], ["aux_ln"], axis=-1)
        if layer_norm else helper.make_node("Identity", ["aux"], ["aux_ln"]),
        helper.make_node("Gemm", ["aux_ln", "aux_w", "aux_b"], ["aux_term"], transB=1),
        helper.make_node("Resize", [low, "roi", "scales4"], ["up1024"], mode="linear",
                         coordinate_transformation_mode="half_pixel"),
        helper.make_node("Slice", ["up1024", "crop_start", "crop_end", "crop_axes"], ["cropped"]),
        helper.make_node("Resize", ["cropped", "roi", "no_scales", "orig_sizes"], ["masks"],
                         mode="linear",
                         coordinate_transformation_mode="half_pixel"),
        helper.make_node("GlobalAveragePool", [low], ["mean_logit"]),
        helper.make_node("Reshape", ["mean_logit", "shape_iou"], ["mean_iou"]),
        helper.make_node("Add", ["mean_iou", "aux_term"], ["iou_predictions"]),
    ]
    if invert_low_res:
        nodes.append(helper.make_node("Mul", [low, "minus_one"], ["low_res_masks"]))
    initializers = [
        const("shape_box", np.array([1, 4], np.int64)),
        const("wx", np.ascontiguousarray(wx.T)), const("bx", bx),
        const("wy", np.ascontiguousarray(wy.T)), const("by", by),
        const("shape_x", np.array([1, 2, 1, LOW_RES], np.int64)),
        const("shape_y", np.array([1, 2, LOW_RES, 1], np.int64)),
        const("spread_rows", np.array([1, 1, LOW_RES, 1], np.float32)),
        const("spread_cols", np.array([1, 1, 1, LOW_RES], np.float32)),
        const("shape_cells", np.array([1, 1, cells, 5], np.int64)),
        const("ch_start", np.array([0], np.int64)), const("ch_end", np.array([1], np.int64)),
        const("ch_axes", np.array([1], np.int64)),
        const("roi", np.zeros((0,), np.float32)),
        const("no_scales", np.zeros((0,), np.float32)),
        const("scales4", np.array([1, 1, 4, 4], np.float32)),
        const("neg_gain", np.array(-EMBED_GAIN, np.float32)),
        const("shape_low", np.array([1, 1, LOW_RES, LOW_RES], np.int64)),
        const("minus_one", np.array(-1.0, np.float32)),
        const("zero", np.array(0.0, np.float32)),
        const("shape_row2", np.array([1, 2], np.int64)),
        const("shape_row1", np.array([1, 1], np.int64)),
        const("aux_w", np.zeros((1, 5), np.float32)),
        const("aux_b", np.zeros((1,), np.float32)),
        const("ln_scale", np.ones((5,), np.float32)),
        const("ln_bias", np.zeros((5,), np.float32)),
        const("crop_start", np.array([0, 0], np.int64)),
        const("crop_end", np.array([resized_h, resized_w], np.int64)),
        const("crop_axes", np.array([2, 3], np.int64)),
        const("orig_sizes", np.array([1, 1, height, width], np.int64)),
        const("shape_iou", np.array([1, 1], np.int64)),
    ]
    f = TensorProto.FLOAT
    inputs = [
        helper.make_tensor_value_info("image_embeddings", f, [1, 256, EMBED, EMBED]),
        helper.make_tensor_value_info(coords_name, f, [1, "num_points", 2]),
        helper.make_tensor_value_info("point_labels", f, [1, "num_points"]),
        helper.make_tensor_value_info("mask_input", f, [1, 1, LOW_RES, LOW_RES]),
        helper.make_tensor_value_info("has_mask_input", f, [1]),
        helper.make_tensor_value_info("orig_im_size", f, [2]),
    ]
    outputs = [
        helper.make_tensor_value_info("masks", f, [1, 1, height, width]),
        helper.make_tensor_value_info("iou_predictions", f, [1, 1]),
        helper.make_tensor_value_info("low_res_masks", f, [1, 1, LOW_RES, LOW_RES]),
    ]
    save(helper.make_graph(nodes, "sam_like_decoder", inputs, outputs, initializers), path,
         17 if layer_norm else 11)


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    out_dir, height, width = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    os.makedirs(out_dir, exist_ok=True)
    make_encoder(os.path.join(out_dir, "encoder.onnx"))
    make_decoder(os.path.join(out_dir, "decoder.onnx"), height, width)
    make_decoder(os.path.join(out_dir, "decoder_wrong_names.onnx"), height, width, "coords")
    make_decoder(os.path.join(out_dir, "decoder_layer_norm.onnx"), height, width, layer_norm=True)
    make_decoder(os.path.join(out_dir, "decoder_inverted_low_res.onnx"), height, width,
                 invert_low_res=True)


if __name__ == "__main__":
    main()

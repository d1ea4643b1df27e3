#!/usr/bin/env python3
"""Rewrite an ultralytics YOLO ONNX export so that OpenCV 4.6 dnn can import and run it.

Usage:
  python3 scripts/prepare_onnx_for_opencv.py IN.onnx OUT.onnx

Needs only python3-onnx (>= 1.12) and numpy; static-shape graphs (ultralytics' default dynamic=False).
  1. Constant folding: nodes whose inputs are all constant are evaluated with numpy (Identity Shape
     Gather Concat (Un)Squeeze Reshape Transpose Slice Cast Range Expand Add Sub Mul Div Neg ...)
     and become initializers; Shape of a tensor with a statically inferred shape is folded too.
  2. A constant Add/Sub/Mul/Div operand smaller than the variable one is broadcast to full shape.
  3. Split with a size input (opset >= 13): equal sizes -> input dropped, else one Slice per output.
  4. MatMul(A, B) * scalar (A, B variables) -> MatMul(A * scalar, B).
  Dead nodes/initializers and stale value_info are removed; the result passes onnx.checker.

Why (what the OpenCV 4.6.0 importer does with torch.onnx exports of YOLOv8/YOLO11 otherwise):
  - Identity on an initializer (torch dedups equal tensors, e.g. the equal Detect box biases of
    untrained weights): "Identity ... (-215) inputs.size() in function 'getMemoryShapes'".
  - Shape->Gather->Add->Div chain of dist2bbox's Slice:
    "Add ... (-215) blob_0.size == blob_1.size in function 'parseBias'".
  - stride constant [1,8400] * [1,4,8400]: imports, then forward() fails with
    "(-215) start <= (int)shape.size() && ... in function 'total'".
  - Split sizes given as input are ignored (equal split): YOLO11 C2PSA [32,32,64] -> "(-215) splits > 0
    && inpShape[axis_rw] % splits == 0"; Detect [64,80] -> "dfl/Reshape ... computeShapeByReshapeMask".
  - YOLO11 C2PSA attention scale (MatMul then Mul 0.1768): with fusion on (the default) the scale is
    fused into the MatMul layer and lost -> silently wrong output (boxes off by ~170 px).

Verified with ultralytics 8.3.40 exports (torch 1.13, onnx 1.12; imgsz 640, batch 1, simplify=False)
  of YOLOv8n and YOLO11n detect models at opsets 12, 13, 14, 15, 16, 17: all import and run in
  OpenCV 4.6.0 (Debian 12); output0 [1,84,8400] matches the TorchScript export to 3.2e-5 in class
  scores and 3.5e-3 px in boxes (float32 noise: TorchScript vs eager PyTorch differ by 4.3e-3 px).
  Untested: seg/pose/obb heads, YOLOv10/end2end, dynamic=True, other OpenCV versions.

Exit codes: 0 ok, 1 rewrite failed, 2 bad arguments or missing/unreadable/corrupt input.
"""
import collections
import os
import sys

import numpy as np

try:
    import onnx
    from onnx import helper, numpy_helper, shape_inference
except ImportError:
    sys.exit("prepare_onnx_for_opencv: error: python module 'onnx' missing (apt-get install python3-onnx)")

NP_TYPE = getattr(helper, "tensor_dtype_to_np_dtype", None) or onnx.mapping.TENSOR_TYPE_TO_NP_TYPE.get


def fail(msg, code=1):
    print(f"prepare_onnx_for_opencv: error: {msg}", file=sys.stderr)
    sys.exit(code)


def attrs_of(node):
    return {a.name: helper.get_attribute_value(a) for a in node.attribute}


def init_values(g):
    return {i.name: numpy_helper.to_array(i) for i in g.initializer}


def replace_nodes(g, nodes):
    del g.node[:]
    g.node.extend(nodes)


def static_shapes(model):
    """Tensor name -> dims, for every tensor whose shape is fully known."""
    try:
        g = shape_inference.infer_shapes(model).graph
    except Exception as e:  # not fatal: we just fold less
        print(f"prepare_onnx_for_opencv: warning: shape inference failed: {e}", file=sys.stderr)
        g = model.graph
    shapes = {i.name: tuple(i.dims) for i in g.initializer}
    for vi in list(g.input) + list(g.value_info) + list(g.output):
        t = vi.type.tensor_type
        if t.HasField("shape") and all(d.HasField("dim_value") for d in t.shape.dim):
            shapes[vi.name] = tuple(d.dim_value for d in t.shape.dim)
    return shapes


def slice_np(data, starts, ends, axes=None, steps=None):
    axes = range(len(starts)) if axes is None else axes
    steps = [1] * len(starts) if steps is None else steps
    idx = [slice(None)] * data.ndim
    for s, e, a, st in zip(starts, ends, axes, steps):
        idx[int(a)] = slice(int(s), int(e), int(st))  # python slicing clamps like ONNX
    return data[tuple(idx)]


def evaluate(op, x, at, opset):
    """numpy result of op on constant inputs x (trailing omitted inputs removed); None if unhandled."""
    if op in ("Add", "Sub", "Mul", "Pow"):
        f = {"Add": np.add, "Sub": np.subtract, "Mul": np.multiply, "Pow": np.power}[op]
        return np.asarray(f(x[0], x[1])).astype(x[0].dtype)
    if op == "Div":  # ONNX integer division truncates
        q = np.true_divide(x[0], x[1])
        return (np.trunc(q) if np.issubdtype(x[0].dtype, np.integer) else q).astype(x[0].dtype)
    simple = {"Identity": lambda: x[0], "Neg": lambda: -x[0], "Sqrt": lambda: np.sqrt(x[0]),
              "Equal": lambda: np.equal(x[0], x[1]), "Where": lambda: np.where(x[0], x[1], x[2]),
              "Cast": lambda: x[0].astype(NP_TYPE(at["to"])),
              "Gather": lambda: np.take(x[0], x[1], axis=at.get("axis", 0)),
              "Concat": lambda: np.concatenate(x, axis=at["axis"]),
              "Transpose": lambda: np.transpose(x[0], at.get("perm")),
              "Range": lambda: np.arange(x[0], x[1], x[2]).astype(x[0].dtype),
              "Expand": lambda: x[0] * np.ones(tuple(x[1]), dtype=x[0].dtype)}
    if op in simple:
        return simple[op]()
    if op in ("Unsqueeze", "Squeeze"):
        axes = at.get("axes") if opset < 13 else (x[1].tolist() if len(x) > 1 else None)
        if op == "Squeeze":
            return np.squeeze(x[0], axis=None if axes is None else tuple(axes))
        r = x[0]
        for a in sorted(a % (r.ndim + len(axes)) for a in axes):
            r = np.expand_dims(r, a)
        return r
    if op == "Reshape":
        keep0 = not at.get("allowzero", 0)
        return x[0].reshape([x[0].shape[i] if s == 0 and keep0 else s for i, s in enumerate(x[1])])
    if op == "Slice":
        return slice_np(x[0], at["starts"], at["ends"], at.get("axes")) if opset < 10 else slice_np(*x)
    return None


def fold_constants(model):
    """Pass 1; returns the number of folded nodes."""
    g = model.graph
    opset = max([o.version for o in model.opset_import if o.domain in ("", "ai.onnx")] or [1])
    shapes, consts = static_shapes(model), init_values(g)
    kept = []
    for node in g.node:
        at, val = attrs_of(node), None
        if node.op_type == "Constant" and "value" in at:
            val = numpy_helper.to_array(at["value"])
        elif node.op_type == "Shape" and node.input[0] in shapes:
            val = np.array(shapes[node.input[0]], dtype=np.int64)[at.get("start", 0):at.get("end")]
        elif len(node.output) == 1 and node.domain in ("", "ai.onnx") and node.input \
                and all(i == "" or i in consts for i in node.input):
            args = [consts[i] if i else None for i in node.input]
            while args[-1] is None:
                args.pop()
            try:
                val = evaluate(node.op_type, args, at, opset)
            except Exception as e:
                fail(f"cannot fold node '{node.name}' ({node.op_type}): {e}")
        if val is None:
            kept.append(node)
        else:
            consts[node.output[0]] = np.asarray(val)
    folded = len(g.node) - len(kept)
    replace_nodes(g, kept)
    del g.initializer[:]
    g.initializer.extend(numpy_helper.from_array(v, k) for k, v in consts.items())
    return folded


def expand_broadcast_constants(model):
    """Pass 2."""
    g = model.graph
    shapes, consts, changed = static_shapes(model), init_values(g), 0
    for k, node in enumerate(g.node):
        if node.op_type not in ("Add", "Sub", "Mul", "Div") or len(node.input) != 2:
            continue
        ci = [j for j, n in enumerate(node.input) if n in consts]
        if len(ci) != 1 or node.input[1 - ci[0]] not in shapes:
            continue
        c, vshape = consts[node.input[ci[0]]], shapes[node.input[1 - ci[0]]]
        if c.size == 1 or c.shape == vshape:
            continue
        if np.broadcast_shapes(c.shape, vshape) != tuple(vshape):
            fail(f"node '{node.name}': constant {c.shape} would broadcast the variable {vshape}")
        name = f"{node.input[ci[0]]}__expanded{k}"
        g.initializer.append(numpy_helper.from_array(np.ascontiguousarray(np.broadcast_to(c, vshape)), name))
        node.input[ci[0]] = name
        changed += 1
    return changed


def split_sizes_to_slices(model):
    """Pass 3."""
    g = model.graph
    consts, nodes, changed = init_values(g), [], 0
    for node in g.node:
        if node.op_type != "Split" or len(node.input) < 2 or node.input[1] not in consts:
            nodes.append(node)
            continue
        sizes, axis = [int(v) for v in consts[node.input[1]]], attrs_of(node).get("axis", 0)
        changed += 1
        if len(set(sizes)) == 1 and len(sizes) == len(node.output):
            del node.input[1]
            nodes.append(node)
            continue
        bounds = np.cumsum([0] + sizes)
        for j, out in enumerate(node.output):
            names = [f"{out}__{p}" for p in ("starts", "ends", "axes")]
            for nm, v in zip(names, (bounds[j], bounds[j + 1], axis)):
                g.initializer.append(numpy_helper.from_array(np.array([v], dtype=np.int64), nm))
            nodes.append(helper.make_node("Slice", [node.input[0]] + names, [out], name=f"{node.name}__{j}"))
    replace_nodes(g, nodes)
    return changed


def scale_before_matmul(model):
    """Pass 4."""
    g = model.graph
    consts = init_values(g)
    producer = {o: n for n in g.node for o in n.output}
    uses = collections.Counter(i for n in g.node for i in n.input)
    moved, drop = {}, set()
    for node in g.node:
        if node.op_type not in ("Mul", "Div") or len(node.input) != 2 or node.input[1] not in consts \
                or consts[node.input[1]].size != 1:
            continue
        mm = producer.get(node.input[0])
        if mm is None or mm.op_type != "MatMul" or uses[node.input[0]] != 1 or any(i in consts for i in mm.input):
            continue
        s = consts[node.input[1]].reshape(())
        s = s if node.op_type == "Mul" else (1.0 / s).astype(s.dtype)
        sname, scaled = f"{node.name}__scale", f"{mm.input[0]}__scaled_{node.name}"
        g.initializer.append(numpy_helper.from_array(np.array(s), sname))
        moved[id(mm)] = (helper.make_node("Mul", [mm.input[0], sname], [scaled], name=scaled), node.output[0])
        drop.add(id(node))
    nodes = []
    for node in g.node:
        if id(node) in moved:
            scale_node, out = moved[id(node)]
            nodes.append(scale_node)
            node.input[0], node.output[0] = scale_node.output[0], out
        if id(node) not in drop:
            nodes.append(node)
    replace_nodes(g, nodes)
    return len(moved)


def cleanup(model):
    """Drop dead nodes, unused initializers, weights listed as graph inputs, stale value_info."""
    g = model.graph
    needed, nodes = {o.name for o in g.output}, []
    for node in reversed(list(g.node)):
        if any(o in needed for o in node.output):
            nodes.append(node)
            needed.update(node.input)
    replace_nodes(g, nodes[::-1])
    produced = {o for n in g.node for o in n.output} | {i.name for i in g.input}
    for o in g.output:
        if o.name not in produced:
            fail(f"graph output '{o.name}' became a constant; nothing left to run")
    inits = [i for i in g.initializer if i.name in needed]
    del g.initializer[:]
    g.initializer.extend(inits)
    names = {i.name for i in inits}
    inputs = [i for i in g.input if i.name not in names]
    del g.input[:]
    g.input.extend(inputs)
    del g.value_info[:]


def main(argv):
    if len(argv) != 3:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 0 if len(argv) == 2 and argv[1] in ("-h", "--help") else 2
    src, dst = argv[1], argv[2]
    if not os.path.isfile(src):
        fail(f"input file not found (or not a regular file): {src}", 2)
    try:
        model = onnx.load(src)
        onnx.checker.check_model(model)
    except Exception as e:
        fail(f"{src} is not a readable ONNX model (corrupt or truncated?): {e}", 2)
    if not model.graph.node:
        fail(f"{src}: graph has no nodes", 2)
    n0 = len(model.graph.node)
    folded = fold_constants(model)
    cleanup(model)
    counts = (expand_broadcast_constants(model), split_sizes_to_slices(model), scale_before_matmul(model))
    cleanup(model)
    try:
        onnx.checker.check_model(model)
        onnx.save(model, dst)
    except Exception as e:
        fail(f"could not write a valid model to {dst}: {e}")
    print(f"{src}: {n0} -> {len(model.graph.node)} nodes ({folded} folded, {counts[0]} broadcasts "
          f"expanded, {counts[1]} Splits fixed, {counts[2]} MatMul scales moved) -> {dst}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

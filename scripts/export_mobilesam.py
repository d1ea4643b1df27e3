#!/usr/bin/env python3
"""Export MobileSAM (TinyViT "vit_t") to TorchScript for the C++ side (libtorch 1.13).

Usage:
  python3 scripts/export_mobilesam.py --repo MOBILESAM_CHECKOUT --checkpoint mobile_sam.pt \
      --out DIR [--model-type vit_t]

  MOBILESAM_CHECKOUT is a clone of https://github.com/ChaoningZhang/MobileSAM (the directory that
  contains the `mobile_sam` package). timm is not needed: a minimal stand-in is used if missing.

Writes (CPU, float32, traced with torch.jit.trace):
  DIR/mobilesam_encoder.pt
    forward(image) -> image_embeddings
      image            float32 [1,3,1024,1024], already SAM-preprocessed, i.e. exactly sam.preprocess()
                       output: RGB, resized so the longest side is 1024 (ResizeLongestSide),
                       (x - [123.675,116.28,103.53]) / [58.395,57.12,57.375], zero-padded bottom/right.
      image_embeddings float32 [1,256,64,64]
  DIR/mobilesam_decoder.pt
    forward(image_embeddings, point_coords, point_labels) -> (low_res_masks, iou_predictions)
      image_embeddings float32 [1,256,64,64]
      point_coords     float32 [1,N,2]  (x, y) in the resized 1024 frame (ResizeLongestSide.apply_coords)
      point_labels     float32 [1,N]    -1 not-a-point (padding), 0 background, 1 foreground,
                                         2 box top-left, 3 box bottom-right
      low_res_masks    float32 [1,1,256,256] mask logits (single-mask output, multimask_output=False)
      iou_predictions  float32 [1,1]
    Box = 2 points (x0,y0,label 2),(x1,y1,label 3), no padding point: equals SamPredictor.predict(
    box=..., multimask_output=False). Point-only prompts: append a padding point (0,0) label -1, as
    SamPredictor does. No mask input. Full-res logits = sam.postprocess_masks: bilinear to 1024x1024,
    crop to the resized size, bilinear to the original size (align_corners=False).

Exit codes: 0 ok, 1 verification failed, 2 bad arguments (repo/checkpoint missing or not matching).
"""
import argparse
import collections.abc
import os
import sys
import types
import warnings

import torch
from torch import nn


def fail(msg, code=2):
    print(f"export_mobilesam: error: {msg}", file=sys.stderr)
    sys.exit(code)


def install_timm_standin():
    """Provide the few timm symbols tiny_vit_sam.py imports, if timm itself is unavailable:
    `from timm.models.layers import DropPath, to_2tuple, trunc_normal_`
    `from timm.models.registry import register_model`"""
    try:
        import timm  # noqa: F401
        return False
    except Exception:  # not installed (or broken): drop partial imports, use the stand-in
        for name in [n for n in sys.modules if n == "timm" or n.startswith("timm.")]:
            del sys.modules[name]

    class DropPath(nn.Module):
        """Stochastic depth per sample; identity in eval mode or with drop_prob 0."""
        def __init__(self, drop_prob=None, scale_by_keep=True):
            super().__init__()
            self.drop_prob, self.scale_by_keep = drop_prob, scale_by_keep

        def forward(self, x):
            p = float(self.drop_prob or 0.0)
            if p == 0.0 or not self.training:
                return x
            keep = 1.0 - p
            mask = x.new_empty((x.shape[0],) + (1,) * (x.ndim - 1)).bernoulli_(keep)
            if keep > 0.0 and self.scale_by_keep:
                mask.div_(keep)
            return x * mask

    def to_2tuple(x):
        if isinstance(x, collections.abc.Iterable) and not isinstance(x, str):
            return tuple(x)
        return (x, x)

    def trunc_normal_(tensor, mean=0.0, std=1.0, a=-2.0, b=2.0):
        return nn.init.trunc_normal_(tensor, mean=mean, std=std, a=a, b=b)

    def register_model(fn):  # timm's model registry is irrelevant here
        return fn

    mods = {n: types.ModuleType(n) for n in ("timm", "timm.models", "timm.models.layers", "timm.models.registry")}
    for m in mods.values():
        m.__path__ = []  # mark as package
    mods["timm"].models = mods["timm.models"]
    mods["timm.models"].layers, mods["timm.models"].registry = mods["timm.models.layers"], mods["timm.models.registry"]
    vars(mods["timm.models.layers"]).update(DropPath=DropPath, to_2tuple=to_2tuple, trunc_normal_=trunc_normal_)
    mods["timm.models.registry"].register_model = mods["timm.models"].register_model = register_model
    sys.modules.update(mods)
    return True


class Encoder(nn.Module):
    def __init__(self, sam):
        super().__init__()
        self.image_encoder = sam.image_encoder

    def forward(self, image):
        return self.image_encoder(image)


class Decoder(nn.Module):
    """Prompt embedding as in SamOnnxModel._embed_points + mask decoder, single-mask output."""

    def __init__(self, sam):
        super().__init__()
        pe = sam.prompt_encoder
        self.pe_layer, self.point_embeddings = pe.pe_layer, pe.point_embeddings
        self.not_a_point_embed, self.no_mask_embed = pe.not_a_point_embed, pe.no_mask_embed
        self.mask_decoder = sam.mask_decoder
        self.img_size = float(sam.image_encoder.img_size)
        with torch.no_grad():
            self.register_buffer("image_pe", pe.get_dense_pe().clone())  # constant [1,256,64,64]

    def forward(self, image_embeddings, point_coords, point_labels):
        coords = (point_coords + 0.5) / self.img_size  # pixel centre, normalised to [0,1]
        sparse = self.pe_layer._pe_encoding(coords)  # [1,N,256]
        labels = point_labels.unsqueeze(-1)  # broadcast over channels, no baked N
        sparse = sparse * (labels != -1) + self.not_a_point_embed.weight * (labels == -1)
        for i, emb in enumerate(self.point_embeddings):
            sparse = sparse + emb.weight * (labels == i)
        dense = self.no_mask_embed.weight.reshape(1, -1, 1, 1)  # broadcast to [B,256,64,64]
        masks, iou = self.mask_decoder.predict_masks(image_embeddings, self.image_pe, sparse, dense)
        return masks[:, 0:1], iou[:, 0:1]  # multimask_output=False


def load_sam(repo, checkpoint, model_type):
    if not os.path.isdir(os.path.join(repo, "mobile_sam")):
        fail(f"--repo {repo!r} is not a MobileSAM checkout (no mobile_sam/ package inside)")
    if not os.path.isfile(checkpoint):
        fail(f"--checkpoint {checkpoint!r} does not exist")
    standin = install_timm_standin()
    sys.path.insert(0, os.path.abspath(repo))
    from mobile_sam import sam_model_registry

    if model_type not in sam_model_registry:
        fail(f"unknown --model-type {model_type!r}; choices: {sorted(sam_model_registry)}")
    print(f"timm: {'minimal stand-in' if standin else 'installed package'}")
    sam = sam_model_registry[model_type](checkpoint=None)
    try:
        state = torch.load(checkpoint, map_location="cpu")
    except Exception as e:
        fail(f"cannot read checkpoint {checkpoint!r}: {e}")
    if not isinstance(state, collections.abc.Mapping):
        fail(f"checkpoint {checkpoint!r} is not a state_dict (got {type(state).__name__})")
    expected = sam.state_dict()
    missing = [k for k in expected if k not in state]
    unexpected = [k for k in state if k not in expected]
    badshape = [f"{k} {tuple(getattr(state[k], 'shape', ()))}!={tuple(v.shape)}"
                for k, v in expected.items() if k in state and tuple(getattr(state[k], "shape", ())) != tuple(v.shape)]
    def brief(keys):
        return ", ".join(keys[:5]) + (f", ... ({len(keys)} total)" if len(keys) > 5 else "")
    if missing or unexpected or badshape:
        fail(f"checkpoint does not fit model '{model_type}': " + "; ".join(
            f"{what}: {brief(keys)}" for what, keys in
            (("missing keys", missing), ("unexpected keys", unexpected), ("shape mismatch", badshape)) if keys))
    sam.load_state_dict(state)
    # eval() AFTER loading: TinyViT caches its attention biases ('ab') in Attention.train(False).
    return sam.float().cpu().eval()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repo", required=True, help="MobileSAM checkout (contains mobile_sam/)")
    ap.add_argument("--checkpoint", required=True, help="MobileSAM weights, e.g. mobile_sam.pt")
    ap.add_argument("--out", required=True, help="output directory")
    ap.add_argument("--model-type", default="vit_t")
    args = ap.parse_args()

    sam = load_sam(args.repo, args.checkpoint, args.model_type)
    os.makedirs(args.out, exist_ok=True)
    enc_path = os.path.join(args.out, "mobilesam_encoder.pt")
    dec_path = os.path.join(args.out, "mobilesam_decoder.pt")
    encoder, decoder = Encoder(sam).eval(), Decoder(sam).eval()

    torch.manual_seed(0)
    image = torch.randn(1, 3, 1024, 1024)
    box = torch.tensor([[[300.0, 200.0], [700.0, 650.0]]]), torch.tensor([[2.0, 3.0]])
    pts = torch.tensor([[[512.0, 400.0], [100.0, 900.0], [0.0, 0.0]]]), torch.tensor([[1.0, 0.0, -1.0]])
    with torch.no_grad(), warnings.catch_warnings():
        warnings.filterwarnings("ignore", category=torch.jit.TracerWarning)
        emb = encoder(image)
        torch.jit.trace(encoder, (image,)).save(enc_path)
        torch.jit.trace(decoder, (emb,) + pts).save(dec_path)

    with torch.no_grad():  # verify the saved files against the eager model
        enc_ts, dec_ts = torch.jit.load(enc_path), torch.jit.load(dec_path)
        pe = sam.prompt_encoder
        checks = [("encoder traced vs eager", [enc_ts(image)], [emb])]
        for name, (c, l) in (("box N=2", box), ("points N=3", pts),
                             ("points N=5", (torch.rand(1, 5, 2) * 1024, torch.tensor([[1.0, 0, 1, 0, -1]])))):
            checks.append((f"decoder traced vs eager, {name}", dec_ts(emb, c, l), decoder(emb, c, l)))
        # the original prompt encoder path, as SamPredictor.predict_torch runs it (pads point prompts itself)
        for name, prompt, (c, l) in (("box", dict(points=None, boxes=box[0].reshape(1, 4)), box),
                                     ("points", dict(points=(pts[0][:, :2], pts[1][:, :2]), boxes=None), pts)):
            sparse, dense = pe(masks=None, **prompt)
            ref = sam.mask_decoder(emb, pe.get_dense_pe(), sparse, dense, multimask_output=False)
            checks.append((f"decoder traced vs mobile_sam prompt_encoder+mask_decoder, {name}", dec_ts(emb, c, l), ref))
    ok = True
    for name, a, b in checks:
        d = max((x - y).abs().max().item() for x, y in zip(a, b))
        print(f"{name}: max abs diff {d:.3g}")
        ok &= d < 1e-4  # NaN fails too
    print(f"wrote {enc_path}\nwrote {dec_path}")
    if not ok:
        fail("verification failed (difference above 1e-4)", code=1)


if __name__ == "__main__":
    main()

"""Warn when USD rescales the time samples of a sublayer or reference because its rate differs.

USD's layer-offset rule: a sublayer, reference or payload whose ``timeCodesPerSecond`` differs from the
root layer's (falling back to ``framesPerSecond``, then 24, when not authored) has its time samples scaled
by root rate / layer rate. A wrapper layer without ``timeCodesPerSecond`` around a 30 fps cache therefore
reads samples 10, 20 as 8, 16, and every reported time follows. That is USD's answer and usdksl keeps it
(times are reported in the root layer's time codes), but it is rarely what the author meant, so each such
layer gets one warning line.

Only layers that hold opinions on the prims that move the loaded meshes (the meshes, their ancestors, their
skeletons and animations, their instancers) are looked at, through each prim's stack of specs with its
layer offsets (``Usd.Prim.GetPrimStackWithLayerOffsets``). A layer whose rate differs but whose authored
offset scale cancels the difference is not rescaled and not reported; an authored offset scale between
layers of equal rate is a deliberate retime and not reported either.
"""

from __future__ import annotations

from typing import Dict, Iterable, List

from pxr import Sdf, Usd

#: The rate USD assumes for a layer that authors neither timeCodesPerSecond nor framesPerSecond.
DEFAULT_TIME_CODES_PER_SECOND = 24.0
#: Relative difference below which two rates (or a scale and 1) count as equal.
RATE_TOLERANCE = 1e-9


def layer_rate(layer: Sdf.Layer) -> float:
    """The time codes per second USD uses for ``layer``'s samples."""
    if layer.HasTimeCodesPerSecond():
        return float(layer.timeCodesPerSecond)
    if layer.HasFramesPerSecond():
        return float(layer.framesPerSecond)
    return DEFAULT_TIME_CODES_PER_SECOND


def _differs(a: float, b: float) -> bool:
    return abs(a - b) > RATE_TOLERANCE * max(abs(a), abs(b), 1.0)


def _specs_with_offsets(prim: Usd.Prim):
    if hasattr(prim, "GetPrimStackWithLayerOffsets"):
        return prim.GetPrimStackWithLayerOffsets()
    return [(spec, None) for spec in prim.GetPrimStack()]   # older USD: rates only


def rescaled_layers(stage: Usd.Stage, prims: Iterable[Usd.Prim]) -> Dict[str, tuple]:
    """{layer identifier: (layer rate, stage rate, scale)} for the layers whose samples of ``prims`` (or
    their ancestors) USD rescales because of a rate mismatch."""
    stage_rate = float(stage.GetTimeCodesPerSecond())
    seen_prims = set()
    found: Dict[str, tuple] = {}
    for prim in prims:
        probe = prim
        while probe and not probe.IsPseudoRoot() and probe.GetPath() not in seen_prims:
            seen_prims.add(probe.GetPath())
            for spec, offset in _specs_with_offsets(probe):
                layer = spec.layer
                if layer.identifier in found:
                    continue
                rate = layer_rate(layer)
                if not _differs(rate, stage_rate):
                    continue
                scale = stage_rate / rate if offset is None else float(offset.scale)
                if _differs(scale, 1.0):
                    found[layer.identifier] = (rate, stage_rate, scale)
            probe = probe.GetParent()
    return found


def rescaled_layer_warnings(stage: Usd.Stage, prims: Iterable[Usd.Prim], file: str) -> List[str]:
    """One warning line per rescaled layer (module docstring)."""
    return [f"{file}: layer {identifier} has timeCodesPerSecond {rate:g} but the root layer has {stage_rate:g}: "
            f"USD scales its time samples by {scale:g}, and times are reported in the root layer's time codes"
            for identifier, (rate, stage_rate, scale) in sorted(rescaled_layers(stage, prims).items())]

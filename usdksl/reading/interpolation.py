"""Values USD does not interpolate from time samples: what "Held interpolation" means for a cache.

usdksl's flightplans are linear between the time samples of ``points`` and of the xformOps above a mesh
(docs/contracts.md, Motion). A file can make USD evaluate motion some other way:

* **Spline-valued xformOps** (USD >= 24: ``float xformOp:rotateY.spline = { 0: 0; post held, 10: 90 }``):
  the attribute has no time samples at all, so a reader that merges time samples sees a mesh that never
  moves, while USD holds the value and then jumps (``held`` knots) or follows a curve. Checking such a
  shot would silently miss contacts, so it is an input error (exit 2) naming the prim, the attribute and
  the first knot's time: bake the spline to time samples first.
* **Arrays whose size changes between samples** (e.g. ``points`` with 100 then 120 entries): USD cannot
  blend them and holds the earlier value. The loader reports these as a points count / topology change.
* ``Usd.Stage.SetInterpolationType(Held)`` is a runtime setting of one opened stage and is not stored in
  files; the loader opens its own stage with the default linear interpolation.
"""

from __future__ import annotations

from typing import Iterable, Optional, Tuple

from ..errors import UsdkslInputError


def _knot_summary(spline) -> Tuple[Optional[float], str]:
    """(first knot time, 'held' or 'curve'/'linear' of the first knot that is not linear)."""
    from pxr import Ts

    knot_map = spline.GetKnots()
    knots = [knot_map[time] for time in sorted(knot_map.keys())]
    first_time = float(knots[0].GetTime()) if knots else None
    for knot in knots:
        if knot.GetNextInterpolation() == Ts.InterpHeld:
            return float(knot.GetTime()), "held"
    return first_time, "spline"


def find_spline_motion(stage, mesh_paths: Iterable[str]) -> Optional[Tuple[str, str, Optional[float], str]]:
    """The first (prim path, attribute name, time, 'held'|'spline') that animates a mesh through a spline:
    an xformOp of the mesh or of an ancestor up to a resetXformStack, or the points attribute."""
    from pxr import UsdGeom

    from .meshes import transform_chain

    seen = set()
    for mesh_path in mesh_paths:
        prim = stage.GetPrimAtPath(str(mesh_path))
        candidates = [UsdGeom.Mesh(prim).GetPointsAttr()] if prim else []
        for xformable in transform_chain(prim):
            if xformable.GetPath() not in seen:
                seen.add(xformable.GetPath())
                candidates.extend(op.GetAttr() for op in xformable.GetOrderedXformOps())
        for attribute in candidates:
            if attribute and hasattr(attribute, "HasSpline") and attribute.HasSpline():
                time, how = _knot_summary(attribute.GetSpline())
                return str(attribute.GetPrim().GetPath()), attribute.GetName(), time, how
    return None


def reject_spline_motion(stage, mesh_paths: Iterable[str], file: str) -> None:
    """Raise UsdkslInputError when any checked mesh moves through a spline (see module docstring)."""
    found = find_spline_motion(stage, mesh_paths)
    if found is None:
        return
    prim, attribute, time, how = found
    kind = "held interpolation" if how == "held" else "spline interpolation"
    raise UsdkslInputError(
        f"{attribute} is a spline with {kind}: usdksl reads motion from time samples only and would see "
        f"no motion; bake the spline to time samples", file=file, prim=prim, time=time)

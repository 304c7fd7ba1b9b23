"""Reading USD: the stage as world-space arrays, and which meshes and pairs are checked."""

from .loader import MeshData, Shot, load_shot
from .scope import Plan, ScopeOptions, plan_shot

__all__ = ["MeshData", "Plan", "ScopeOptions", "Shot", "load_shot", "plan_shot"]

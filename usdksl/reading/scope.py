"""Scene scoping: which mesh pairs ``usdksl check`` simulates, and why it leaves the others out.

Two layers:

* :func:`read_scene_flags` asks the USD stage what the scene says about each mesh (UsdPhysics collision
  flags, filtered pairs, collision groups, purpose, visibility, ``usdksl:selfCollision``).
* :func:`plan_pairs` is a pure function of those flags, the meshes' motion and the user's options; it
  works on N x N boolean matrices (no loop over pairs) and is tested without a stage or the core.

Rules (docs/contracts.md, What is checked), in the order a skipped pair is explained:

1. A skipped mesh takes all its pairs with it. Meshes are skipped when ``--prims`` / ``--exclude``
   leave them out, when ``physics:collisionEnabled`` is false on the mesh, when their computed purpose
   is ``guide`` (unless ``--include-guides``), or when they are invisible at every moment of the checked
   range (unless ``--include-invisible``). A mesh that is visible for part of the range is checked over
   the whole range: conservative, since a contact while invisible is still reported.
2. Self pairs: only meshes that deform. A mesh that never moves (static, or all samples equal) is a
   collider only; a rigidly moving mesh cannot collide with itself; ``usdksl:selfCollision = false``
   on the mesh or its nearest ancestor that authors it turns the self check off; so does ``--no-self``.
3. Inter pairs: ``--no-inter`` turns them all off; ``physics:filteredPairs`` between the meshes (or
   prims above them) skips the pair; collision groups skip the pair only when *every* combination of a
   group of one mesh and a group of the other is filtered (conservative when a mesh is in several
   groups; a mesh in no group collides with everything); two meshes that both never move are skipped.
4. Default scope: a pair needs a deforming mesh. Inter pairs of two meshes that only move rigidly (or one
   rigid and one still) are left out unless ``--rigid`` (``ScopeOptions.rigid``); the plan counts them.
   Characters' collision proxies and falling props otherwise drown the cloth's contacts.

For PointInstancer instances the scene flags are the instancer's (``MeshData.scene_path``).
"""

from __future__ import annotations

import fnmatch
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from .positions import samples_all_alike

# Reasons a mesh is left out (mesh level).
MESH_EXCLUDED_BY_PATTERN = "excluded by --prims/--exclude"
MESH_COLLISION_DISABLED = "physics:collisionEnabled = false"
MESH_GUIDE = "purpose guide (use --include-guides)"
MESH_INVISIBLE = "invisible over the whole checked range (use --include-invisible)"
MESH_ABSENT = "no points over this stretch (empty or blocked samples, or a topology change)"

# Reasons a pair is left out (pair level), in the order they are tried.
PAIR_MESH_SKIPPED = "a mesh of the pair is skipped"
PAIR_SELF_DISABLED_BY_OPTION = "self checks off (--no-self)"
PAIR_SELF_STATIC = "never moves: collider only"
PAIR_SELF_RIGID = "rigid: cannot collide with itself"
PAIR_SELF_DISABLED_BY_ATTRIBUTE = "usdksl:selfCollision = false"
PAIR_INTER_DISABLED_BY_OPTION = "inter checks off (--no-inter)"
PAIR_FILTERED = "physics:filteredPairs"
PAIR_COLLISION_GROUP = "collision groups filter each other"
PAIR_STATIC_STATIC = "both never move"
PAIR_RIGID_ONLY = "neither deforms (use --rigid)"

# Reasons a pair is checked.
PAIR_CHECK_SELF = "self: deforms"
PAIR_CHECK_INTER = "inter: at least one moves"


@dataclass(frozen=True)
class ScopeOptions:
    """What the user asked for on the command line."""

    self_check: bool = True
    inter_check: bool = True
    include: Tuple[str, ...] = ()   # fnmatch patterns on prim paths; empty means every mesh
    exclude: Tuple[str, ...] = ()   # fnmatch patterns on prim paths
    include_guides: bool = False
    include_invisible: bool = False
    rigid: bool = False             # also check pairs in which neither mesh deforms


@dataclass
class SceneFlags:
    """What the scene says about each of N meshes (same order as the mesh list)."""

    collision_enabled: np.ndarray          # bool[N]
    guide: np.ndarray                      # bool[N]
    invisible: np.ndarray                  # bool[N], invisible at every moment of the checked range
    self_collision: np.ndarray             # bool[N], usdksl:selfCollision (default true)
    filtered: np.ndarray                   # bool[N, N], symmetric: physics:filteredPairs
    group_filtered: np.ndarray             # bool[N, N], symmetric: collision groups forbid the pair
    #: bool[N]: no points over the checked stretch (usdksl.reading.segments); None: every mesh has points.
    absent: Optional[np.ndarray] = None

    @classmethod
    def permissive(cls, count: int) -> "SceneFlags":
        """A scene that says nothing: everything collides."""
        return cls(collision_enabled=np.ones(count, bool), guide=np.zeros(count, bool),
                   invisible=np.zeros(count, bool), self_collision=np.ones(count, bool),
                   filtered=np.zeros((count, count), bool), group_filtered=np.zeros((count, count), bool))


@dataclass
class Plan:
    """The pairs to check, each with its reason, and everything left out with its reason."""

    paths: List[str]
    kinds: List[str]
    moving: np.ndarray                                   # bool[N]
    pairs: np.ndarray                                    # int32[P, 2], i <= j, sorted
    pair_reasons: List[str]                              # len P
    skipped_meshes: Dict[int, str] = field(default_factory=dict)
    skipped_pairs: List[Tuple[int, int, str]] = field(default_factory=list)
    notes: List[str] = field(default_factory=list)
    excluded_paths: List[str] = field(default_factory=list)   # meshes --prims/--exclude kept from loading

    @property
    def mesh_count(self) -> int:
        return len(self.paths)

    @property
    def possible_pairs(self) -> int:
        """Every self pair plus every unordered inter pair among the loaded meshes."""
        count = self.mesh_count
        return count * (count + 1) // 2

    @property
    def checked_pairs(self) -> int:
        return int(len(self.pairs))

    def skipped_pair_counts(self) -> Dict[str, int]:
        counts: Dict[str, int] = {}
        for _, _, reason in self.skipped_pairs:
            counts[reason] = counts.get(reason, 0) + 1
        return counts

    def describe(self, max_listed: int = 20) -> List[str]:
        """Human lines: the counter, the checked pairs, and why the rest is left out."""
        lines = [f"pairs checked: {self.checked_pairs} of {self.possible_pairs} possible "
                 f"({self.mesh_count} meshes, {int(self.moving.sum())} moving)"]
        for (i, j), reason in list(zip(self.pairs.tolist(), self.pair_reasons))[:max_listed]:
            name = self.paths[i] if i == j else " x ".join(sorted((self.paths[i], self.paths[j])))
            lines.append(f"  check {name}: {reason}")
        if self.checked_pairs > max_listed:
            lines.append(f"  ... and {self.checked_pairs - max_listed} more checked pairs")
        for index in sorted(self.skipped_meshes):
            lines.append(f"  skip mesh {self.paths[index]}: {self.skipped_meshes[index]}")
        for path in self.excluded_paths[:max_listed]:
            lines.append(f"  skip mesh {path}: {MESH_EXCLUDED_BY_PATTERN} (not loaded)")
        if len(self.excluded_paths) > max_listed:
            lines.append(f"  ... and {len(self.excluded_paths) - max_listed} more meshes excluded by pattern")
        for reason, count in sorted(self.skipped_pair_counts().items(), key=lambda item: -item[1]):
            lines.append(f"  skip {count} pair{'s' if count != 1 else ''}: {reason}")
        lines.extend(f"  note: {note}" for note in self.notes)
        return lines

    def to_dict(self) -> dict:
        return {
            "pairs_checked": self.checked_pairs,
            "pairs_possible": self.possible_pairs,
            "checked": [{"prim_a": self.paths[i], "prim_b": self.paths[j], "kind": "self" if i == j else "inter",
                         "reason": reason} for (i, j), reason in zip(self.pairs.tolist(), self.pair_reasons)],
            "skipped_meshes": [{"prim": self.paths[i], "reason": reason}
                               for i, reason in sorted(self.skipped_meshes.items())]
                              + [{"prim": path, "reason": MESH_EXCLUDED_BY_PATTERN} for path in self.excluded_paths],
            "skipped_pairs": [{"prim_a": self.paths[i], "prim_b": self.paths[j],
                               "kind": "self" if i == j else "inter", "reason": reason}
                              for i, j, reason in self.skipped_pairs],
            "notes": list(self.notes),
        }


def mesh_moves(points: np.ndarray) -> bool:
    """True when any point differs between any two samples (float64[K, N, 3]); exact comparison."""
    points = np.asarray(points)
    if points.ndim != 3 or points.shape[0] < 2:
        return False
    return not samples_all_alike(points)


def pattern_mask(paths: Sequence[str], include: Sequence[str], exclude: Sequence[str]) -> np.ndarray:
    """bool[N]: kept by ``--prims`` (any include pattern, or no include pattern) and no exclude pattern."""
    def matches(patterns):
        if not patterns:
            return np.zeros(len(paths), bool)
        return np.array([any(path_matches(path, pattern) for pattern in patterns) for path in paths],
                        dtype=bool).reshape(len(paths))
    kept = matches(include) if include else np.ones(len(paths), bool)
    return kept & ~matches(exclude)


def path_matches(path: str, pattern: str) -> bool:
    """fnmatch on the whole prim path ('*' also crosses '/'); a pattern naming a prim also matches every
    prim below it and every instance of a PointInstancer it names (same rule as the loader's ``include``).
    In fnmatch '[' opens a character class: one instance is ``'/World/scatter[[]3]*'``."""
    pattern = pattern.rstrip("/") or "/"
    return (fnmatch.fnmatchcase(path, pattern) or path.startswith(pattern + "/")
            or path.startswith(pattern + "["))   # PointInstancer instances: <instancer>[<index>]/...


def include_predicate(include: Sequence[str], exclude: Sequence[str]):
    """A callable for ``load_shot(include=...)`` that also remembers which mesh paths it rejected."""
    rejected: List[str] = []

    def wanted(path: str) -> bool:
        keep = bool(pattern_mask([path], include, exclude)[0])
        if not keep:
            rejected.append(path)
        return keep

    wanted.rejected = rejected
    return wanted


def split_patterns(patterns: Sequence[str], excludes: Sequence[str] = ()) -> Tuple[Tuple[str, ...], Tuple[str, ...]]:
    """``--prims`` values starting with '!' are exclude patterns; ``--exclude`` values always are."""
    include = tuple(p for p in patterns if not p.startswith("!"))
    exclude = tuple(p[1:] for p in patterns if p.startswith("!")) + tuple(excludes)
    return include, exclude


def plan_pairs(paths: Sequence[str], kinds: Sequence[str], moving: np.ndarray, flags: SceneFlags,
               options: ScopeOptions = ScopeOptions()) -> Plan:
    """Decide every self and inter pair among the meshes. Pure: no USD, no core."""
    paths = list(paths)
    count = len(paths)
    moving = np.asarray(moving, bool).reshape(count)
    kinds = list(kinds)
    deforming = np.array([kind == "deforming" for kind in kinds], bool).reshape(count)
    rigid = np.array([kind == "rigid" for kind in kinds], bool).reshape(count)

    mesh_reason: Dict[int, str] = {}
    mesh_rules = [
        (~pattern_mask(paths, options.include, options.exclude), MESH_EXCLUDED_BY_PATTERN),
        (~flags.collision_enabled, MESH_COLLISION_DISABLED),
        (flags.guide & (not options.include_guides), MESH_GUIDE),
        (flags.invisible & (not options.include_invisible), MESH_INVISIBLE),
        (np.zeros(count, bool) if flags.absent is None else flags.absent, MESH_ABSENT),
    ]
    for mask, reason in mesh_rules:
        for index in np.flatnonzero(mask).tolist():
            mesh_reason.setdefault(index, reason)
    active = np.ones(count, bool)
    active[list(mesh_reason)] = False

    # reason code per (i, j) for i <= j: 0 = checked, k > 0 = the k-th skip reason.
    pair_mesh_skipped = ~(active[:, None] & active[None, :])
    eye = np.eye(count, dtype=bool)
    self_rules = [
        (np.full(count, not options.self_check), PAIR_SELF_DISABLED_BY_OPTION),
        (~moving, PAIR_SELF_STATIC),
        (rigid | ~deforming, PAIR_SELF_RIGID),
        (~flags.self_collision, PAIR_SELF_DISABLED_BY_ATTRIBUTE),
    ]
    both_still = ~moving[:, None] & ~moving[None, :]
    deforms = deforming & moving
    neither_deforms = ~deforms[:, None] & ~deforms[None, :] & (not options.rigid)
    inter_rules = [
        (np.full((count, count), not options.inter_check), PAIR_INTER_DISABLED_BY_OPTION),
        (flags.filtered | flags.filtered.T, PAIR_FILTERED),
        (flags.group_filtered | flags.group_filtered.T, PAIR_COLLISION_GROUP),
        (both_still, PAIR_STATIC_STATIC),
        (neither_deforms, PAIR_RIGID_ONLY),
    ]
    reasons = [PAIR_MESH_SKIPPED] + [r for _, r in self_rules] + [r for _, r in inter_rules]
    code = np.zeros((count, count), np.int16)

    def assign(mask, reason):
        code[(code == 0) & mask] = reasons.index(reason) + 1

    assign(pair_mesh_skipped, PAIR_MESH_SKIPPED)
    for mask, reason in self_rules:
        assign(eye & mask[:, None], reason)
    off_diagonal = ~eye
    for mask, reason in inter_rules:
        assign(off_diagonal & mask, reason)

    upper_i, upper_j = np.triu_indices(count)
    upper_code = code[upper_i, upper_j]
    checked = upper_code == 0
    pairs = np.stack([upper_i[checked], upper_j[checked]], axis=1).astype(np.int32).reshape(-1, 2)
    pair_reasons = [PAIR_CHECK_SELF if i == j else PAIR_CHECK_INTER for i, j in pairs.tolist()]
    skipped = [(i, j, reasons[c - 1]) for i, j, c in
               zip(upper_i[~checked].tolist(), upper_j[~checked].tolist(), upper_code[~checked].tolist())]
    return Plan(paths=paths, kinds=kinds, moving=moving, pairs=pairs, pair_reasons=pair_reasons,
                skipped_meshes=mesh_reason, skipped_pairs=skipped)


# ---------------------------------------------------------------------------------------------------------
# Reading the scene


def _under(paths, root) -> np.ndarray:
    """Indices of the meshes at or below ``root`` (an Sdf.Path)."""
    from pxr import Sdf

    return np.array([i for i, path in enumerate(paths) if Sdf.Path(path).HasPrefix(root)], dtype=np.int64)


def _visibility_times(prim, t0: float, t1: float) -> List[float]:
    """Times at which the computed visibility can change within [t0, t1]: visibility is a token and held,
    so its value anywhere in the range equals its value at t0 or at one of its samples inside the range."""
    from pxr import Gf, UsdGeom

    times = {t0}
    probe = prim
    while probe and not probe.IsPseudoRoot():
        imageable = UsdGeom.Imageable(probe)
        if imageable:
            attribute = imageable.GetVisibilityAttr()
            if attribute and attribute.ValueMightBeTimeVarying():
                times.update(attribute.GetTimeSamplesInInterval(Gf.Interval(t0, t1)))
        probe = probe.GetParent()
    return sorted(times)


def _self_collision(prim) -> bool:
    probe = prim
    while probe and not probe.IsPseudoRoot():
        attribute = probe.GetAttribute("usdksl:selfCollision")
        if attribute and attribute.HasAuthoredValue():
            return bool(attribute.Get())
        probe = probe.GetParent()
    return True


#: The physics schemas the scope reads, found by their registered type names: a stage that uses neither
#: never imports UsdPhysics (which loads UsdShade and Sdr with it: a tenth of a second of start-up).
COLLISION_GROUP_TYPE_NAME = "UsdPhysicsCollisionGroup"
FILTERED_PAIRS_API_TYPE_NAME = "UsdPhysicsFilteredPairsAPI"


def _physics_schema_type(type_name: str):
    """The Tf.Type of a UsdPhysics schema (declared by its plugin, no library loaded); when this USD build
    has no UsdPhysics plugin, importing the module raises what it always raised."""
    from pxr import Tf

    schema_type = Tf.Type.FindByName(type_name)
    if schema_type.isUnknown:
        from pxr import UsdPhysics  # noqa: F401
    return schema_type


def _has_collision_groups(stage) -> bool:
    """Whether any prim of the stage, inactive, abstract and instance proxies included, is a collision group
    (a superset of where UsdPhysics.CollisionGroup.ComputeCollisionGroupTable can find one)."""
    from pxr import Usd

    group_type = _physics_schema_type(COLLISION_GROUP_TYPE_NAME)
    every_prim = Usd.TraverseInstanceProxies(Usd.PrimAllPrimsPredicate)
    return any(prim.IsA(group_type) for prim in Usd.PrimRange.Stage(stage, every_prim))


def _group_filtered(stage, paths) -> np.ndarray:
    count = len(paths)
    if not _has_collision_groups(stage):
        return np.zeros((count, count), bool)
    from pxr import UsdPhysics

    table = UsdPhysics.CollisionGroup.ComputeCollisionGroupTable(stage)
    groups = [str(path) for path in table.GetGroups()]
    if not groups or count == 0:
        return np.zeros((count, count), bool)
    merge_name_to_index = {}
    for index, group_path in enumerate(groups):
        group = UsdPhysics.CollisionGroup(stage.GetPrimAtPath(group_path))
        name = group.GetMergeGroupNameAttr().Get() if group else None
        if name:
            merge_name_to_index.setdefault(name, index)
    membership = np.zeros((count, len(groups)), bool)
    for prim in stage.Traverse():
        if not prim.IsA(UsdPhysics.CollisionGroup):
            continue
        group = UsdPhysics.CollisionGroup(prim)
        path = str(prim.GetPath())
        if path in groups:
            index = groups.index(path)
        else:
            index = merge_name_to_index.get(group.GetMergeGroupNameAttr().Get() or None)
            if index is None:
                continue
        query = group.GetCollidersCollectionAPI().ComputeMembershipQuery()
        membership[:, index] |= np.array([query.IsPathIncluded(path) for path in paths], bool)
    enabled = np.array([[table.IsCollisionEnabled(a, b) for b in range(len(groups))]
                        for a in range(len(groups))], bool)
    enabled_combinations = membership.astype(np.int64) @ enabled.astype(np.int64) @ membership.T.astype(np.int64)
    in_group = membership.any(axis=1)
    return in_group[:, None] & in_group[None, :] & (enabled_combinations == 0)


def read_scene_flags(stage, paths: Sequence[str], time_range: Optional[Tuple[float, float]]) -> SceneFlags:
    """Ask the stage what it says about each mesh over the checked time range (inclusive)."""
    from pxr import Sdf, Usd, UsdGeom

    filtered_pairs_api = _physics_schema_type(FILTERED_PAIRS_API_TYPE_NAME)
    paths = list(paths)
    count = len(paths)
    flags = SceneFlags.permissive(count)
    for index, path in enumerate(paths):
        prim = stage.GetPrimAtPath(path)
        if not prim:
            continue
        attribute = prim.GetAttribute("physics:collisionEnabled")
        if attribute and attribute.HasAuthoredValue() and attribute.Get() is False:
            flags.collision_enabled[index] = False
        imageable = UsdGeom.Imageable(prim)
        flags.guide[index] = imageable.ComputePurpose() == UsdGeom.Tokens.guide
        if time_range is None:
            samples = [Usd.TimeCode.Default()]
        else:
            samples = [Usd.TimeCode(t) for t in _visibility_times(prim, float(time_range[0]), float(time_range[1]))]
        flags.invisible[index] = all(imageable.ComputeVisibility(t) == UsdGeom.Tokens.invisible for t in samples)
        flags.self_collision[index] = _self_collision(prim)

    for prim in stage.Traverse():
        if not prim.HasAPI(filtered_pairs_api):
            continue
        sources = _under(paths, prim.GetPath())
        if sources.size == 0:
            continue
        from pxr import UsdPhysics

        for target in UsdPhysics.FilteredPairsAPI(prim).GetFilteredPairsRel().GetTargets():
            targets = _under(paths, Sdf.Path(target))
            if targets.size:
                flags.filtered[np.ix_(sources, targets)] = True
    flags.filtered |= flags.filtered.T
    np.fill_diagonal(flags.filtered, False)
    flags.group_filtered = _group_filtered(stage, paths)
    np.fill_diagonal(flags.group_filtered, False)
    return flags


def plan_shot(shot, options: ScopeOptions = ScopeOptions(), time_range=None) -> Plan:
    """Scope a loaded shot (usdksl.reading.loader.Shot): flags from its stage, motion from its sample arrays."""
    paths = [mesh.path for mesh in shot.meshes]
    kinds = [mesh.kind for mesh in shot.meshes]
    moving = np.array([mesh.kind != "static" and mesh_moves(mesh.points) for mesh in shot.meshes], bool)
    if time_range is None and len(shot.times):
        time_range = (float(shot.times[0]), float(shot.times[-1]))
    flags = read_scene_flags(shot.stage, [getattr(mesh, "scene_path", mesh.path) for mesh in shot.meshes],
                             time_range)
    if shot.absent:
        flags.absent = np.array([path in shot.absent for path in paths], bool)
    plan = plan_pairs(paths, kinds, moving, flags, options)
    for index, mesh in enumerate(shot.meshes):
        if mesh.kind != "static" and not moving[index]:
            plan.notes.append(f"{mesh.path}: {len(mesh.times)} samples that are all equal: treated as static")
        elif mesh.kind == "static" and _single_points_sample(shot.stage, getattr(mesh, "prim_path", mesh.path)):
            plan.notes.append(f"{mesh.path}: a single time sample: treated as static")
    return plan


def _single_points_sample(stage, path: str) -> bool:
    from pxr import UsdGeom

    mesh = UsdGeom.Mesh(stage.GetPrimAtPath(path))
    return bool(mesh) and mesh.GetPointsAttr().GetNumTimeSamples() == 1


#: Pair-level skip reasons that follow from how the meshes move over one segment only.
MOTION_SKIP_REASONS = (PAIR_STATIC_STATIC, PAIR_SELF_STATIC, PAIR_SELF_RIGID, PAIR_RIGID_ONLY)
PAIR_KEPT_ACROSS_SEGMENTS = "checked in another segment: kept where its meshes rest"


def keep_pairs_across_segments(plans: Sequence[Plan]) -> None:
    """In a shot cut into segments, check a pair in every segment where both its meshes are there once any segment
    checks it, even where neither moves: the segment does not know the motion around it, and a contact that goes on
    while the meshes rest must keep its last contact (and be confirmed there). Edits ``plans`` in place."""
    if len(plans) < 2:
        return
    union = {pair for plan in plans for pair in map(tuple, plan.pairs.tolist())}
    for plan in plans:
        kept = [(i, j) for i, j, reason in plan.skipped_pairs if (i, j) in union and reason in MOTION_SKIP_REASONS]
        if not kept:
            continue
        reasons = dict(zip(map(tuple, plan.pairs.tolist()), plan.pair_reasons))
        reasons.update({pair: PAIR_KEPT_ACROSS_SEGMENTS for pair in kept})
        ordered = sorted(reasons)
        plan.pairs = np.array(ordered, dtype=np.int32).reshape(-1, 2)
        plan.pair_reasons = [reasons[pair] for pair in ordered]
        kept_set = set(kept)
        plan.skipped_pairs = [(i, j, reason) for i, j, reason in plan.skipped_pairs if (i, j) not in kept_set]


def merge_plans(plans: Sequence[Plan]) -> Plan:
    """One plan for a shot checked in several time segments (same meshes, same order): a pair is checked
    when any segment checks it (with that segment's reason); a pair or mesh is reported skipped with the
    first segment's reason only when no segment checks it."""
    if len(plans) == 1:
        return plans[0]
    first = plans[0]
    reasons: Dict[Tuple[int, int], str] = {}
    for plan in plans:
        if plan.paths != first.paths:
            raise ValueError("segments of one shot loaded different meshes")
        for pair, reason in zip(map(tuple, plan.pairs.tolist()), plan.pair_reasons):
            reasons.setdefault(pair, reason)
    ordered = sorted(reasons)
    pairs = np.array(ordered, dtype=np.int32).reshape(-1, 2)
    checked_meshes = set(pairs.reshape(-1).tolist())
    notes: List[str] = []
    for plan in plans:
        notes.extend(note for note in plan.notes if note not in notes)
    return Plan(paths=list(first.paths), kinds=list(first.kinds),
                moving=np.logical_or.reduce([plan.moving for plan in plans]), pairs=pairs,
                pair_reasons=[reasons[pair] for pair in ordered],
                skipped_meshes={i: r for i, r in first.skipped_meshes.items()
                                if i not in checked_meshes and all(i in p.skipped_meshes for p in plans)},
                skipped_pairs=[(i, j, r) for i, j, r in first.skipped_pairs if (i, j) not in reasons],
                notes=notes, excluded_paths=list(first.excluded_paths))

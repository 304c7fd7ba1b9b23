"""Memory a check needs, known before it starts, against the memory the machine has: refuse rather than swap.

:func:`sources_size` counts what a check will hold without loading any motion: per mesh its vertices, its
triangles and its time samples in the checked range (one sample of points and the face counts are read),
from the mesh sources the loader found on the check's one open stage
(:func:`usdksl.reading.loader.find_mesh_sources`), which it then loads. :func:`scan_shot` opens a file and
counts the same on its own, reading past whatever the loader would refuse.
:func:`estimated_bytes` turns the counts into bytes with a model calibrated against measured peak RSS
(``python benchmarks/memory_model.py`` measures and fits it again):

- per vertex-sample of the whole checked range: the loader's float64 points, which the regions, the
  cross-check and the report's pictures read at any time of the shot;
- per vertex-sample of one memory window (usdksl.checking.memory_windows): the core's merged flightplans
  and what it derives from the points (it reads the loader's points in place), which it holds for the
  window it checks; a long shot is handed to the
  core a window at a time, so this part is set by the window, not by the shot's length;
- per triangle and thread (not per sample: the trees and lists exist once per time window, and each
  thread checks one window at a time): the step-box trees, separation-list entries and clearance certificates of KSL,
  the swept-volume trees of the other methods;
- a fixed part: modules imported during the check, the stage, the reports.

:func:`plan_memory` picks the window: as many sample steps as hold WINDOW_BYTES of the core's points and
flightplans, or as much as its trees and lists take when that is more (so the window adds at most what the
triangles cost already), or a shorter one (never under MIN_STEPS_PER_WINDOW) when that would not fit in
what is available; it refuses only when even the shortest window does not fit.

Contacts cost on top (reports, override layer; about a kilobyte per contacting triangle pair), which
no scan can know: shots in heavy self contact can need more than the estimate.

:func:`available_bytes` is MemAvailable of /proc/meminfo, or the cgroup's limit minus its usage when
that is lower (a container, a farm slot). ``--memory-limit`` or the environment variable
:data:`MEMORY_LIMIT_VARIABLE` override it (``off`` skips the check). :func:`check_memory` raises a
one-line UsdkslUsageError (exit 2) saying what is needed, what there is and what to do.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, field
from typing import Callable, Iterable, List, Optional, Tuple, Union

import numpy as np

from ..checking.memory_windows import MIN_STEPS_PER_WINDOW
from ..errors import UsdkslUsageError

#: Environment variable with the memory a check may use (same values as ``--memory-limit``).
MEMORY_LIMIT_VARIABLE = "USDKSL_MEMORY_LIMIT"
#: ``--memory-limit`` / MEMORY_LIMIT_VARIABLE value that turns the check off.
NO_LIMIT = "off"

#: The model, per method: bytes per vertex-sample, and per triangle and thread (each thread checks a
#: time window with trees and lists of its own), fitted on tablecloth shots (2k to 4k faces, 11 to 51
#: samples, 1 and 2 threads; with the step-batched KSL core and UsdPhysics no longer imported during a
#: check of a stage without physics schemas, benchmarks/memory_model.py --quick fitted KSL at 198 B per
#: vertex sample and 2,274 B per triangle and thread, swept at 127 B and 294 B, and a fixed 1.5 to 5.5 MiB),
#: rounded up so that every measured shot lies between 1x and 2x. Discrete and brute hold what swept holds.
#: On a 100k-face tablecloth (benchmarks/scale.py) KSL rose by 2,440 B per triangle with the vertex
#: samples at 117 B: the front grows a little faster than the cloth, and 2,600 B stays above it.
#: The same script fits the fixed part at 5.0 MiB (KSL) and 3.7 MiB (swept); at 8 MiB a small shot's estimate
#: stood at 1.67x to 1.98x of its peak and one noisy measurement of a 2k-face shot crossed 2x, at 6 MiB every
#: shot lies between 1.08x and 1.89x. Since the core reads the loader's points in place (no copy of its own, and
#: flightplans that keep every sample read them too), the same script fits KSL at 100 B per vertex sample
#: (and 1,846 B per triangle and thread); 160 B keeps the shots of every sample count between 1.04x and 1.75x.
BYTES_PER_VERTEX_SAMPLE = {"ksl": 160, "swept": 120, "discrete": 120, "brute": 120}
#: Of BYTES_PER_VERTEX_SAMPLE, what the loader holds for the whole checked range (float64 points, 24 B,
#: plus their share of its per-mesh arrays); the rest is the core's, held for one memory window.
LOADED_BYTES_PER_VERTEX_SAMPLE = 32
#: Memory of the core's part of one memory window by the model (BYTES_PER_VERTEX_SAMPLE less what the loader
#: holds), unless its trees and lists take more (then as much as they do) or memory asks for less: each window
#: is checked afresh (its front is built again and the contacts still going on where it begins are found and
#: confirmed again), so a window as long as memory allows costs least. The model covers curved motion (a
#: flightplan breakpoint at every sample); on the 150k-triangle production shot (benchmarks/production_shot.py)
#: raising it from 1 to 2 GiB doubled its windows to 223 samples and raised the measured peak by 280 MiB (33 B
#: per vertex-sample of the longer window), the 480-frame peak staying at 1.12x the 240-frame one; the
#: 10x-resampled tablecloth is then checked in one window instead of two.
WINDOW_BYTES = 2 * 2 ** 30
BYTES_PER_TRIANGLE = {"ksl": 2600, "swept": 450, "discrete": 450, "brute": 450}
FIXED_BYTES = 6 * 2 ** 20

_SIZE = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*([kmgt]?)i?b?\s*$", re.IGNORECASE)
_UNITS = {"": 1, "k": 2 ** 10, "m": 2 ** 20, "g": 2 ** 30, "t": 2 ** 40}

TimeRange = Tuple[float, float]


@dataclass
class ShotSize:
    """What a check holds, counted before loading: meshes, vertices x samples, triangles; the checked
    span in time codes (None when the shot has no samples)."""

    meshes: int = 0
    vertex_samples: int = 0
    triangles: int = 0
    #: Vertices of the meshes with more than one sample in the range (the ones a memory window cuts), and
    #: the most samples one of them has there.
    animated_vertices: int = 0
    animated_vertex_samples: int = 0
    most_samples: int = 0
    span: Optional[TimeRange] = None
    #: Time codes at which every animated mesh has a sample (None: no animated mesh): where a shot can be cut
    #: into parts that usdksl merge joins exactly.
    shared_samples: Optional[np.ndarray] = field(default=None, compare=False)


def parse_memory_size(text: Union[str, int, None]) -> Optional[int]:
    """Bytes from ``"8G"``, ``"512M"``, ``"1073741824"``, ``"1.5GiB"``; None for ``off``. Raises
    UsdkslUsageError on anything else."""
    if text is None or isinstance(text, int):
        return text
    if text.strip().lower() == NO_LIMIT:
        return None
    match = _SIZE.match(text)
    if not match or float(match.group(1)) <= 0:
        raise UsdkslUsageError(f"memory limit must be a size like 8G, 512M or 1073741824 bytes, or "
                               f"'{NO_LIMIT}'; got {text!r}")
    return int(float(match.group(1)) * _UNITS[match.group(2).lower()])


def format_bytes(count: float) -> str:
    for unit, scale in (("TiB", 2 ** 40), ("GiB", 2 ** 30), ("MiB", 2 ** 20)):
        if count >= scale:
            return f"{count / scale:.1f} {unit}"
    return f"{count / 2 ** 10:.0f} KiB"


# --------------------------------------------------------------------------- what there is

def _read_int(path: str) -> Optional[int]:
    try:
        with open(path) as handle:
            text = handle.read().strip()
    except OSError:
        return None
    return int(text) if text.isdigit() else None   # cgroup v2 says "max" for no limit


def _meminfo_available(path: str = "/proc/meminfo") -> Optional[int]:
    try:
        with open(path) as handle:
            for line in handle:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


def _cgroup_room(root: str = "/sys/fs/cgroup") -> Optional[int]:
    """The cgroup's limit minus its usage (v2, then v1); None without a limit."""
    for limit_file, usage_file in (("memory.max", "memory.current"),
                                   ("memory/memory.limit_in_bytes", "memory/memory.usage_in_bytes")):
        limit = _read_int(os.path.join(root, limit_file))
        usage = _read_int(os.path.join(root, usage_file))
        if limit is not None and usage is not None and limit < 2 ** 60:   # v1 writes a huge number for none
            return max(limit - usage, 0)
    return None


def available_bytes() -> Optional[int]:
    """Memory this process can still take: MemAvailable, or the cgroup's room when lower; None when
    neither can be read (the check is then skipped)."""
    found = [value for value in (_meminfo_available(), _cgroup_room()) if value is not None]
    return min(found) if found else None


def memory_limit(option: Union[str, int, None] = None,
                 environ=None, detect: Callable[[], Optional[int]] = available_bytes) -> Optional[int]:
    """The bytes a check may use: ``option`` (``--memory-limit``), else MEMORY_LIMIT_VARIABLE, else what
    the machine has; None when the check is off or nothing can be read."""
    environ = os.environ if environ is None else environ
    if option is not None:
        return parse_memory_size(option)
    if environ.get(MEMORY_LIMIT_VARIABLE):
        return parse_memory_size(environ[MEMORY_LIMIT_VARIABLE])
    return detect()


# --------------------------------------------------------------------------- what is needed

def sources_size(found, time_range: Optional[TimeRange] = None) -> ShotSize:
    """Count the meshes of ``found`` (usdksl.reading.loader.MeshSources) that ``load_sources(found,
    time_range)`` will load: each authored UsdGeom.Mesh prim (a skinned one at the samples it is posed at)
    with the sample times found with it (the instances of a PointInstancer's prototypes are not counted, as
    :func:`scan_shot` does not count them). Reads one sample of points and the face counts of each; whatever
    cannot be read is left out of the count (the loader then reports it)."""
    return _count_meshes(zip(found.prims, found.sample_times), time_range)


def scan_shot(path: str, time_range: Optional[TimeRange] = None, include=None,
              skin_keys_only: bool = False) -> ShotSize:
    """Count the meshes ``load_shot(path, time_range, include, skin_keys_only=skin_keys_only)`` would load,
    as :func:`sources_size` does, with a stage of its own: a skinned mesh counts the samples it is posed at,
    the frames between sparse keys included unless ``skin_keys_only`` (usdksl.reading.skinning). Raises
    UsdkslInputError only when the file cannot be opened."""
    from ..reading.loader import _skinned_meshes, mesh_prims, mesh_sample_times, open_stage

    stage = open_stage(path)
    try:
        prims = mesh_prims(stage, include)
    except Exception:   # noqa: BLE001  (an estimate: the loader reports what is wrong)
        return ShotSize()
    try:
        skinned = _skinned_meshes(stage, skin_keys_only)
    except Exception:   # noqa: BLE001  (counted by their authored samples; the loader reports what is wrong)
        skinned = {}

    def sample_times(prim) -> Callable[[], np.ndarray]:
        posed = skinned.get(str(prim.GetPath()))
        return posed.sample_times if posed is not None else lambda: mesh_sample_times(prim)

    return _count_meshes(((prim, sample_times(prim)) for prim in prims), time_range)


def _count_meshes(meshes: Iterable, time_range: Optional[TimeRange]) -> ShotSize:
    """ShotSize of (UsdGeom.Mesh prim, its sample times: float64[K] or a callable giving them) pairs."""
    from pxr import UsdGeom

    size = ShotSize()
    starts, ends = [], []
    for prim, times in meshes:
        try:
            mesh = UsdGeom.Mesh(prim)
            times = times() if callable(times) else times
            first = float(times[0]) if times.size else (time_range[0] if time_range else 0.0)
            points = mesh.GetPointsAttr().Get(first)
            # a value USD could not parse as its type comes back as an opaque object: counted as nothing
            point_count = len(points) if points is not None else 0
            counts = np.asarray(mesh.GetFaceVertexCountsAttr().Get(first) or [], dtype=np.int64)
        except Exception:   # noqa: BLE001  (left out of the count; the loader reports it)
            continue
        samples = _samples_in(times, time_range)
        if times.size > 1:
            size.shared_samples = (times if size.shared_samples is None
                                   else np.intersect1d(size.shared_samples, times, assume_unique=True))
        if samples:
            starts.append(max(float(times[0]), time_range[0]) if time_range else float(times[0]))
            ends.append(min(float(times[-1]), time_range[1]) if time_range else float(times[-1]))
        size.meshes += 1
        size.vertex_samples += max(samples, 1) * point_count
        if samples > 1:
            size.animated_vertices += point_count
            size.animated_vertex_samples += samples * point_count
            size.most_samples = max(size.most_samples, samples)
        size.triangles += int(np.clip(counts - 2, 0, None).sum())
    if time_range is not None:
        size.span = time_range
    elif starts:
        size.span = (min(starts), max(ends))
    return size


def _samples_in(times: np.ndarray, time_range: Optional[TimeRange]) -> int:
    """Samples the loader keeps: those strictly inside the range plus both ends (usdksl.reading.loader)."""
    if time_range is None or times.size == 0:
        return int(times.size)
    inside = int(np.count_nonzero((times > time_range[0]) & (times < time_range[1])))
    return inside + (1 if time_range[0] == time_range[1] else 2)


def window_vertex_samples(size: ShotSize, steps_per_window: Optional[int]) -> int:
    """Vertex-samples the core holds at once when handed ``size`` in memory windows of ``steps_per_window``
    sample steps (None: the whole range at once): the still meshes' one sample each, and at most
    ``steps_per_window + 1`` samples of each animated mesh."""
    if steps_per_window is None:
        return size.vertex_samples
    window = min(size.animated_vertex_samples, size.animated_vertices * (int(steps_per_window) + 1))
    return size.vertex_samples - size.animated_vertex_samples + window


def _vertex_sample_bytes(method: str) -> Tuple[int, int]:
    """(loaded, core): bytes per vertex-sample that the loader holds for the whole range and that the core
    holds for one memory window (the model above)."""
    total = BYTES_PER_VERTEX_SAMPLE.get(method, max(BYTES_PER_VERTEX_SAMPLE.values()))
    loaded = min(LOADED_BYTES_PER_VERTEX_SAMPLE, total)
    return loaded, total - loaded


def _tree_bytes(size: ShotSize, method: str, threads: int) -> int:
    """Bytes of the core's trees and lists (per triangle and thread)."""
    return BYTES_PER_TRIANGLE.get(method, max(BYTES_PER_TRIANGLE.values())) * size.triangles * max(int(threads), 1)


def estimated_bytes(size: ShotSize, method: str = "ksl", threads: int = 1,
                    steps_per_window: Optional[int] = None) -> int:
    """Peak memory the check of ``size`` on ``threads`` threads adds to the process (the model above),
    handed to the core in memory windows of ``steps_per_window`` sample steps (None: whole): each thread
    checks one time window at a time with trees and lists of its own."""
    loaded, core = _vertex_sample_bytes(method)
    return int(FIXED_BYTES + loaded * size.vertex_samples + core * window_vertex_samples(size, steps_per_window)
               + _tree_bytes(size, method, threads))


def default_steps_per_window(size: ShotSize, method: str = "ksl", threads: int = 1) -> Optional[int]:
    """Sample steps of a memory window when memory does not ask for fewer (module docstring); None when the
    shot has no animated vertex to cut."""
    core = _vertex_sample_bytes(method)[1]
    if not size.animated_vertices or core <= 0:
        return None
    window_bytes = max(WINDOW_BYTES, _tree_bytes(size, method, threads))
    return max(MIN_STEPS_PER_WINDOW, int(window_bytes // (core * size.animated_vertices)) - 1)


def part_bounds(span: TimeRange, parts: int, shared_samples: Optional[np.ndarray]) -> List[float]:
    """``parts`` + 1 increasing bounds (time codes) splitting ``span`` into about equal parts, each inner bound
    moved to the nearest time at which every animated mesh has a sample (``shared_samples``) so that the parts'
    outputs merge exactly (docs/contracts.md, Windows and merging)."""
    start, end = float(span[0]), float(span[1])
    bounds = [start + (end - start) * i / parts for i in range(parts + 1)]
    if shared_samples is not None:
        inner = shared_samples[(shared_samples > start) & (shared_samples < end)]
        if inner.size:
            bounds[1:-1] = [float(inner[np.argmin(np.abs(inner - bound))]) for bound in bounds[1:-1]]
    return sorted(set(bounds))


@dataclass
class MemoryPlan:
    """How a check fits: the sample steps of its memory windows (None: the range whole), the estimate
    with them, and whether memory made them shorter than the default."""

    steps_per_window: Optional[int]
    estimate: int
    shortened: bool = False


def plan_memory(size: ShotSize, method: str, limit: Optional[int], file: Optional[str] = None,
                threads: int = 1, steps_per_window: Optional[int] = None) -> MemoryPlan:
    """The memory windows of the check of ``size`` on ``threads`` threads within ``limit`` bytes (None: no
    limit): ``steps_per_window`` when given (--window), else the default, shortened to what fits when the
    default does not. Raises UsdkslUsageError (exit 2) when even the shortest window does not fit (or the
    given one does not): the line says how much is needed and there is, and how to split the work."""
    steps = (default_steps_per_window(size, method, threads) if steps_per_window is None
             else max(int(steps_per_window), MIN_STEPS_PER_WINDOW))
    needed = estimated_bytes(size, method, threads, steps)
    if limit is None or needed <= limit:
        return MemoryPlan(steps, needed)
    if steps_per_window is None and size.animated_vertices:
        per_step = _vertex_sample_bytes(method)[1] * size.animated_vertices   # one more sample of each
        room = limit - estimated_bytes(size, method, threads, MIN_STEPS_PER_WINDOW)
        if room >= 0 and per_step > 0:
            fitting = min(steps, MIN_STEPS_PER_WINDOW + room // per_step)
            return MemoryPlan(int(fitting), estimated_bytes(size, method, threads, int(fitting)), shortened=True)
    refuse(size, method, limit, file, threads, steps if steps_per_window is not None else MIN_STEPS_PER_WINDOW)


def refuse(size: ShotSize, method: str, limit: int, file: Optional[str], threads: int, steps: int) -> None:
    """Raise the one-line UsdkslUsageError of a check that does not fit in ``limit`` bytes even in memory
    windows of ``steps`` sample steps: what is needed and there is, and how to split the work."""
    needed = estimated_bytes(size, method, threads, steps)
    what = (f"needs about {format_bytes(needed)} of memory to check ({size.meshes} meshes, "
            f"{size.vertex_samples:,} vertex samples, {size.triangles:,} triangles) but "
            f"{format_bytes(limit)} is available")
    loaded = _vertex_sample_bytes(method)[0]
    # what a part of the range needs besides the points the loader holds for it
    fixed = needed - loaded * size.vertex_samples
    chunks = math.ceil(loaded * size.vertex_samples / (limit - fixed) * 1.25) if fixed < limit else 0
    # parts shorter than a window each would not be worth a farm task: fewer meshes is the way then
    if not 0 < chunks <= max(size.most_samples // steps, 1) or size.span is None or size.span[1] <= size.span[0]:
        advice = "check fewer meshes at a time with --prims/--exclude"
    else:
        cuts = part_bounds(size.span, chunks, size.shared_samples)
        example = ", ".join(f"{a:g} {b:g}" for a, b in zip(cuts[:3], cuts[1:4]))
        advice = (f"check it in about {chunks} parts with --time-range A B ({example}"
                  f"{', ...' if chunks > 3 else ''}; farm chunks join with usdksl merge), or fewer meshes "
                  f"with --prims/--exclude")
    if threads > 1 and estimated_bytes(size, method, 1, steps) <= limit:
        advice = f"use --threads 1 (it fits on one thread), or {advice}"
    raise UsdkslUsageError(f"{what}; {advice} (--memory-limit or {MEMORY_LIMIT_VARIABLE} overrides "
                           f"the available figure)", file=file)

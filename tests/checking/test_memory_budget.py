"""The memory estimate against measured peak memory, what the machine has, and the refusal path."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from usdksl.pipeline.memory_budget import (
    MEMORY_LIMIT_VARIABLE, ShotSize, _cgroup_room, _meminfo_available,
    default_steps_per_window, estimated_bytes, memory_limit, parse_memory_size, part_bounds, plan_memory,
    scan_shot)
from usdksl.checking.memory_windows import MIN_STEPS_PER_WINDOW
from usdksl.pipeline.memory_budget import BYTES_PER_TRIANGLE, BYTES_PER_VERTEX_SAMPLE, LOADED_BYTES_PER_VERTEX_SAMPLE, WINDOW_BYTES
from usdksl.cli.main import main
from usdksl.errors import UsdkslUsageError
from usdksl.reading.loader import load_shot

REPO_ROOT = Path(__file__).resolve().parents[2]
#: How far the estimate may be from the measured peak (the factor docs/contracts.md, Memory, promises).
WITHIN = 2.0

# The peak is the process's own high-water mark (VmHWM). ru_maxrss would do in a shell, but Linux carries
# it over exec from the process that spawned the child: under pytest that is pytest's own peak.
MEASURE = """
import json, resource, sys
from usdksl import _native
from usdksl.pipeline import CheckOptions, check_shot
from usdksl.pipeline.memory_budget import plan_memory, scan_shot
def status(field):
    with open("/proc/self/status") as lines:
        return next(int(line.split()[1]) * 1024 for line in lines if line.startswith(field))
path, method, threads = sys.argv[1], sys.argv[2], int(sys.argv[3])
size = scan_shot(path)
estimate = plan_memory(size, method, None, threads=threads).estimate
del size
before = status("VmRSS:")
check_shot(path, CheckOptions(method=method, memory_limit="off", threads=threads))
print(json.dumps({"estimate": estimate, "rise": status("VmHWM:") - before,
                  "ru_maxrss_rise": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 - before}))
"""


def tablecloth(folder, faces, samples_per_keyframe):
    path = folder / f"tablecloth_{faces}_{samples_per_keyframe}.usdc"
    subprocess.run([sys.executable, str(REPO_ROOT / "samples" / "generate.py"), "tablecloth", "--faces",
                    str(faces), "--keyframes", "11", "--samples-per-keyframe", str(samples_per_keyframe),
                    "--out", str(path)], check=True, capture_output=True)
    return path


@pytest.fixture(scope="module")
def shots(tmp_path_factory):
    folder = tmp_path_factory.mktemp("memory")
    return {"small": tablecloth(folder, 2000, 1), "large": tablecloth(folder, 4000, 5)}


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads RSS from /proc")
@pytest.mark.parametrize("name, method, threads", [("small", "ksl", 1), ("large", "ksl", 2), ("large", "ksl", 1),
                                                   ("small", "swept", 2)])
def test_the_estimate_is_within_2x_of_the_measured_peak(shots, name, method, threads):
    # -P: not the working folder first on sys.path (from a checkout, the source tree without _native)
    output = subprocess.run([sys.executable, "-P", "-c", MEASURE, str(shots[name]), method, str(threads)],
                            check=True, capture_output=True, text=True).stdout
    measured = json.loads(output.strip().splitlines()[-1])
    ratio = measured["estimate"] / measured["rise"]
    assert 1 / WITHIN <= ratio <= WITHIN, measured


def test_the_scan_counts_what_the_loader_loads(shots):
    for time_range in (None, (3.0, 17.5)):
        size = scan_shot(str(shots["large"]), time_range)
        shot = load_shot(str(shots["large"]), time_range=time_range)
        assert size.meshes == len(shot.meshes)
        assert size.triangles == sum(mesh.triangle_count for mesh in shot.meshes)
        # static meshes count one sample, as the loader keeps them
        assert size.vertex_samples == sum(mesh.sample_count * mesh.vertex_count for mesh in shot.meshes)
        assert size.span == (time_range or (float(shot.times[0]), float(shot.times[-1])))


def test_the_estimate_grows_with_samples_and_triangles():
    small = estimated_bytes(ShotSize(meshes=1, vertex_samples=1000, triangles=2000))
    assert estimated_bytes(ShotSize(meshes=1, vertex_samples=2000, triangles=2000)) > small
    assert estimated_bytes(ShotSize(meshes=1, vertex_samples=1000, triangles=4000)) > small


def _smallest_window_need(shot, threads=1):
    return estimated_bytes(scan_shot(str(shot)), "ksl", threads, MIN_STEPS_PER_WINDOW)


def test_refusal_is_one_line_with_need_room_and_advice(shots, tmp_path):
    out = tmp_path / "out"
    # one thread, below what even the shortest memory window needs
    limit = _smallest_window_need(shots["large"]) - 2 ** 20
    result = CliRunner().invoke(main, ["check", str(shots["large"]), "--out", str(out), "--threads", "1",
                                       "--memory-limit", str(limit)])
    assert result.exit_code == 2, result.output
    lines = result.stderr.splitlines()
    assert len(lines) == 1, lines
    line = lines[0]
    assert line.startswith(f"usdksl: error: {shots['large']}: needs about ")
    assert "MiB of memory" in line and f"but {limit / 2 ** 20:.1f} MiB is available" in line
    assert "--time-range" in line and "usdksl merge" in line and "--prims/--exclude" in line
    assert not out.exists()


def test_a_shot_that_does_not_fit_whole_is_checked_in_shorter_windows_with_the_same_files(shots, tmp_path):
    size = scan_shot(str(shots["large"]))
    default_steps = default_steps_per_window(size, "ksl", 1)
    default = estimated_bytes(size, "ksl", 1, default_steps)
    shortest = estimated_bytes(size, "ksl", 1, MIN_STEPS_PER_WINDOW)
    assert shortest < default, "the shot is long enough for windows to matter"
    limit = (shortest + default) // 2
    plan = plan_memory(size, "ksl", limit, threads=1)
    assert plan.shortened and MIN_STEPS_PER_WINDOW <= plan.steps_per_window < min(default_steps, size.most_samples)
    assert plan.estimate <= limit
    fitted = CliRunner().invoke(main, ["check", str(shots["large"]), "--out", str(tmp_path / "fitted"), "--threads",
                                       "1", "--memory-limit", str(limit), "-v"])
    whole = CliRunner().invoke(main, ["check", str(shots["large"]), "--out", str(tmp_path / "whole"), "--threads",
                                      "1", "--memory-limit", "off", "--window", "100000"])
    assert fitted.exit_code == whole.exit_code == 1, (fitted.stderr, whole.stderr)
    assert f"windows of {plan.steps_per_window} sample steps" in fitted.stderr
    for name in ("tablecloth_4000_5.contacts.csv", "tablecloth_4000_5.regions.csv",
                 "tablecloth_4000_5.summary.csv"):
        assert (tmp_path / "fitted" / name).read_bytes() == (tmp_path / "whole" / name).read_bytes(), name


def test_the_default_window_holds_window_bytes_of_samples_or_what_the_triangles_take():
    # the small mesh's shot is longer than one window holds
    small = ShotSize(meshes=1, vertex_samples=10_000 * 3000, triangles=20_000, animated_vertices=10_000,
                     animated_vertex_samples=10_000 * 3000, most_samples=3000)
    large = ShotSize(meshes=1, vertex_samples=500_000 * 480, triangles=1_000_000, animated_vertices=500_000,
                     animated_vertex_samples=500_000 * 480, most_samples=480)
    for size, threads in ((small, 1), (large, 1), (large, 2)):
        steps = default_steps_per_window(size, "ksl", threads)
        window = (estimated_bytes(size, "ksl", threads, steps)
                  - estimated_bytes(ShotSize(triangles=size.triangles), "ksl", threads)
                  - LOADED_BYTES_PER_VERTEX_SAMPLE * size.vertex_samples)
        trees = BYTES_PER_TRIANGLE["ksl"] * size.triangles * threads
        assert window <= max(WINDOW_BYTES, trees) < estimated_bytes(size, "ksl", threads, steps + 2) - (
            estimated_bytes(size, "ksl", threads, steps) - window), (steps, window)
    assert default_steps_per_window(ShotSize(meshes=1, vertex_samples=100, triangles=10)) is None, "nothing moves"


def test_memory_windows_bound_what_the_core_holds_not_what_the_loader_holds():
    short = ShotSize(meshes=1, vertex_samples=10_000 * 100, triangles=20_000, animated_vertices=10_000,
                     animated_vertex_samples=10_000 * 100, most_samples=100, span=(1.0, 100.0))
    long = ShotSize(meshes=1, vertex_samples=10_000 * 1000, triangles=20_000, animated_vertices=10_000,
                    animated_vertex_samples=10_000 * 1000, most_samples=1000, span=(1.0, 1000.0))
    whole_growth = estimated_bytes(long) - estimated_bytes(short)
    window_growth = estimated_bytes(long, steps_per_window=32) - estimated_bytes(short, steps_per_window=32)
    extra_samples = long.vertex_samples - short.vertex_samples
    assert whole_growth == BYTES_PER_VERTEX_SAMPLE["ksl"] * extra_samples
    assert window_growth == LOADED_BYTES_PER_VERTEX_SAMPLE * extra_samples, "ten times the frames add only the loader's points"
    assert window_growth < whole_growth
    # a still mesh counts its one sample whatever the window
    still = ShotSize(meshes=2, vertex_samples=10_000 * 100 + 500, triangles=20_000, animated_vertices=10_000,
                     animated_vertex_samples=10_000 * 100, most_samples=100)
    assert estimated_bytes(still, steps_per_window=32) > estimated_bytes(short, steps_per_window=32)


def test_the_advice_is_fewer_meshes_when_time_chunks_cannot_help():
    size = ShotSize(meshes=3, vertex_samples=10_000, triangles=100_000, span=(1.0, 100.0))
    with pytest.raises(UsdkslUsageError) as refused:
        plan_memory(size, "ksl", estimated_bytes(ShotSize(triangles=50_000), "ksl"), file="shot.usd")
    assert "--prims/--exclude" in str(refused.value) and "--time-range" not in str(refused.value)


def test_the_suggested_chunks_each_fit(tmp_path):
    # a long shot: the loader's points of the whole range do not fit, one window of the core does
    size = ShotSize(meshes=1, vertex_samples=10_000_000, triangles=10_000, span=(1.0, 1000.0),
                    animated_vertices=10_000, animated_vertex_samples=10_000_000, most_samples=1000)
    limit = estimated_bytes(size, steps_per_window=MIN_STEPS_PER_WINDOW) // 3
    with pytest.raises(UsdkslUsageError) as refused:
        plan_memory(size, "ksl", limit)
    chunks = int(str(refused.value).split("in about ")[1].split(" parts")[0])
    samples = -(-size.most_samples // chunks)
    part = ShotSize(meshes=1, vertex_samples=10_000 * samples, triangles=size.triangles, animated_vertices=10_000,
                    animated_vertex_samples=10_000 * samples, most_samples=samples)
    assert estimated_bytes(part, steps_per_window=MIN_STEPS_PER_WINDOW) <= limit
    assert chunks <= 12, "no more chunks than needed, give or take a margin"


def test_environment_variable_and_off(shots, tmp_path, monkeypatch):
    monkeypatch.setenv(MEMORY_LIMIT_VARIABLE, "1M")   # below even the fixed part: refused
    refused = CliRunner().invoke(main, ["check", str(shots["small"]), "--out", str(tmp_path / "a")])
    assert refused.exit_code == 2 and "but 1.0 MiB is available" in refused.stderr
    allowed = CliRunner().invoke(main, ["check", str(shots["small"]), "--out", str(tmp_path / "b"),
                                        "--memory-limit", "off"])
    assert allowed.exit_code == 1, allowed.stderr
    monkeypatch.setenv(MEMORY_LIMIT_VARIABLE, "off")
    assert CliRunner().invoke(main, ["check", str(shots["small"]), "--out", str(tmp_path / "c")]).exit_code == 1


@pytest.mark.parametrize("text, expected", [("8G", 8 * 2 ** 30), ("512M", 512 * 2 ** 20), ("1.5GiB", 3 * 2 ** 29),
                                            ("1073741824", 2 ** 30), ("64k", 65536), ("off", None), ("OFF", None)])
def test_sizes_parse(text, expected):
    assert parse_memory_size(text) == expected


@pytest.mark.parametrize("text", ["", "lots", "-1G", "0", "8X", "nan"])
def test_bad_sizes_are_usage_errors(text):
    with pytest.raises(UsdkslUsageError):
        parse_memory_size(text)


def test_available_memory_is_the_lower_of_meminfo_and_the_cgroup(tmp_path):
    meminfo = tmp_path / "meminfo"
    meminfo.write_text("MemTotal:       16000000 kB\nMemFree:         1000000 kB\nMemAvailable:    8000000 kB\n")
    assert _meminfo_available(str(meminfo)) == 8_000_000 * 1024
    cgroup = tmp_path / "cgroup"
    cgroup.mkdir()
    assert _cgroup_room(str(cgroup)) is None
    (cgroup / "memory.max").write_text("max\n")
    (cgroup / "memory.current").write_text("1000\n")
    assert _cgroup_room(str(cgroup)) is None, "v2 'max' means no limit"
    (cgroup / "memory.max").write_text(f"{4 * 2 ** 30}\n")
    assert _cgroup_room(str(cgroup)) == 4 * 2 ** 30 - 1000
    assert memory_limit(None, environ={}, detect=lambda: 123) == 123
    assert memory_limit("2G", environ={MEMORY_LIMIT_VARIABLE: "1G"}) == 2 * 2 ** 30
    assert memory_limit(None, environ={MEMORY_LIMIT_VARIABLE: "1G"}) == 2 ** 30


def test_more_threads_need_more_and_the_advice_says_one_thread_fits():
    size = ShotSize(meshes=1, vertex_samples=100_000, triangles=20_000, span=(1.0, 101.0))
    one, two = estimated_bytes(size, "ksl", 1), estimated_bytes(size, "ksl", 2)
    assert two > one
    with pytest.raises(UsdkslUsageError) as refused:
        plan_memory(size, "ksl", (one + two) // 2, threads=2)
    assert "--threads 1" in str(refused.value)
    assert plan_memory(size, "ksl", (one + two) // 2, threads=1).estimate == one


def test_the_scan_leaves_out_a_mesh_it_cannot_read(tmp_path):
    """A points value of a type USD does not know (found by fuzzing) is the loader's to report."""
    text = (REPO_ROOT / "samples" / "drape.usda").read_text()
    path = tmp_path / "shot.usda"
    path.write_text(text.replace("point3f[] points = [(-0.5", "point9f[] points = [(-0.5"))
    whole = scan_shot(str(REPO_ROOT / "samples" / "drape.usda"))
    size = scan_shot(str(path))
    assert size.meshes == whole.meshes - 1 and 0 < size.vertex_samples < whole.vertex_samples


def test_the_suggested_parts_are_cut_at_shared_samples_and_merge(tmp_path):
    # a 60 fps cache: equal parts of 0..150 would be cut between samples (21.4286), which merge refuses
    size = ShotSize(meshes=1, vertex_samples=100_000 * 151, triangles=10_000, span=(0.0, 150.0),
                    shared_samples=np.arange(0.0, 151.0), animated_vertices=100_000,
                    animated_vertex_samples=100_000 * 151, most_samples=151)
    assert part_bounds(size.span, 7, size.shared_samples) == [0.0, 21.0, 43.0, 64.0, 86.0, 107.0, 129.0, 150.0]
    assert part_bounds(size.span, 7, None)[1] == pytest.approx(150.0 / 7)
    with pytest.raises(UsdkslUsageError) as refused:
        plan_memory(size, "ksl", estimated_bytes(size, steps_per_window=MIN_STEPS_PER_WINDOW) * 3 // 5)
    example = str(refused.value).split("--time-range A B (")[1].split(";")[0]
    assert all(float(value).is_integer() for pair in example.rstrip(", .").split(", ") for value in pair.split())


def test_the_advice_of_a_real_refusal_merges(shots, tmp_path):
    limit = _smallest_window_need(shots["large"]) - 2 ** 20
    result = CliRunner().invoke(main, ["check", str(shots["large"]), "--out", str(tmp_path / "x"), "--threads", "1",
                                       "--memory-limit", str(limit)])
    first, second = str(result.stderr).split("--time-range A B (")[1].split(";")[0].split(",")[:2]
    parts = [tuple(float(v) for v in first.split()), tuple(float(v) for v in second.split())]
    times = set(load_shot(shots["large"]).times.tolist())
    assert parts[0][1] == parts[1][0] and parts[0][1] in times

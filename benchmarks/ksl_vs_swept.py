"""KSL against its swept-volume baseline on one or more shots, in one run: times, ratios, counters.

    .venv/bin/python benchmarks/ksl_vs_swept.py SHOT[,SHOT...] swept,ksl [--threads 1,2] [--repeat 1]
    .venv/bin/python benchmarks/ksl_vs_swept.py SHOT[,SHOT...] ksl,ksl@baseline,swept --threads 1 \
        --baseline-python ../other-worktree/.venv/bin/python [--markdown benchmarks/results/PAGE.md]

SHOT is a USD file (loaded with usdksl.load_shot; every deforming mesh is checked against itself and
every pair with at least one deforming mesh is checked) or a generated per-frame shot:

    perframe:N:F   a cloth of 2*N*N triangles sampled at every one of F frames, waving on curves, sinking
                   onto a static slab and folding over itself (self and inter contacts; no Newton needed).

Each (shot, method, threads) run happens in a fresh subprocess (benchmarks/harness.py) so that its peak
memory (the RSS high-water mark during find_contacts, loaded shot included, reported in MB and in bytes
per triangle-sample) is its own; the time is measured around find_contacts alone: process time (CPU, all
threads added up) and wall time. With --repeat, the repeats go round all settings in turn (so that every
setting sees the same stretch of machine load) and the one of least process time counts.

A method written METHOD@baseline runs METHOD with the --baseline-python interpreter instead: another
build of usdksl (e.g. another worktree's .venv), measured in the same run as this one's, so that a
before/after ratio of the core is read from one machine period. The children print which usdksl they
imported.

Answers: every run of one build must give the same answer (the first contact time of every triangle
pair) bit for bit, or the script says so and exits 1. Across builds, the authored face pairs and their
first-contact times are compared against the baseline build's first run: a pair the baseline reports
that this build misses, or reports later than ANSWER_TIME_ALLOWANCE sample intervals after the
baseline, is printed as MISSED/LATER and the script exits 1 (earlier times and extra pairs are printed
too). Printed per run: seconds, narrow-phase tests and us per test, event counts; then per shot the
ratios ksl/swept (process time, one thread), each METHOD/METHOD@baseline (process time) and the
wall-time speed-up of each thread count over one. --markdown writes the same as a page, rewritten
after every shot, with the 1-minute load average seen at the start of every run.
"""

from __future__ import annotations

import argparse
import datetime
import hashlib
import os
import shlex
import sys
import tempfile

import numpy as np

from harness import Build, alternate, git_revision, load_average, measuring

EVENT_COUNTERS = ("kinetic_tree_events", "bv_overlap_events", "fathers_do_not_overlap_events",
                  "leaves_do_not_overlap_events", "plane_kept_steps", "polygons_collide_events", "bv_change_events")

#: A method label ending in this runs with the --baseline-python interpreter (another build of usdksl).
BASELINE_SUFFIX = "@baseline"

#: Largest difference between two builds' first-contact times of one face pair that still counts as the
#: same answer, in sample intervals (the shot's longest): the CCD root search stops once its time
#: interval is this narrow (native DEFAULT_CCD_TOLERANCE, a fraction of one step), so two correct
#: builds may report any time inside that last interval.
ANSWER_TIME_ALLOWANCE = 1e-6

#: Columns of the face-contact table a child saves for the cross-build comparison.
FACE_CONTACT_COLUMNS = ("time", "mesh_a", "face_a", "mesh_b", "face_b")


class GeneratedMesh:
    """The fields find_contacts reads, plus the loader's path and kind."""

    def __init__(self, path, kind, times, points, triangles, triangle_face):
        self.path, self.kind = path, kind
        self.times = np.asarray(times, dtype=np.float64)
        self.points = np.ascontiguousarray(points, dtype=np.float64)
        self.triangles = np.asarray(triangles, dtype=np.int32)
        self.triangle_face = np.asarray(triangle_face, dtype=np.int32)


def per_frame_cloth(n, frames):
    """A cloth (n x n quads, two triangles each) sampled at every frame on curved paths: it waves,
    sinks onto a static slab and folds its right half over its left (like
    tests/collision/test_exact_times.py::per_frame_cloth, scaled up)."""
    xs, zs = np.meshgrid(np.linspace(0.0, 1.0, n + 1), np.linspace(0.0, 1.0, n + 1), indexing="ij")
    rest = np.stack([xs.ravel(), np.zeros(xs.size), zs.ravel()], axis=1)
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    tris = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    quads = np.concatenate([np.arange(n * n), np.arange(n * n)])
    times = np.arange(0.0, float(frames))
    samples = np.empty((frames, rest.shape[0], 3))
    right = rest[:, 0] > 0.5
    dx = rest[right, 0] - 0.5
    for k, t in enumerate(times):
        u = t * 40.0 / frames  # the motion of the 40-frame test shot, spread over `frames`
        p = rest.copy()
        p[:, 1] = 0.35 - 0.012 * u + 0.04 * np.sin(3.0 * p[:, 0] + 0.4 * u) * np.cos(2.0 * p[:, 2] + 0.3 * u)
        fold = 1.15 * np.pi * min(u / 32.0, 1.0) ** 2
        p[right, 0] = 0.5 + dx * np.cos(fold)
        p[right, 1] += dx * np.sin(fold) + 0.03 * dx
        samples[k] = p
    cloth = GeneratedMesh("/cloth", "deforming", times, samples, tris, quads)
    w = 0.4
    slab_points = np.array([[[-w, 0.0, -w], [w, 0.0, -w], [w, 0.0, w], [-w, 0.0, w]]]) + [0.5, 0.0, 0.5]
    slab = GeneratedMesh("/slab", "static", [0.0], slab_points, [[0, 1, 2], [0, 2, 3]], [0, 0])
    return [cloth, slab]


def load_meshes(shot):
    if shot.startswith("perframe:"):
        _, n, frames = shot.split(":")
        return per_frame_cloth(int(n), int(frames))
    import usdksl
    return usdksl.load_shot(shot).meshes


def checked_pairs(meshes):
    deforming = [m.kind == "deforming" for m in meshes]
    pairs = [(i, i) for i, d in enumerate(deforming) if d]
    pairs += [(i, j) for i in range(len(meshes)) for j in range(i + 1, len(meshes)) if deforming[i] or deforming[j]]
    return pairs


def longest_sample_interval(meshes):
    """The longest gap between consecutive sample times of any mesh (time codes); 1.0 if none moves."""
    gaps = [float(np.diff(m.times).max()) for m in meshes if m.times.shape[0] > 1]
    return max(gaps) if gaps else 1.0


def run_one(shot, method, threads, contacts_out=None):
    """Runs one check in this process and returns its measurements as a dict; saves the first contact of
    every authored face pair (FACE_CONTACT_COLUMNS) to ``contacts_out`` (.npz) when given."""
    import usdksl
    meshes = load_meshes(shot)
    pairs = checked_pairs(meshes)
    kwargs = {} if threads is None else {"threads": threads}
    with measuring() as measured:
        result = usdksl.find_contacts(meshes, pairs, method=method, **kwargs)
    answer = hashlib.sha256()
    for column in (result.time, result.mesh_a, result.tri_a, result.mesh_b, result.tri_b, result.feature):
        answer.update(np.ascontiguousarray(column).tobytes())
    triangle_samples = sum(int(m.triangles.shape[0]) * int(m.times.shape[0]) for m in meshes)
    faces = result.face_contacts(meshes)
    if contacts_out:
        np.savez(contacts_out, **{name: getattr(faces, name) for name in FACE_CONTACT_COLUMNS})
    return {"cpu": measured.cpu_s, "wall": measured.wall_s, "counters": result.counters, "pairs": len(result),
            "face_pairs": len(faces), "answer": answer.hexdigest()[:16],
            "peak_bytes": measured.peak_rss_bytes, "triangle_samples": triangle_samples,
            "triangles": sum(int(m.triangles.shape[0]) for m in meshes),
            "sample_interval": longest_sample_interval(meshes), "usdksl": os.path.dirname(usdksl.__file__)}


def run_isolated(shot, label, threads, baseline_python=None, contacts_out=None):
    """Runs ``label`` (a method, or METHOD@baseline for the baseline interpreter) in a fresh process;
    ``run_one``'s measurements with the load average at the start."""
    build, method = Build.current(), label
    if label.endswith(BASELINE_SUFFIX):
        if not baseline_python:
            raise SystemExit(f"{label} needs --baseline-python")
        build, method = Build.of(baseline_python), label[:-len(BASELINE_SUFFIX)]
    load = load_average()
    measured = build.call(run_one, shot, method, threads, contacts_out)
    if measured.error:
        raise RuntimeError(f"{label} on {shot} failed: {measured.error}\n{measured.stderr}")
    return dict(measured.value, load=load)


def build_of(label):
    return "baseline" if label.endswith(BASELINE_SUFFIX) else "current"


def compare_face_contacts(reference, other, allowance):
    """Face contacts of ``other`` against ``reference`` (dicts of FACE_CONTACT_COLUMNS arrays, one row per
    face pair). ``allowance``: time codes by which the two may differ and still agree. Returns counts of
    pairs missed (in reference only), extra (in other only), later / earlier (in both, other's time past
    the allowance after / before reference's) and the largest time difference (time codes)."""
    def keys(contacts):
        return np.stack([np.asarray(contacts[c], np.int64) for c in FACE_CONTACT_COLUMNS[1:]], axis=1)

    ref_keys, other_keys = keys(reference), keys(other)
    _, inverse = np.unique(np.concatenate([ref_keys, other_keys]), axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    common, ref_at, other_at = np.intersect1d(inverse[:len(ref_keys)], inverse[len(ref_keys):],
                                              assume_unique=True, return_indices=True)
    delta = np.asarray(other["time"], np.float64)[other_at] - np.asarray(reference["time"], np.float64)[ref_at]
    return {"common": int(len(common)), "missed": int(len(ref_keys) - len(common)),
            "extra": int(len(other_keys) - len(common)), "later": int(np.count_nonzero(delta > allowance)),
            "earlier": int(np.count_nonzero(delta < -allowance)),
            "max_abs_dt": float(np.abs(delta).max()) if delta.size else 0.0}


def is_same_answer(comparison):
    return not any(comparison[k] for k in ("missed", "extra", "later", "earlier"))


def describe(shot, method, threads, r):
    c = r["counters"]
    tests = max(1, c["narrow_phase_tests"])
    events = sum(c.get(k, 0) for k in EVENT_COUNTERS)  # a baseline build may lack newer counters
    return (f"{os.path.basename(shot):32s} {method:12s} thr={threads or 1:<2d} cpu={r['cpu']:8.2f}s "
            f"wall={r['wall']:8.2f}s tests={c['narrow_phase_tests']:>10d} us/test={1e6 * r['cpu'] / tests:6.2f} "
            f"queries={c['primitive_queries']:>10d} events={events:>9d} (tree={c['kinetic_tree_events']} "
            f"pc={c['polygons_collide_events']} bvchg={c['bv_change_events']} overlap={c['bv_overlap_events']} "
            f"fathers={c['fathers_do_not_overlap_events']} leaves={c['leaves_do_not_overlap_events']} "
            f"plane={c.get('plane_kept_steps', 0)}) "
            f"confirm={c['raw_confirmations']} reject={c['raw_rejections']} windows={c.get('time_windows', 1)} "
            f"tri_pairs={r['pairs']} "
            f"face_pairs={r['face_pairs']} peak={r['peak_bytes'] / 2**20:.0f}MB "
            f"({r['peak_bytes'] / max(1, r['triangle_samples']):.0f} B/tri-sample) answer={r['answer']} "
            f"load={r['load']:.2f}")


def measure_shot(shot, labels, thread_counts, repeat, baseline_python, scratch):
    """Runs every (label, threads) ``repeat`` times, round after round; returns {(label, threads): best
    run} (least process time) and {(label, threads): saved face contacts}."""
    contacts = {}

    def setting(label, threads):
        def measure():
            path = os.path.join(scratch, f"{len(os.listdir(scratch))}.npz")
            r = run_isolated(shot, label, threads, baseline_python, path)
            print(describe(shot, label, threads, r), flush=True)
            contacts.setdefault((label, threads), path)
            return r
        return measure

    runs = alternate({(label, threads): setting(label, threads) for label in labels for threads in thread_counts},
                     repeat)
    return {key: min(records, key=lambda r: r["cpu"]) for key, records in runs.items()}, contacts


def judge_answers(shot, results, contacts):
    """Prints and returns (lines, cross-build comparisons {key: comparison}, failed)."""
    lines, comparisons, failed = [], {}, False
    for build in ("current", "baseline"):
        answers = {r["answer"] for (label, _), r in results.items() if build_of(label) == build}
        if len(answers) > 1:
            lines.append(f"{shot}: ANSWERS DIFFER between runs of the {build} build: {sorted(answers)}")
            failed = True
        elif answers:
            lines.append(f"{shot}: every run of the {build} build gave the same answer ({answers.pop()})")
    reference_key = next((key for key in results if build_of(key[0]) == "baseline"), None)
    if reference_key is not None:
        with np.load(contacts[reference_key]) as saved:
            reference = dict(saved)
        interval = results[reference_key]["sample_interval"]
        for key, r in results.items():
            if build_of(key[0]) != "current":
                continue
            with np.load(contacts[key]) as saved:
                c = compare_face_contacts(reference, dict(saved), ANSWER_TIME_ALLOWANCE * interval)
            comparisons[key] = c
            verdict = ("SAME answer within the CCD tolerance" if is_same_answer(c) else
                       "DIFFERENT answer")
            lines.append(f"{shot}: {key[0]} against {reference_key[0]}: {verdict}: {c['common']} face pairs in "
                         f"both, missed {c['missed']}, extra {c['extra']}, later {c['later']}, earlier "
                         f"{c['earlier']}, max |dt| {c['max_abs_dt']:.3g} time codes "
                         f"({c['max_abs_dt'] / interval:.3g} sample intervals)")
            if c["missed"] or c["later"]:
                lines.append(f"{shot}: !!! {key[0]} MISSES {c['missed']} AND DELAYS {c['later']} CONTACTS "
                             f"THAT {reference_key[0]} REPORTS !!!")
                failed = True
    for line in lines:
        print(line, flush=True)
    return lines, comparisons, failed


def ratio_lines(shot, results, labels, thread_counts):
    single, lines = thread_counts[0], []
    if ("ksl", single) in results and ("swept", single) in results:
        ratio = results[("ksl", single)]["cpu"] / results[("swept", single)]["cpu"]
        lines.append(f"{shot}: ksl/swept process time at threads={single or 'default'}: {ratio:.3f}")
    for label in labels:
        baseline = (label + BASELINE_SUFFIX, single)
        if baseline in results and (label, single) in results:
            ratio = results[(label, single)]["cpu"] / results[baseline]["cpu"]
            lines.append(f"{shot}: {label}/{baseline[0]} process time at threads={single or 'default'}: {ratio:.3f}")
    for label in labels:
        base = results.get((label, single))
        for threads in thread_counts[1:]:
            r = results[(label, threads)]
            lines.append(f"{shot}: {label} wall speed-up threads={threads} over threads={single}: "
                         f"{base['wall'] / r['wall']:.2f}x")
    for line in lines:
        print(line, flush=True)
    return lines


def answer_cell(comparisons, results, single):
    """'yes'/'NO' with the numbers for the markdown page, from the comparisons of this build's KSL run."""
    c = comparisons.get(("ksl", single)) or next(iter(comparisons.values()), None)
    if c is None:
        return "not compared"
    interval = next(iter(results.values()))["sample_interval"]
    detail = f"{c['common']} face pairs, max \\|dt\\| {c['max_abs_dt'] / interval:.2g} intervals"
    if is_same_answer(c):
        return f"yes ({detail})"
    return (f"**NO**: missed {c['missed']}, later {c['later']}, extra {c['extra']}, earlier {c['earlier']} "
            f"({detail})")


def render_markdown(title, command, shots_done, labels, thread_counts, builds):
    single = thread_counts[0]
    lines = [f"# {title}", "", f"Command (run under `nice`): `{command}`", "",
             f"Run on {os.uname().machine}, {os.cpu_count()} cores, started "
             f"{shots_done[0]['started'] if shots_done else ''}; builds: " +
             "; ".join(f"{build} = `{folder}` at {rev}" for build, (folder, rev) in builds.items()) + ".", "",
             f"`METHOD{BASELINE_SUFFIX}` is METHOD run by the baseline build, every other method by the current "
             "build; each run is a fresh process, the runs of one shot follow each other, so every ratio "
             "compares runs made minutes apart under the same machine load. Seconds are process time "
             "(CPU) of find_contacts alone, threads="
             f"{single or 'default'}; the machine is shared, so read the ratios, not the seconds. Same answer: "
             "authored face pairs and first-contact times of the current build's KSL against the baseline's "
             f"KSL, equal within {ANSWER_TIME_ALLOWANCE:g} sample intervals (the CCD tolerance).", ""]
    pairs = [label for label in labels if label + BASELINE_SUFFIX in labels]
    head = ["shot", "triangles x samples"] + [f"{label} CPU s" for label in labels]
    head += [f"{label}/{label}{BASELINE_SUFFIX}" for label in pairs]
    if "ksl" in labels and "swept" in labels:
        head.append("swept/ksl")
    head += ["same answer", "load (1 min)"]
    lines += ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for done in shots_done:
        results = done["results"]
        first = next(iter(results.values()))
        cells = [os.path.basename(done["shot"]),
                 f"{first['triangles']} x {first['triangle_samples'] // max(1, first['triangles'])}"]
        cells += [f"{results[(label, single)]['cpu']:.2f}" for label in labels]
        cells += [f"**{results[(label, single)]['cpu'] / results[(label + BASELINE_SUFFIX, single)]['cpu']:.3f}**"
                  for label in pairs]
        if "ksl" in labels and "swept" in labels:
            cells.append(f"{results[('swept', single)]['cpu'] / results[('ksl', single)]['cpu']:.2f}")
        loads = [r["load"] for r in results.values()]
        cells += [answer_cell(done["comparisons"], results, single), f"{min(loads):.1f}-{max(loads):.1f}"]
        lines.append("| " + " | ".join(cells) + " |")
    counters = ("bv_tests", "narrow_phase_tests", "primitive_queries", "cleared_steps")
    lines += ["", "## Counters", "",
              "Events: the sum of " + ", ".join(EVENT_COUNTERS) + ". Face pairs: contacting authored face pairs.", "",
              "| shot | method | threads | CPU s | wall s | " + " | ".join(counters) + " | events | face pairs | "
              "peak MB |", "|" + "---|" * (9 + len(counters))]
    for done in shots_done:
        for (label, threads), r in done["results"].items():
            c = r["counters"]
            lines.append(f"| {os.path.basename(done['shot'])} | {label} | {threads or 'default'} | {r['cpu']:.2f} | "
                         f"{r['wall']:.2f} | " + " | ".join(str(c.get(name, '')) for name in counters) +
                         f" | {sum(c.get(k, 0) for k in EVENT_COUNTERS)} | {r['face_pairs']} | "
                         f"{r['peak_bytes'] / 2**20:.0f} |")
    lines += ["", "## Printed verdicts", "", "```"]
    for done in shots_done:
        lines += done["lines"]
    lines += ["```", ""]
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("shots", nargs="?")
    parser.add_argument("methods", nargs="?", default="swept,ksl",
                        help=f"comma-separated; METHOD{BASELINE_SUFFIX} runs METHOD with --baseline-python")
    parser.add_argument("--threads", default=None,
                        help="comma-separated thread counts (default: the core's default, one run)")
    parser.add_argument("--repeat", type=int, default=1, help="runs per setting; the least process time counts")
    parser.add_argument("--baseline-python", default=None,
                        help="interpreter of another build of usdksl, for the METHOD@baseline methods")
    parser.add_argument("--markdown", default=None, help="write the results as a markdown page here")
    parser.add_argument("--title", default="KSL against swept in one run", help="heading of the --markdown page")
    args = parser.parse_args()
    thread_counts = [int(t) for t in args.threads.split(",")] if args.threads else [None]
    labels = args.methods.split(",")
    command = "python benchmarks/ksl_vs_swept.py " + " ".join(shlex.quote(a) for a in sys.argv[1:])
    status, shots_done, builds = 0, [], {}
    with tempfile.TemporaryDirectory(prefix="ksl_vs_swept_") as scratch:
        for shot in args.shots.split(","):
            started = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
            results, contacts = measure_shot(shot, labels, thread_counts, args.repeat, args.baseline_python, scratch)
            for (label, _), r in results.items():
                if build_of(label) not in builds:
                    builds[build_of(label)] = (r["usdksl"], git_revision(r["usdksl"]))
            lines, comparisons, failed = judge_answers(shot, results, contacts)
            lines += ratio_lines(shot, results, labels, thread_counts)
            status |= int(failed)
            shots_done.append({"shot": shot, "started": started, "results": results, "comparisons": comparisons,
                               "lines": lines})
            if args.markdown:
                with open(args.markdown, "w") as handle:
                    handle.write(render_markdown(args.title, command, shots_done, labels, thread_counts, builds))
    return status


if __name__ == "__main__":
    sys.exit(main())

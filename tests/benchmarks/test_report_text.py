"""The computed sentences of the report: ratios of work counters and the verdicts against the targets."""

import report


def record(cpu_s, wall_s=None, **counters):
    base = {name: 0 for name in ("kinetic_tree_events", "bv_overlap_events", "fathers_do_not_overlap_events",
                                 "leaves_do_not_overlap_events", "polygons_collide_events", "bv_change_events",
                                 "bv_tests", "narrow_phase_tests", "primitive_queries")}
    base.update(counters)
    return {"status": "ok", "cpu_s": cpu_s, "wall_s": wall_s or cpu_s, "peak_mem_bytes": 2**20, "counters": base}


def test_counter_reading_states_work_ratios_and_cost_per_query():
    ksl = record(10.0, polygons_collide_events=90, bv_overlap_events=10, bv_tests=100, narrow_phase_tests=50,
                 primitive_queries=1_000_000)
    swept = record(20.0, bv_tests=3000, narrow_phase_tests=500, primitive_queries=8_000_000)
    sparse = record(5.0, bv_tests=300, narrow_phase_tests=50, primitive_queries=800_000)
    text = report.counter_reading(ksl, swept, sparse)
    assert "swept does 30.0x the BV tests, 10.0x the narrow-phase tests and 8.0x the primitive CCD queries" in text
    assert "10.00 us against 2.50 us for swept" in text
    assert "90% of KSL's events are polygons-collide events" in text and "close contact dominates" in text
    assert "swept(dense)/swept(sparse) = 4.0x" in text


def shot(scene, size, spk):
    return {"scene": scene, "size": size, "samples_per_keyframe": spk, "triangles": size * 2,
            "moving_triangles": size * 2, "samples": 10 * spk + 1}


def test_headlines_judge_the_targets_on_the_largest_shot():
    rows = [
        {"shot": shot("tablecloth", 2000, 10), "methods": {"ksl": record(1.0), "swept": record(100.0)}},
        {"shot": shot("tablecloth", 16000, 1), "methods": {"ksl": record(4.0), "read": record(8.0)}},
        {"shot": shot("tablecloth", 16000, 10), "methods": {"ksl": record(5.0), "swept": record(50.0),
                                                             "read": record(10.0)}},
        {"shot": shot("swirl", 4000, 1), "methods": {"ksl": record(3.0), "swept": record(3.0)}},
    ]
    text = "\n".join(report.headlines(rows))
    assert "tablecloth 16000, 10 samples/keyframe" in text and "swept/KSL time **10.00x**" in text
    assert "target >= 20x: missed by 2.0x" in text
    assert "swirl 4000" in text and "target >= 2x: missed by 2.0x" in text
    assert "KSL time growth on tablecloth 16000 from 1 to 10 samples/keyframe: **+25%**" in text
    assert "target within 20%: missed" in text
    assert "**0.50x** the read time" in text and "target <= 1x: met" in text


def test_rows_of_the_same_shot_merge_and_a_run_replaces_a_skip(suite_rows):
    rows, _ = suite_rows
    first = {"shot": rows[0]["shot"], "methods": {label: dict(r) for label, r in rows[0]["methods"].items()}}
    first["methods"]["swept"] = {"label": "swept", "status": "skipped", "reason": "exceeded the 1 s budget"}
    second = {"shot": rows[0]["shot"], "methods": {"swept": dict(rows[0]["methods"]["swept"]),
                                                    "discrete": {"label": "discrete", "status": "skipped",
                                                                 "reason": "exceeded the 1 s budget"}}}
    merged = report.merge_rows([first, second])
    assert len(merged) == 1
    methods = merged[0]["methods"]
    assert methods["swept"]["status"] == "ok" and methods["swept"]["comparison"]["missed"] == 0
    assert methods["discrete"]["status"] == "ok"  # a later skip never hides a method that ran
    assert list(methods)[0] == "read" and "ksl" in methods


def test_swept_headline_uses_the_largest_shot_where_swept_ran():
    rows = [
        {"shot": shot("swirl", 4000, 10), "methods": {"ksl": record(2.0), "swept": record(5.0)}},
        {"shot": shot("swirl", 33000, 1), "methods": {"ksl": record(40.0), "swept": {
            "label": "swept", "status": "skipped", "reason": "exceeded the 900 s budget"}}},
    ]
    text = "\n".join(report.headlines(rows))
    assert "swirl 4000, 10 samples/keyframe" in text and "swept/KSL time **2.50x**" in text
    assert "target >= 2x: met" in text


def test_grid_table_has_a_cell_per_sampling_with_ratio_or_reason():
    rows = [
        {"shot": shot("swirl", 4000, 1), "methods": {"ksl": record(2.0), "swept": record(1.0)}},
        {"shot": shot("swirl", 4000, 10), "methods": {"ksl": record(2.0), "swept": record(8.0)}},
        {"shot": shot("swirl", 33000, 1), "methods": {"ksl": record(40.0), "swept": {
            "label": "swept", "status": "skipped", "reason": "exceeded the 900 s budget"}}},
    ]
    lines = report.grid_table(rows)
    assert lines[0] == "| shot | triangles | 1 spk | 10 spk |"
    assert "| swirl 4000 | 8000 | KSL 2 s, swept/KSL **0.50x** | KSL 2 s, swept/KSL **4.00x** |" in lines
    assert "| swirl 33000 | 66000 | KSL 40 s, swept skipped: exceeded the 900 s budget | not run |" in lines


def _run_row(path, revision, methods):
    return {"shot": dict(shot("character", 35000, 10), path=path), "revisions": [revision], "methods": methods}


def test_rows_merge_by_shot_name_across_checkouts_and_keep_same_build_comparisons(tmp_path):
    """A worktree's rows name the shot by another path and their raw contact files may be gone: the rows
    still merge, and a comparison made by the same build survives the other run's KSL record."""
    gone = str(tmp_path / "removed-worktree" / "raw" / "x.npz")
    quick = _run_row("/removed-worktree/samples/generated/character_35000_k11_s10.usdc", "b328df4", {
        "ksl": dict(record(2.0), contacts_file=gone),
        "discrete": dict(record(1.0), contacts_file=gone,
                         comparison={"missed": 7, "found": 3, "unit": "face pairs"})})
    grid = _run_row("samples/generated/character_35000_k11_s10.usdc", "b328df4", {
        "ksl": dict(record(2.5), contacts_file=gone), "swept": dict(record(9.0), contacts_file=gone,
                                                                    comparison={"missed": 0, "found": 10})})
    merged = report.merge_rows([quick, grid])
    assert len(merged) == 1
    methods = merged[0]["methods"]
    assert methods["ksl"]["cpu_s"] == 2.0  # the earlier run's KSL is kept; the later one only fills gaps
    assert methods["discrete"]["comparison"]["missed"] == 7 and methods["swept"]["comparison"]["missed"] == 0


def test_a_comparison_from_another_build_without_raw_files_is_marked_unavailable(tmp_path):
    gone = str(tmp_path / "gone.npz")
    old = _run_row("a/character_35000_k11_s10.usdc", "old1234", {
        "discrete": dict(record(1.0), contacts_file=gone, comparison={"missed": 7, "found": 3})})
    new = _run_row("b/character_35000_k11_s10.usdc", "new5678", {"ksl": dict(record(2.5), contacts_file=gone)})
    merged = report.merge_rows([old, new])
    discrete = merged[0]["methods"]["discrete"]
    assert "comparison" not in discrete and "raw contacts file missing" in discrete["comparison_unavailable"]
    assert any("discrete: not compared against KSL (raw contacts file missing" in line
               for line in report.method_table(merged[0]))


def test_different_shots_with_one_name_in_different_sizes_stay_apart():
    a = _run_row("x/shot.usdc", "r", {"ksl": record(1.0)})
    b = _run_row("y/shot.usdc", "r", {"ksl": record(1.0)})
    b["shot"]["triangles"] += 2
    assert len(report.merge_rows([a, b])) == 2


def test_ratios_use_ksl_from_the_same_run_and_earlier_runs_are_not_replaced():
    """A later run on a busier machine fills in a method; its ratio uses its own run's KSL, and it never
    replaces the ratios an earlier run measured."""
    quiet = _run_row("s/tablecloth_16000_k11_s10.usdc", "r", {"ksl": record(10.0), "swept": record(30.0)})
    busy = _run_row("t/tablecloth_16000_k11_s10.usdc", "r", {"ksl": record(20.0), "swept": record(50.0),
                                                             "discrete x4": record(40.0)})
    merged = report.merge_rows([quiet, busy])
    row = merged[0]
    assert row["methods"]["ksl"]["cpu_s"] == 10.0 and row["methods"]["swept"]["cpu_s"] == 30.0
    ratios = {r["method"]: r["cpu_vs_ksl"] for r in report.ratio_rows(row["methods"])}
    assert ratios["swept"] == 3.0 and ratios["discrete x4"] == 2.0
    assert "swept/KSL **3.00x**" in "\n".join(report.grid_table(merged))


def test_counter_reading_explains_swept_getting_cheaper_with_denser_sampling():
    ksl = record(10.0, polygons_collide_events=10, bv_overlap_events=10, bv_tests=100, narrow_phase_tests=50,
                 primitive_queries=1_000)
    dense = record(20.0, bv_tests=3000, narrow_phase_tests=500, primitive_queries=5_000)
    sparse = record(40.0, bv_tests=300, narrow_phase_tests=400, primitive_queries=9_000)
    text = report.counter_reading(ksl, dense, sparse)
    assert "= 0.5x in CPU" in text and "primitive CCD queries drop from 9000 to 5000" in text
    assert "drop from" not in report.counter_reading(ksl, sparse, dense)


def test_ipctk_over_its_budget_gives_a_lower_bound_against_check_from_the_same_run():
    run = _run_row("x/character_35000_k11_s1.usdc", "r", {
        "ksl": record(30.0), "check": record(40.0, wall_s=50.0),
        "ipctk": {"label": "ipctk", "status": "skipped", "reason": "exceeded the 2400 s budget"}})
    carried = _run_row("x/character_35000_k11_s10.usdc", "r", {
        "check": record(80.0), "ipctk": {"label": "ipctk", "status": "skipped",
                                          "reason": "exceeded the 2400 s budget at 1 samples/keyframe"}})
    quick = _run_row("q/character_35000_k11_s1.usdc", "r", {
        "check": record(40.0), "ipctk": {"label": "ipctk", "status": "skipped", "reason": "exceeded the 60 s budget"}})
    text = "\n".join(report.headlines(report.merge_rows([quick, run, carried])))
    assert "ipctk/check >= **48.0x** in wall time" in text and "met on 1 of 1" in text
    assert "10 samples/keyframe: ipctk over" not in text  # a carried skip has no time of its own


def test_hand_written_notes_are_embedded_under_investigations(tmp_path):
    rows = [{"shot": dict(shot("tablecloth", 2000, 1), path="a.usdc"), "methods": {"ksl": record(1.0)}}]
    assert "## Investigations" not in report.render(rows, 60.0, {}, str(tmp_path))
    (tmp_path / report.NOTES_MD).write_text("- a finding, with the command that checks it\n")
    page = report.render(rows, 60.0, {}, str(tmp_path))
    assert "## Investigations" in page and "- a finding, with the command that checks it" in page


def test_the_keyframed_before_after_page_follows_the_grid_it_checks(tmp_path):
    rows = [{"shot": dict(shot("tablecloth", 2000, 1), path="a.usdc"),
             "methods": {"ksl": record(1.0), "swept": record(2.0)}}]
    name, heading = report.GRID_BEFORE_AFTER_PAGE
    assert heading not in report.render(rows, 60.0, {}, str(tmp_path))
    (tmp_path / name).write_text("# before and after\n\n| shot | ksl/ksl@baseline |\n\n## Counters\n\nnumbers\n")
    page = report.render(rows, 60.0, {}, str(tmp_path))
    grid, section, plots = (page.index(s) for s in ("## KSL against swept across the grid", f"## {heading}",
                                                    "## Plots"))
    assert grid < section < plots
    assert "| shot | ksl/ksl@baseline |" in page and "### Counters" in page and "# before and after" not in page

"""The benchmark suite end to end on a tiny generated shot: every method, ratios, report, command."""

import json

import numpy as np
from click.testing import CliRunner

import report
from usdksl.ccd import DEFAULT_TOLERANCE
import suite


def test_every_method_runs_and_appears_in_the_ratio_table(suite_rows):
    rows, lines = suite_rows
    methods = rows[0]["methods"]
    table = {row["method"]: row for row in suite.ratio_rows(methods)}
    assert set(table) == set(suite.METHODS)
    assert all(row["status"] == "ok" for row in table.values()), {k: v["reason"] for k, v in table.items()}
    assert table["ksl"]["time_vs_ksl"] == 1.0
    for row in table.values():
        assert row["time_vs_ksl"] == row["wall_s"] / table["ksl"]["wall_s"]
    # the printed ratio lines name every method that ran
    assert all(any(line.strip().startswith(f"{label}/KSL time") for line in "\n".join(lines).splitlines())
               for label in suite.METHODS)


def test_counts_are_consistent_with_the_reference(suite_rows):
    rows, _ = suite_rows
    methods = rows[0]["methods"]
    ksl = np.load(methods["ksl"]["contacts_file"])
    assert len(ksl["time"]) > 0, "the tiny tablecloth should touch the table"
    for label in ("swept", "discrete", "discrete x2", "discrete x4", "discrete x8"):
        comparison = methods[label]["comparison"]
        assert comparison["found"] - comparison["extra"] + comparison["missed"] == len(ksl["time"])
    # both continuous methods report the same face pairs at the same first-contact times within the CCD
    # tolerance (a fraction of a flightplan step; merged steps are at most the whole shot long)
    swept = methods["swept"]["comparison"]
    assert (swept["missed"], swept["extra"]) == (0, 0)
    duration = float(ksl["sample_times"][-1] - ksl["sample_times"][0])
    assert swept["time_error_max"] <= 2 * DEFAULT_TOLERANCE * duration
    assert methods["ksl"]["counters"]["polygons_collide_events"] > 0
    assert methods["swept"]["counters"]["bv_tests"] > 0
    # the discrete methods report sample (or substep) times, never before the continuous first contact
    discrete = np.load(methods["discrete"]["contacts_file"])
    assert np.all(np.isin(discrete["time"], discrete["sample_times"]))
    first = {tuple(key): time for key, time in zip(suite._pair_keys(ksl).tolist(), ksl["time"])}
    later = [time >= first[tuple(key)] for key, time in zip(suite._pair_keys(discrete).tolist(), discrete["time"])
             if tuple(key) in first]
    assert later and all(later)


def test_removing_a_contact_from_a_method_counts_it_as_missed(suite_rows, tmp_path):
    rows, _ = suite_rows
    methods = {label: dict(record) for label, record in rows[0]["methods"].items()}
    swept_file = tmp_path / "swept.npz"
    with np.load(methods["swept"]["contacts_file"]) as data:
        arrays = {name: data[name] for name in data.files}
    np.savez(swept_file, **{name: (value[1:] if name != "sample_times" else value) for name, value in arrays.items()})
    methods["swept"]["contacts_file"] = str(swept_file)
    suite.add_comparisons(methods)
    assert methods["swept"]["comparison"]["missed"] == 1
    assert methods["swept"]["comparison"]["extra"] == 0


def test_ipctk_is_compared_per_interval(suite_rows):
    rows, _ = suite_rows
    record = rows[0]["methods"]["ipctk"]
    assert record["comparison"]["unit"] == "intervals"
    assert record["counters"]["intervals"] == rows[0]["shot"]["samples"] - 1
    assert record["comparison"]["found"] <= record["counters"]["intervals"]


def test_report_has_a_row_per_method_and_real_plots(suite_rows, tmp_path):
    rows, _ = suite_rows
    dense = json.loads(json.dumps(rows, default=float))
    sparse = json.loads(json.dumps(rows, default=float))
    sparse[0]["shot"]["samples_per_keyframe"] = 1  # a second sampling of the same shot for the Fig. 10 plot
    page_path = report.write_report(sparse + dense, 300.0, str(tmp_path), "test")
    page = open(page_path).read()
    for label in suite.METHODS:
        assert f"| {label} | " in page
    assert "KSL vs swept on tablecloth 150, 2 samples/keyframe" in page
    assert "KSL time growth on tablecloth 150 from 1 to 2 samples/keyframe: **+0%**" in page
    for name in ("time_vs_missed.png", "events_vs_bv_tests.png", "time_vs_samples.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert f"]({name})" in page
    saved = json.loads((tmp_path / report.SUMMARY_JSON).read_text())
    assert len(saved["rows"]) == 2


def test_skipped_methods_are_listed_with_their_reason(suite_rows):
    rows, _ = suite_rows
    methods = dict(rows[0]["methods"])
    methods["discrete x8"] = {"label": "discrete x8", "status": "skipped", "reason": "exceeded the 1 s budget"}
    row = {"shot": rows[0]["shot"], "methods": methods}
    table = "\n".join(report.method_table(row))
    assert "| discrete x8 | skipped: exceeded the 1 s budget |" in table


def test_bench_command_runs_the_same_suite(tiny_tablecloth, tmp_path):
    from usdksl.cli.main import main
    out = tmp_path / "rows.json"
    result = CliRunner().invoke(main, ["bench", str(tiny_tablecloth), "--methods", "ksl,swept", "--json", str(out)])
    assert result.exit_code == 0, result.output
    assert "swept/KSL time" in result.output
    saved = json.loads(out.read_text())
    assert set(saved["rows"][0]["methods"]) == {"ksl", "swept"}
    assert saved["rows"][0]["methods"]["swept"]["comparison"]["missed"] == 0
    bad = CliRunner().invoke(main, ["bench", str(tiny_tablecloth), "--methods", "ksl,nope"])
    assert bad.exit_code == 2 and "unknown methods: nope" in bad.output

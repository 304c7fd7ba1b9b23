"""``usdksl info``: one row per mesh with the loader's numbers; one error line and exit 2."""

from click.testing import CliRunner

from usdksl.cli.main import main
from usdksl.reading.loader import load_shot
from builders import sha256 as file_digest


def run(*args):
    return CliRunner().invoke(main, list(args))


def test_info_lists_each_mesh_with_counts_samples_range_and_kind(samples_dir):
    path = samples_dir / "clean.usda"
    result = run("info", str(path))
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[0].split() == ["prim", "faces", "vertices", "triangles", "samples", "time", "kind"]
    shot = load_shot(path)
    rows = {line.split()[0]: line.split() for line in lines[1:-1]}
    assert set(rows) == {m.path for m in shot.meshes}
    for mesh in shot.meshes:
        time = f"{mesh.times[0]:g}" if mesh.sample_count == 1 else f"{mesh.times[0]:g}..{mesh.times[-1]:g}"
        assert rows[mesh.path][1:] == [str(mesh.face_count), str(mesh.vertex_count),
                                       str(mesh.triangle_count), str(mesh.sample_count), time, mesh.kind]
    assert rows["/World/Mover/Box"][-1] == "rigid" and rows["/World/Box"][-1] == "static"
    assert lines[-1].startswith("shot: 3 meshes, 24 time samples, time 1..24, timeCodesPerSecond 24")


def test_info_time_range(samples_dir):
    result = run("info", "--time-range", "2.5", "4", str(samples_dir / "fold.usda"))
    assert result.exit_code == 0
    assert result.stdout.splitlines()[1].split()[4:] == ["3", "2.5..4", "deforming"]   # 2.5, 3, 4


def test_info_bad_input_prints_one_line_and_exits_2(tmp_path):
    path = tmp_path / "broken.usdc"
    path.write_bytes(b"PXR-USDC" + bytes(100))
    digest = file_digest(path)
    result = run("info", str(path))
    assert result.exit_code == 2
    assert result.stdout == ""
    assert result.stderr.count("\n") == 1
    assert result.stderr.startswith(f"usdksl: error: {path}: cannot open as USD")
    assert file_digest(path) == digest


def test_info_missing_file_exits_2(tmp_path):
    result = run("info", str(tmp_path / "missing.usd"))
    assert result.exit_code == 2
    assert result.stderr == f"usdksl: error: {tmp_path / 'missing.usd'}: no such file\n"

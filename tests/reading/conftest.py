"""Fixtures of the reading tests: new stages, and ``usdksl check`` with its CSV output read back."""

import csv

import pytest
from click.testing import CliRunner
from pxr import Sdf, Usd, UsdGeom

from builders import bare_stage, box, define_mesh, stretching_sheet, write_mesh
from usdksl.cli.main import main


@pytest.fixture
def build(tmp_path):
    """build(name, fill) -> path: a new stage, fill(stage) authors it, then it is saved."""
    def make(name, fill):
        path = tmp_path / name
        stage = bare_stage(path)
        fill(stage)
        stage.GetRootLayer().Save()
        return str(path)
    return make


def run_cli(*args):
    """CliRunner result of ``usdksl *args`` (stderr kept apart)."""
    return CliRunner().invoke(main, [str(arg) for arg in args])


def contact_rows(csv_path):
    """{(prim_a, face_a, prim_b, face_b): time} of a contacts.csv."""
    with open(csv_path, newline="") as stream:
        return {(row["prim_a"], int(row["face_a"]), row["prim_b"], int(row["face_b"])): float(row["time"])
                for row in csv.DictReader(stream)}


def summary_rows(csv_path):
    """{(prim_a, prim_b): (first_contact_time, face_pairs)} of a summary.csv."""
    with open(csv_path, newline="") as stream:
        return {(row["prim_a"], row["prim_b"]): (float(row["first_contact_time"]), int(row["face_pairs"]))
                for row in csv.DictReader(stream)}


@pytest.fixture
def check(tmp_path):
    """check(shot, *options) -> (result, contacts {pair: time}, summary {mesh pair: (time, count)})."""
    def run(shot, *options):
        out = tmp_path / "out"
        result = run_cli("check", shot, "--out", out, *options)
        stem = shot.stem if hasattr(shot, "stem") else str(shot).rsplit("/", 1)[-1].rsplit(".", 1)[0]
        contacts = out / f"{stem}.contacts.csv"
        summary = out / f"{stem}.summary.csv"
        return (result, contact_rows(contacts) if contacts.exists() else None,
                summary_rows(summary) if summary.exists() else None)
    return run


#: How the body of :func:`cloth_and_body` comes onto the shot's stage.
BODY_ARCS = ("reference", "payload", "sublayer", "clip")


@pytest.fixture
def cloth_and_body(tmp_path):
    """cloth_and_body(arc) -> (shot, body): shot.usda with a deforming cloth /World/Cloth and a box
    /World/Body falling through it (16 contacting face pairs from time 9.625), the box's animation in
    body.usda, brought in by ``arc`` (BODY_ARCS): a reference or payload (body.usda's default prim /Body), a
    sublayer (body.usda authors /World/Body), or a value clip (shot.usda defines the box's topology, its
    points come from clip body.usda through the manifest body_manifest.usda)."""
    def make(arc):
        points, counts, indices = box(0.5)
        falling = {1.0: points + [0.0, 1.0, 0.0], 24.0: points + [0.0, -1.0, 0.0]}
        body_path = tmp_path / "body.usda"
        body = Usd.Stage.CreateNew(str(body_path))
        body.SetTimeCodesPerSecond(24)
        root = "/World/Body" if arc == "sublayer" else "/Body"
        if arc == "sublayer":
            UsdGeom.Xform.Define(body, "/World")
        define_mesh(body, root, None, counts, indices, samples=falling)
        body.SetDefaultPrim(body.GetPrimAtPath("/" + root.split("/")[1]))
        body.GetRootLayer().Save()

        shot_path = tmp_path / "shot.usda"
        shot = Usd.Stage.CreateNew(str(shot_path))
        shot.SetTimeCodesPerSecond(24)
        shot.SetStartTimeCode(1)
        shot.SetEndTimeCode(24)
        shot.SetDefaultPrim(UsdGeom.Xform.Define(shot, "/World").GetPrim())
        stretching_sheet(shot, "/World/Cloth")
        if arc == "reference":
            shot.DefinePrim("/World/Body").GetReferences().AddReference("./body.usda")
        elif arc == "payload":
            shot.DefinePrim("/World/Body").GetPayloads().AddPayload("./body.usda")
        elif arc == "sublayer":
            shot.GetRootLayer().subLayerPaths.append("./body.usda")
        elif arc == "clip":
            manifest = Sdf.Layer.CreateNew(str(tmp_path / "body_manifest.usda"))
            spec = Sdf.CreatePrimInLayer(manifest, "/Body")
            spec.specifier = Sdf.SpecifierOver
            Sdf.AttributeSpec(spec, "points", Sdf.ValueTypeNames.Point3fArray)
            manifest.Save()
            # no points in the shot: a stronger default would hide the clip's samples
            clips = Usd.ClipsAPI(write_mesh(shot, "/World/Body", counts, indices).GetPrim())
            clips.SetClipAssetPaths([Sdf.AssetPath("./body.usda")])
            clips.SetClipPrimPath("/Body")
            clips.SetClipActive([(1.0, 0.0)])
            clips.SetClipTimes([(1.0, 1.0), (24.0, 24.0)])
            clips.SetClipManifestAssetPath(Sdf.AssetPath("./body_manifest.usda"))
        else:
            raise ValueError(arc)
        shot.GetRootLayer().Save()
        return shot_path, body_path
    return make

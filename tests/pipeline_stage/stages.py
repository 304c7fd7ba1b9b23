"""Stages the check_stage and validator tests open and change in memory (tests/validation imports it too): a
cloth with a prop whose variant decides which mesh it is, and a variant switched as usdchecker and DCCs switch
them."""

from pxr import Usd, UsdGeom

from builders import box, define_mesh, new_stage, stretching_sheet

#: The prop's variant set: "clear" holds a box above the cloth, "through" one the cloth passes through.
PROP_VARIANTS = "placement"
CLEAR_BOX = "/World/Prop/Clear"
THROUGH_BOX = "/World/Prop/Through"


def write_prop_with_variants(path):
    """A stretching cloth at y = 0 and a prop whose variant "clear" (selected in the file) is a box 3 units
    above it and whose variant "through" is a box the cloth passes through. Returns ``path``."""
    stage = new_stage(path)
    stretching_sheet(stage, "/World/Cloth")
    prop = UsdGeom.Xform.Define(stage, "/World/Prop").GetPrim()
    variants = prop.GetVariantSets().AddVariantSet(PROP_VARIANTS)
    points, counts, indices = box(1.0)
    for variant, mesh, height in (("clear", CLEAR_BOX, 3.0), ("through", THROUGH_BOX, 0.0)):
        variants.AddVariant(variant)
        variants.SetVariantSelection(variant)
        with variants.GetVariantEditContext():
            define_mesh(stage, mesh, points + [0.0, height, 0.0], counts, indices)
    variants.SetVariantSelection("clear")
    stage.GetRootLayer().Save()
    return path


def select_in_session(stage, prim_path, variant_set, variant):
    """Switch a variant on the stage only, as usdchecker and a DCC do: in its session layer."""
    with Usd.EditContext(stage, stage.GetSessionLayer()):
        stage.GetPrimAtPath(prim_path).GetVariantSets().SetSelection(variant_set, variant)

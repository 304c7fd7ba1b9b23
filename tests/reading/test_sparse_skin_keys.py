"""Skinned meshes keyed more sparsely than the frames are posed at every frame, as UsdSkel.BakeSkinning bakes
them: USD slerps joint rotations between keys, and a straight line between two skinned keys is not that pose."""

import numpy as np
import pytest
from pxr import Usd, UsdSkel

from usdksl.pipeline.memory_budget import scan_shot
from usdksl.reading.loader import load_shot, shot_sample_times
from usdksl.reading.skinning import find_skinned_meshes, playback_frames

from builders import baked_copy, skinned_arm

#: Largest time difference between a contact on the skinned stage and on its baked copy (time codes).
TIME_AGREEMENT = 1e-4
#: Largest difference between a posed point and BakeSkinning's (scene units; both are float32 skinning).
POINT_AGREEMENT = 1e-5
#: The arm's elbow bends this far between its first and last key (degrees): 50 degrees between two keys four
#: frames apart, so the straight line between keys cuts well inside the slerped arc.
BEND_DEGREES = 150.0
#: Frames between two keys of the sparse arm.
KEY_EVERY = 4
FIRST_KEY, LAST_KEY = 1.0, 13.0
ARM = "/World/Character/Arm"


def sparse_arm(path, end=None, tcps=None, fps=None, time_range=True):
    """The skinned arm of builders.skinned_arm bending down through the sheet, its joint rotations keyed
    every KEY_EVERY frames from FIRST_KEY to LAST_KEY only, the SkelRoot's translation keyed at both ends
    (BakeSkinning takes the keys of the Skeleton's own transform, not of its ancestors', into its times).
    ``end``/``tcps``/``fps``: the stage's endTimeCode and rates; ``time_range=False`` removes
    startTimeCode/endTimeCode."""
    skinned_arm(path, bend_degrees=((FIRST_KEY, 0.0), (LAST_KEY, BEND_DEGREES)),
                root_motion=((FIRST_KEY, (0.0, 0.0, 0.0)), (LAST_KEY, (0.4, 0.0, 0.0))))
    stage = Usd.Stage.Open(str(path))
    rotations = UsdSkel.Animation(stage.GetPrimAtPath("/World/Character/Anim")).GetRotationsAttr()
    every_frame = {time: rotations.Get(time) for time in rotations.GetTimeSamples()}
    rotations.Clear()
    for time in np.arange(FIRST_KEY, LAST_KEY + 0.5, KEY_EVERY):
        rotations.Set(every_frame[float(time)], float(time))
    layer = stage.GetRootLayer()
    if end is not None:
        stage.SetEndTimeCode(end)
    if tcps is not None:
        stage.SetTimeCodesPerSecond(tcps)
    if fps is not None:
        stage.SetFramesPerSecond(fps)
    if not time_range:
        layer.ClearStartTimeCode()
        layer.ClearEndTimeCode()
    layer.Save()
    return path


@pytest.fixture
def sparse(tmp_path):
    path = sparse_arm(tmp_path / "sparse.usda")
    return path, baked_copy(path, tmp_path / "sparse_baked.usda")


def test_contacts_equal_those_of_the_baked_copy_and_differ_on_keys_only(sparse, check):
    path, baked = sparse
    result, contacts, _ = check(path)
    baked_result, baked_contacts, _ = check(baked)
    keys_result, keys_contacts, _ = check(path, "--skin-keys-only")
    assert result.exit_code == baked_result.exit_code == keys_result.exit_code == 1, (
        result.stderr + baked_result.stderr + keys_result.stderr)
    assert len(contacts) > 10
    assert set(contacts) == set(baked_contacts)
    assert max(abs(contacts[key] - baked_contacts[key]) for key in contacts) <= TIME_AGREEMENT
    # on straight lines between the keys the forearm cuts inside its arc: other pairs, or later
    shared = set(keys_contacts) & set(baked_contacts)
    assert set(keys_contacts) != set(baked_contacts) or max(
        abs(keys_contacts[key] - baked_contacts[key]) for key in shared) > TIME_AGREEMENT


def test_points_at_every_frame_equal_bake_skinning(sparse):
    path, baked = sparse
    mesh, reference = load_shot(path).mesh(ARM), load_shot(baked).mesh(ARM)
    assert mesh.times.tolist() == reference.times.tolist() == [float(t) for t in range(1, 14)]
    assert np.allclose(mesh.points, reference.points, rtol=0, atol=POINT_AGREEMENT)
    keys = load_shot(path, skin_keys_only=True).mesh(ARM)
    assert keys.times.tolist() == [1.0, 5.0, 9.0, 13.0]
    between = int(np.flatnonzero(reference.times == 3.0)[0])
    # at frame 3 the straight line between the keys at 1 and 5 is not UsdSkel's pose
    chord = 0.5 * (keys.points[0] + keys.points[1])
    assert np.abs(chord - reference.points[between]).max() > 0.05


@pytest.mark.parametrize("end, tcps, fps, expected", [
    (24.0, None, None, [float(t) for t in range(1, 14)]),
    # BakeSkinning's frames run one step past endTimeCode (11), not further
    (10.0, None, None, [float(t) for t in range(1, 12)] + [13.0]),
    # two time codes per frame: frames at 1, 3, 5, ...
    (24.0, 48.0, 24.0, [1.0, 3.0, 5.0, 7.0, 9.0, 11.0, 13.0]),
])
def test_frames_are_those_bake_skinning_bakes(tmp_path, end, tcps, fps, expected):
    path = sparse_arm(tmp_path / "rates.usda", end=end, tcps=tcps, fps=fps)
    baked = baked_copy(path, tmp_path / "rates_baked.usda")
    mesh, reference = load_shot(path).mesh(ARM), load_shot(baked).mesh(ARM)
    assert mesh.times.tolist() == reference.times.tolist() == expected
    assert np.allclose(mesh.points, reference.points, rtol=0, atol=POINT_AGREEMENT)


def test_playback_frames_follow_bake_skinning_arithmetic(tmp_path):
    stage = Usd.Stage.CreateInMemory()
    assert playback_frames(stage, 0.0, 100.0).size == 0                  # no authored range: no frames
    stage.SetStartTimeCode(1001.0)
    stage.SetEndTimeCode(1003.5)
    stage.SetTimeCodesPerSecond(24.0)
    stage.SetFramesPerSecond(30.0)                                       # 0.8 time codes per frame
    frames = playback_frames(stage, 0.0, 2000.0)
    assert frames.tolist() == [1001.0 + 0.8 * i for i in range(5)]       # int(2.5 / 0.8 + 1) = 4: 0..4
    assert playback_frames(stage, 1001.5, 1002.7).tolist() == [1001.0 + 0.8 * i for i in (1, 2)]


def test_only_frames_within_the_time_range_are_added(sparse):
    path, _ = sparse
    mesh = load_shot(path, time_range=(2.5, 7.5)).mesh(ARM)
    assert mesh.times.tolist() == [2.5, 3.0, 4.0, 5.0, 6.0, 7.0, 7.5]


def test_a_note_says_so_and_names_the_option(sparse):
    path, baked = sparse
    notes = load_shot(path).notes
    assert notes == [f"{path}: 1 skinned mesh keyed more sparsely than the frames (first {ARM}) is posed at "
                     f"every frame, as UsdSkel.BakeSkinning does (--skin-keys-only checks on the keys only)"]
    keys_only = load_shot(path, skin_keys_only=True).notes
    assert len(keys_only) == 1 and "posed at the keys only (--skin-keys-only)" in keys_only[0]
    assert load_shot(baked).notes == []
    # a range between the keys at 5 and 9 that holds no frame: nothing is added, nothing said
    assert load_shot(path, time_range=(5.25, 5.75)).notes == []


def test_a_mesh_keyed_every_frame_gets_no_extra_samples(tmp_path):
    path = tmp_path / "dense.usda"
    skinned_arm(path)                                  # joints keyed at every frame from 1 to 12
    stage = Usd.Stage.Open(str(path))
    arm = find_skinned_meshes(stage)[ARM]
    assert arm.frames_between_keys().size == 0
    assert arm.sample_times().tolist() == arm.key_times().tolist() == [float(t) for t in range(1, 13)]
    shot = load_shot(path)
    assert shot.mesh(ARM).times.tolist() == load_shot(path, skin_keys_only=True).mesh(ARM).times.tolist()
    assert shot.notes == []


def test_without_an_authored_range_the_keys_are_posed_and_a_note_says_why(tmp_path):
    """BakeSkinning bakes no playback frame on a stage without startTimeCode/endTimeCode; nor does usdksl."""
    path = sparse_arm(tmp_path / "unranged.usda", time_range=False)
    baked = baked_copy(path, tmp_path / "unranged_baked.usda")
    shot = load_shot(path)
    assert shot.mesh(ARM).times.tolist() == load_shot(baked).mesh(ARM).times.tolist() == [1.0, 5.0, 9.0, 13.0]
    assert len(shot.notes) == 1 and "authors no startTimeCode/endTimeCode" in shot.notes[0]


def test_sample_counts_and_the_memory_estimate_count_the_frames(sparse):
    path, _ = sparse
    arm_times = [len(times) for times in shot_sample_times(path)]
    keys_times = [len(times) for times in shot_sample_times(path, skin_keys_only=True)]
    assert sorted(arm_times) == [2, 13] and sorted(keys_times) == [2, 4]     # the sheet, the arm
    points = load_shot(path).mesh(ARM).vertex_count
    every_frame, keys_only = scan_shot(str(path)), scan_shot(str(path), skin_keys_only=True)
    assert every_frame.vertex_samples - keys_only.vertex_samples == (13 - 4) * points

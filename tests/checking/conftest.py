"""Fixtures shared by the checking tests."""

from types import SimpleNamespace

import pytest


@pytest.fixture(scope="session")
def newton_twist_within_1cm(newton_twist_path):
    """The third-party twist's one mesh and its contacts within 0.01 at one thread, checked once for the
    tests that look at it: SimpleNamespace(mesh, thickness, result)."""
    from usdksl import load_shot
    from usdksl.checking.collision import find_contacts
    mesh = load_shot(newton_twist_path).meshes[0]
    thickness = 0.01
    return SimpleNamespace(mesh=mesh, thickness=thickness,
                           result=find_contacts([mesh], [(0, 0)], thickness=thickness, threads=1))


@pytest.fixture(scope="session")
def ipctk_reference():
    """tests/reference/tight_inclusion.py: first contacts of whole shots from ipctk's Tight-Inclusion CCD,
    sharing no code with the core (skips without ipctk)."""
    pytest.importorskip("ipctk")
    from reference import tight_inclusion
    return tight_inclusion

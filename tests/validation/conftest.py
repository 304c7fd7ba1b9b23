"""The validator, registered once per test process as a DCC session would register it."""

import pytest

import usdksl


@pytest.fixture(scope="session")
def validator():
    """``usdkslValidators:NoInterpenetration`` from usdksl.register_validators()."""
    return usdksl.register_validators()

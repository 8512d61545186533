"""Fixtures shared by several test files."""

import pytest

from spurdyn.contact.constants import FLANK
from twin_helpers import Loaded


@pytest.fixture(scope="session")
def loaded():
    """The paper's pair after 1,500 compiled steps at 20,000 rpm (twin_helpers.Loaded)."""
    st = Loaded()
    assert st.S.x[-1] < -100.0                    # pressed together by ~200 N
    assert st.contact.mode == FLANK
    assert 0.05 < st.S.theta[0] < 0.14            # on the torque ramp (non-zero slope)
    return st

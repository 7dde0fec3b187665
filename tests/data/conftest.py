"""Fixtures of the data tests."""

from __future__ import annotations

from pathlib import Path

import pytest
from data_recordings import xy_cells


@pytest.fixture
def xy_mat(tmp_path) -> Path:
    import scipy.io

    path = tmp_path / "data_XY.mat"
    scipy.io.savemat(path, {"data": xy_cells()})
    return path

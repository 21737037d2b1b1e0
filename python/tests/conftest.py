"""Shared fixtures: the repository's scenes and LCP files, and the `hopsim` command line.

Tests that compare with the command line need its binary: `HOPSIM_BIN` (set by the Rust
test tests/python_package.rs), else `hopsim` on PATH. Without it they are skipped, or fail
when HOPSIM_REQUIRE_PYTHON=1 (CI).
"""

import os
import shutil
from pathlib import Path

import pytest

import hopsim

REPO = Path(__file__).resolve().parents[2]
SCENES = REPO / "scenes"
LCP_DATA = REPO / "tests" / "data" / "lcp"


@pytest.fixture(scope="session")
def lcp_data() -> Path:
    return LCP_DATA


@pytest.fixture(scope="session")
def robbit_path() -> Path:
    return SCENES / "robbit.toml"


@pytest.fixture(scope="session")
def robbit(robbit_path) -> hopsim.Scene:
    """Robbit for 2 s (10 000 steps): its first brakes and its first hop."""
    return hopsim.Scene.load(robbit_path, overrides={"simulation.duration": 2.0})


@pytest.fixture(scope="session")
def hopsim_bin() -> str:
    path = os.environ.get("HOPSIM_BIN") or shutil.which("hopsim")
    if path is None:
        message = "the hopsim command line is needed: set HOPSIM_BIN or put hopsim on PATH"
        if os.environ.get("HOPSIM_REQUIRE_PYTHON") == "1":
            pytest.fail(message)
        pytest.skip(message)
    return path

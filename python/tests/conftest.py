"""Fixtures of the Python API tests: the pllvo CLI of the same build, a rendered synthetic sequence, the shared data."""
import os
import subprocess
from pathlib import Path

import pytest


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("PLLVO_CLI")
    assert path and Path(path).is_file(), "PLLVO_CLI must name the pllvo executable of this build (ctest sets it)"
    return path


@pytest.fixture(scope="session")
def shared():
    source = Path(os.environ.get("PLLVO_SOURCE_DIR", Path(__file__).resolve().parents[2]))
    root = Path(os.environ.get("PLLVO_SHARED", source.parent / "shared"))
    assert (root / "data").is_dir(), f"the shared fixtures are missing: {root} (set PLLVO_SHARED)"
    return root


@pytest.fixture(scope="session")
def synthetic_stereo(cli, tmp_path_factory):
    """A 3 s synthetic stereo sequence (EuRoC layout, 20 Hz, with ground truth)."""
    out = tmp_path_factory.mktemp("synth") / "easy_normal"
    subprocess.run([cli, "synth", "--preset", "easy_normal", "--duration", "3", "--stereo", "--out", str(out)],
                   check=True, capture_output=True)
    return out

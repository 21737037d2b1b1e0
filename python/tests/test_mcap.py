"""hopsim.read_mcap: recordings of the command line, and files that are not recordings."""

import os
import subprocess

import numpy as np
import pytest

import hopsim


def test_recording_has_its_metadata_impulses_and_scene(hopsim_bin, robbit_path, tmp_path):
    mcap = tmp_path / "r.mcap"
    subprocess.run(
        [hopsim_bin, "run", str(robbit_path), "--duration", "2", "--quiet", "--mcap", str(mcap)],
        check=True,
    )
    r = hopsim.read_mcap(mcap)
    assert r.metadata["scene"] == "Robbit"
    assert r.metadata["coordinates"] == ["x", "y", "phi", "psi"]
    assert r.metadata["dt"] == 2e-4
    assert r.scene_text == robbit_path.read_text()
    assert r.stopped is None
    assert r.q.shape == (len(r), 4) and r.u.shape == (len(r), 4)
    assert r.steps[0] == 0 and np.all(np.diff(r.steps) > 0)
    brakes = [e for e in r.events if e["kind"] == "brake"]
    assert brakes
    channel = np.array(r.impulses["channel"])
    np.testing.assert_array_equal(
        r.impulses["normal"][channel == "brake"], [e["impulse_Nms"] for e in brakes]
    )
    pd = pytest.importorskip("pandas")
    frame = r.to_pandas()
    assert isinstance(frame, pd.DataFrame)
    assert list(frame.columns)[:3] == ["t_s", "step", "x"]


def test_a_recording_kept_after_a_stop_says_why(hopsim_bin, robbit_path, tmp_path):
    mcap = tmp_path / "r.mcap"
    run = subprocess.run(
        [hopsim_bin, "run", str(robbit_path), "--duration", "0.1", "--quiet", "--mcap", str(mcap)],
        env={**os.environ, "HOPSIM_PANIC_AT_STEP": "50"},
        capture_output=True,
    )
    assert run.returncode != 0 and not mcap.exists()
    r = hopsim.read_mcap(tmp_path / "r.partial.mcap")
    assert r.stopped["reason"].startswith("internal error in step 50 ")
    assert r.stopped["step"] == 49
    assert r.stopped["t"] == pytest.approx(49 * r.metadata["dt"], rel=1e-12)
    assert r.steps[-1] <= 49 and "stopped after step 49" in repr(r)


def test_not_a_recording_is_a_value_error(tmp_path):
    bad = tmp_path / "bad.mcap"
    bad.write_bytes(b"not an mcap file")
    with pytest.raises(ValueError) as info:
        hopsim.read_mcap(bad)
    assert "bad.mcap" in str(info.value)
    with pytest.raises(ValueError):
        hopsim.read_mcap(tmp_path / "missing.mcap")

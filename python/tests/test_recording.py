"""Recordings of runs stepped from Python (`Simulation.record`, `Batch.record`): read back
with the `mcap` package and hopsim's reader, against `hopsim run`'s recording and summary
of the same run, `rerun rrd verify` on the `.rrd`, atomic outputs."""

import json
import os
import shutil
import subprocess

import numpy as np
import pytest

import hopsim
from test_simulation import MomentumImpulse, without_timing

mcap_reader = pytest.importorskip("mcap.reader")


def cli_recording(hopsim_bin, robbit_path, out):
    """`hopsim run` of Robbit for 2 s: its MCAP file and its summary."""
    mcap, summary = out / "cli.mcap", out / "cli.json"
    subprocess.run(
        [hopsim_bin, "run", str(robbit_path), "--duration", "2", "--quiet"]
        + ["--mcap", str(mcap), "--summary", str(summary)],
        check=True,
    )
    return mcap, json.loads(summary.read_text())


def messages(path):
    """The MCAP file's messages by topic, JSON decoded, in log-time order."""
    by_topic = {}
    with open(path, "rb") as f:
        reader = mcap_reader.make_reader(f)
        for _, channel, message in reader.iter_messages(log_time_order=True):
            by_topic.setdefault(channel.topic, []).append(json.loads(message.data))
    return by_topic


def test_a_python_controlled_run_records_what_hopsim_run_records(
    robbit, robbit_path, hopsim_bin, tmp_path
):
    """Robbit driven by its controller written in Python (test_simulation.py), recorded to
    MCAP, Rerun and CSV: the MCAP file has `hopsim run`'s channels and message counts (a
    frame at step 0, every `1 / (rate Δt)` steps and at every step with an event), its
    coordinates are the simulation's states at those steps bit for bit, it equals the
    recording of `hopsim run` (the Python controller reproduces the built-in one), and the
    summary `close()` returns is the CLI's but for the wall time."""
    sim = hopsim.Simulation(robbit)
    controller = MomentumImpulse(robbit)
    every = round(1.0 / (robbit.settings["record_rate"] * robbit.dt))
    steps = round(robbit.duration / robbit.dt)
    outputs = [tmp_path / "run.mcap", tmp_path / "run.rrd", tmp_path / "run.csv"]
    states = {0: sim.q}
    with sim.record(*outputs) as recorder:
        for _ in range(steps):
            sim.step(actuation=controller(sim))
            if sim.step_count % every == 0 or sim.events():
                states[sim.step_count] = sim.q
    summary = recorder.summary
    assert recorder.closed and summary is not None
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["run.csv", "run.events.csv", "run.mcap", "run.rrd"], names

    # Read with the `mcap` package.
    topics = messages(tmp_path / "run.mcap")
    cli_mcap, cli_summary = cli_recording(hopsim_bin, robbit_path, tmp_path / "cli")
    cli_topics = messages(cli_mcap)
    assert sorted(topics) == sorted(cli_topics)
    assert "/hopsim/state" in topics and "/foxglove/transforms" in topics
    state = topics["/hopsim/state"]
    assert len(state) == len(states) > steps // every
    brakes = [e for e in topics["/hopsim/events"] if e["kind"] == "brake"]
    assert len(brakes) >= 2
    for message, (step, q) in zip(state, sorted(states.items())):
        assert message["step"] == step
        np.testing.assert_array_equal([message["q"][c] for c in robbit.coordinates], q)
    for topic, recorded in topics.items():
        assert len(recorded) == len(cli_topics[topic]), topic
    assert topics["/hopsim/state"] == cli_topics["/hopsim/state"]
    assert topics["/hopsim/events"] == cli_topics["/hopsim/events"]

    assert without_timing(summary) == without_timing(cli_summary)
    assert summary["steps"] == steps and summary["robbit"]["brakes_per_s"] > 0

    # The CSV has one row per frame.
    rows = (tmp_path / "run.csv").read_text().splitlines()
    assert len(rows) == 1 + len(states)


def test_the_rrd_of_a_python_run_loads_in_the_rerun_cli(robbit, tmp_path):
    rerun = shutil.which("rerun")
    if rerun is None:
        message = "the `rerun` CLI is not on PATH (pip install rerun-sdk==0.36.3)"
        if os.environ.get("HOPSIM_REQUIRE_PYTHON") == "1":
            pytest.fail(message)
        pytest.skip(message)
    sim = hopsim.Simulation(robbit)
    push = hopsim.Actuation()
    push.torque(robbit.controller["flywheel"], 0.1)
    with sim.record(tmp_path / "run.rrd"):
        sim.step(2000, actuation=push)
    env = dict(os.environ, RERUN_ANALYTICS="0")
    verify = subprocess.run(
        [rerun, "rrd", "verify", str(tmp_path / "run.rrd")],
        capture_output=True,
        text=True,
        env=env,
    )
    assert verify.returncode == 0, verify.stdout + verify.stderr


def test_a_run_that_raises_leaves_no_file_that_looks_complete(robbit, tmp_path):
    """An exception in the `with` block keeps the frames up to it under the partial name,
    with the exception as the reason; a recorder dropped unclosed leaves nothing."""
    sim = hopsim.Simulation(robbit)
    with pytest.raises(ZeroDivisionError):
        with sim.record(tmp_path / "run.mcap", tmp_path / "run.csv") as recorder:
            sim.step(500)
            1 / 0
    assert not (tmp_path / "run.mcap").exists() and not (tmp_path / "run.csv").exists()
    assert sorted(os.path.basename(p) for p in recorder.kept) == [
        "run.partial.csv",
        "run.partial.events.csv",
        "run.partial.mcap",
    ]
    partial = hopsim.read_mcap(tmp_path / "run.partial.mcap")
    assert partial.stopped["step"] == 500
    assert "ZeroDivisionError" in partial.stopped["reason"]
    assert partial.steps[-1] <= 500

    recorder = sim.record(tmp_path / "dropped.mcap")
    sim.step(10)
    del recorder
    sim._record_abort("test")  # the simulation still holds it: end it without keeping
    assert not (tmp_path / "dropped.mcap").exists()


def test_a_recorded_run_whose_step_fails_keeps_a_partial_recording(robbit, tmp_path):
    sim = hopsim.Simulation(robbit)
    recorder = sim.record(tmp_path / "run.mcap")
    sim.step(20)
    kick = hopsim.Actuation()
    kick.point_impulse(0, (float("inf"), 0.0))
    with pytest.raises((hopsim.SimulationError, ValueError)):
        sim.step(actuation=kick)
    huge = hopsim.Actuation()
    huge.point_impulse(0, (1e300, 0.0))
    with pytest.raises(hopsim.SimulationError):
        sim.step(actuation=huge)
    with pytest.raises(hopsim.SimulationError, match="run.partial.mcap"):
        recorder.close()
    assert not (tmp_path / "run.mcap").exists()
    assert hopsim.read_mcap(tmp_path / "run.partial.mcap").stopped["step"] == 20


def test_recording_arguments_and_restarts_are_checked(robbit, tmp_path):
    sim = hopsim.Simulation(robbit)
    with pytest.raises(ValueError, match=r"\.mcap, \.rrd or \.csv"):
        sim.record(tmp_path / "run.txt")
    with pytest.raises(ValueError, match="twice"):
        sim.record(tmp_path / "a.mcap", tmp_path / "a.mcap")
    with sim.record(tmp_path / "run.mcap"):
        with pytest.raises(RuntimeError, match="already being recorded"):
            sim.record(tmp_path / "other.mcap")
        with pytest.raises(RuntimeError, match="being recorded"):
            sim.set_state(sim.q, sim.u)
        sim.step(10)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.mcap"]
    with pytest.raises(RuntimeError, match="already ended"):
        recorder = sim.record(tmp_path / "again.mcap")
        sim.step(10)
        recorder.close()
        recorder.close()


def same_states(path, other):
    """The recording at `path`, after checking that it records the steps, states and
    events of the one at `other` bit for bit."""
    a, b = hopsim.read_mcap(path), hopsim.read_mcap(other)
    np.testing.assert_array_equal(a.steps, b.steps)
    np.testing.assert_array_equal(a.q, b.q)
    np.testing.assert_array_equal(a.u, b.u)
    assert a.events == b.events
    return a


def test_a_recorded_copy_of_a_batch_records_as_a_single_simulation(robbit, tmp_path):
    """Copy 3 of a batch of 6 on two threads, recorded while every copy steps with its own
    start: its recording equals that of a single simulation with the same start, frame for
    frame and bit for bit (energies included), and so does its summary. A copy recorded
    from the middle of its run records the same states as the simulation from there."""
    n, copy = 6, 3
    batch = hopsim.Batch(robbit, n, threads=2)
    sim = hopsim.Simulation(robbit)
    for i in range(n):
        q = np.array(robbit.initial_q) + [0.01 * i, 0, 0, 0]
        batch.set_state(i, q, np.zeros(4))
    sim.set_state(batch.q[copy], batch.u[copy])
    with batch.record(copy, tmp_path / "copy.mcap") as from_batch:
        with pytest.raises(RuntimeError, match="recording"):
            batch.reset(copy)
        with sim.record(tmp_path / "single.mcap") as single:
            batch.step(3000)
            sim.step(3000)
    a = same_states(tmp_path / "copy.mcap", tmp_path / "single.mcap")
    assert a.steps[0] == 0 and len(a.steps) > 30
    assert messages(tmp_path / "copy.mcap") == messages(tmp_path / "single.mcap")
    energy = messages(tmp_path / "copy.mcap")["/hopsim/energy"]
    assert max(e["kinetic_J"] for e in energy) > 0.0
    assert without_timing(from_batch.summary) == without_timing(single.summary)
    assert from_batch.summary["steps"] == 3000

    # From the middle of the run (copy and simulation at step 3000, the same state).
    with batch.record(copy, tmp_path / "later.mcap"), sim.record(tmp_path / "later1.mcap"):
        batch.step(500)
        sim.step(500)
    a = same_states(tmp_path / "later.mcap", tmp_path / "later1.mcap")
    assert a.steps[0] == 3000 and len(a.steps) > 5
    batch.reset(copy)

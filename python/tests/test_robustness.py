"""Hostile calls: the bounds of the command line, Ctrl-C during long calls, states checked
as scene files are, and panics raised as hopsim exceptions (docs/python.md, "Errors,
bounds and signals")."""

import os
import re
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import hopsim
from conftest import SCENES


def short_robbit(robbit, **overrides):
    """Robbit for 0.1 s (500 steps) with `overrides`."""
    return robbit.with_overrides({"simulation.duration": 0.1, **overrides})


def depth_in(message):
    """The depth a start error names (`… 1.000000e-2 m inside …`)."""
    found = re.search(r"(\d\.\d+e[-+]?\d+) (m|rad)", message)
    assert found, message
    return float(found.group(1))


# --- bounds ---------------------------------------------------------------------------


def test_run_and_step_obey_max_steps(robbit):
    scene = short_robbit(robbit, **{"simulation.max_steps": 1000})
    assert scene.settings["max_steps"] == 1000
    sim = hopsim.Simulation(scene)
    with pytest.raises(ValueError, match=r"1001 steps.*simulation.max_steps = 1000") as info:
        sim.run(duration=1000.6 * scene.dt)
    assert "with_overrides({'simulation.max_steps': 1001})" in str(info.value)
    with pytest.raises(ValueError, match="simulation.max_steps = 1000"):
        sim.step(1001)
    assert sim.step_count == 0, "a refused call takes no step"
    sim.step(1000)
    assert sim.step_count == 1000
    assert len(sim.run(duration=1000 * scene.dt)) > 0


def test_absurd_runs_are_refused_before_they_start(robbit):
    sim = hopsim.Simulation(robbit)
    with pytest.raises(ValueError, match="more than simulation.max_steps = 100000000"):
        sim.run(duration=1e12)
    with pytest.raises(ValueError, match="at most 1e9: take fewer or larger steps"):
        sim.step(10**12)
    with pytest.raises(OverflowError):
        sim.step(10**30)
    for bad in (float("nan"), float("inf"), -1.0, 0.0):
        with pytest.raises(ValueError, match="duration must be positive and finite"):
            sim.run(duration=bad)
    with pytest.raises(ValueError, match="less than half a step of 0.0002 s"):
        sim.run(duration=0.4 * robbit.dt)
    assert sim.step_count == 0, "no step before the refusal"


def rss_bytes():
    """This process's resident memory now."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


@pytest.mark.skipif(not os.path.exists("/proc/self/statm"), reason="needs Linux /proc")
def test_a_run_without_frames_keeps_memory_bounded(robbit):
    # 200 s of Robbit: 1e6 steps, whose 200 000 frames (1 kHz) take about 27 MB.
    scene = robbit.with_overrides({"simulation.duration": 200.0})
    kept = hopsim.Simulation(scene).run(frames=False)
    before = rss_bytes()
    bare = hopsim.Simulation(scene).run(frames=False)
    grown = rss_bytes() - before
    full = hopsim.Simulation(scene).run()
    frames_bytes = full.frames.nbytes
    assert len(bare) == 0 and bare.events == [] and len(full) > 200_000
    assert frames_bytes > 20e6
    assert grown < 0.1 * frames_bytes, (grown, frames_bytes)
    # The same run either way: the summary does not depend on what is kept.
    for name in ("mean_speed_mps", "hops", "steps"):
        assert bare.summary[name] == full.summary[name] == kept.summary[name]


# --- Ctrl-C ---------------------------------------------------------------------------


def interrupted_after(code, delay=0.5):
    """Runs `code` in a child Python, sends SIGINT `delay` s after it prints `started`,
    and returns (seconds from the signal to its exit, its stdout, its stderr)."""
    script = textwrap.dedent(
        f"""
        import sys
        sys.path.insert(0, {str(SCENES.parent / 'python' / 'tests')!r})
        import numpy as np, hopsim
        from conftest import SCENES
        """
    ) + textwrap.dedent(code)
    child = subprocess.Popen(
        [sys.executable, "-c", script],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    line = child.stdout.readline()
    assert line.strip() == "started", (line, child.stderr.read())
    time.sleep(delay)
    child.send_signal(signal.SIGINT)
    signalled = time.perf_counter()
    try:
        out, err = child.communicate(timeout=30)
    finally:
        child.kill()
    return time.perf_counter() - signalled, out, err


LONG_ROBBIT = """
scene = hopsim.Scene.load(SCENES / "robbit.toml",
                          {"simulation.duration": 1e4, "simulation.max_steps": 1e9})
sim = hopsim.Simulation(scene)
"""


def test_ctrl_c_stops_a_long_run_and_keeps_its_frames():
    # 1e4 s of Robbit is 5e7 steps: half a minute or more.
    elapsed, out, err = interrupted_after(
        LONG_ROBBIT
        + """
print("started", flush=True)
try:
    sim.run()
except KeyboardInterrupt as e:
    frames = e.trajectory
    print(len(frames), int(frames.steps[-1]), sim.step_count, frames.summary, flush=True)
    raise
"""
    )
    assert "KeyboardInterrupt" in err, err
    assert elapsed < 1.5, elapsed
    frames, last, steps, summary = out.split()
    # Frames at 1 kHz (every 5th step) up to the last completed step, where it stopped.
    assert int(frames) > 100 and summary == "None"
    assert 0 <= int(steps) - int(last) < 5


@pytest.mark.parametrize(
    "call",
    [
        "sim.step(10**8)",
        "sim.step(10**8, actuation=hopsim.Actuation())",
        "sim.run(duration=1e4, frames=False)",
    ],
)
def test_ctrl_c_stops_many_steps(call):
    elapsed, _, err = interrupted_after(LONG_ROBBIT + f'print("started", flush=True)\n{call}\n')
    assert "KeyboardInterrupt" in err, err
    assert elapsed < 1.5, elapsed


def test_ctrl_c_stops_a_sweep_and_keeps_its_table():
    # Four runs of 2000 s (1e7 steps each): seconds of work on every core.
    elapsed, out, err = interrupted_after(
        """
scene = hopsim.Scene.load(SCENES / "robbit.toml", {"simulation.duration": 2000.0})
print("started", flush=True)
try:
    hopsim.sweep(scene, {"controller.torque": [0.14, 0.16, 0.18, 0.2]})
except KeyboardInterrupt as e:
    print(len(e.table), e.table["status"], e.table["error"], flush=True)
    raise
"""
    )
    assert "KeyboardInterrupt" in err, err
    assert elapsed < 1.5, elapsed
    assert out.startswith("4 ") and "interrupted at t = " in out, out


def test_ctrl_c_stops_a_large_lcp_solve():
    # n = 2500: several seconds of Lemke pivots.
    elapsed, _, err = interrupted_after(
        """
rng = np.random.default_rng(1)
n = 2500
a = rng.standard_normal((n, n))
m = a @ a.T / n + np.eye(n)
q = -rng.random(n)
print("started", flush=True)
hopsim.lcp.solve(m, q)
"""
    )
    assert "KeyboardInterrupt" in err, err
    assert elapsed < 1.5, elapsed


# --- states ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "q1, u1, t, message",
    [
        (1e300, 0.0, 0.0, r"q\[1\] \(y\) = 1e300: expected .* at most 1000000"),
        (float("nan"), 0.0, 0.0, r"q\[1\] \(y\) = NaN: expected a finite number"),
        (0.2, 1e5, 0.0, r"u\[1\] \(y\) = 100000: expected .* at most 10000"),
        (0.2, 0.0, -1e300, r"t = -1e300: expected .* at most 1000000000"),
        (0.2, 0.0, float("inf"), r"t = inf: expected a finite number"),
    ],
)
def test_set_state_refuses_values_a_scene_refuses(robbit, q1, u1, t, message):
    sim = hopsim.Simulation(robbit)
    q, u = robbit.initial_q, robbit.initial_u
    q[1], u[1] = q1, u1
    for restore in (False, True):
        with pytest.raises(ValueError, match=message):
            sim.set_state(q, u, t, restore=restore)
    np.testing.assert_array_equal(sim.q, robbit.initial_q)
    with pytest.raises(ValueError, match=r"q and u must have 4 entries \(x, y, phi, psi\)"):
        sim.set_state(q[:3], u)


def test_set_state_refuses_a_start_in_the_ground_with_its_depth(robbit):
    sim = hopsim.Simulation(robbit)
    q = robbit.initial_q
    q[1] -= 0.01
    with pytest.raises(ValueError, match="inside the terrain") as info:
        sim.set_state(q, robbit.initial_u)
    message = str(info.value)
    assert "contact 'disc/terrain0'" in message and "restore=True" in message
    # Lowered 1 cm from resting on the ground: 1 cm deep.
    assert depth_in(message) == pytest.approx(0.01, abs=1e-9)
    np.testing.assert_array_equal(sim.q, robbit.initial_q)
    sim.set_state(q, robbit.initial_u, restore=True)
    np.testing.assert_array_equal(sim.q, q)


def test_set_state_refuses_a_joint_past_its_stop():
    scene = hopsim.Scene.load(SCENES / "classic" / "pendulum-stop.toml")
    sim = hopsim.Simulation(scene)
    with pytest.raises(ValueError, match="joint of 'rod' starts at -0.25 rad") as info:
        sim.set_state([-0.25], [0.0])
    assert "below its lower stop at 0 rad" in str(info.value)
    assert depth_in(str(info.value)) == pytest.approx(0.25, rel=1e-12)
    sim.set_state([0.25], [0.0])


def test_set_state_refuses_two_balls_with_one_centre():
    path = SCENES / "classic" / "cradle-3.toml"
    scene = hopsim.Scene.load(path)
    radii = [float(r) for r in re.findall(r"^radius = ([0-9.]+)$", scene.text, re.M)]
    sim = hopsim.Simulation(scene)
    q = scene.initial_q
    q[3] = q[0]
    with pytest.raises(ValueError, match="overlap by") as info:
        sim.set_state(q, scene.initial_u)
    # One centre: each disc reaches through the other, by both radii.
    assert depth_in(str(info.value)) == pytest.approx(radii[0] + radii[1], rel=1e-9)


def test_a_state_the_run_reached_is_restored(robbit):
    sim = hopsim.Simulation(robbit)
    sim.step(100)
    t, q, u = sim.state
    sim.step(100)
    after = sim.q
    sim.set_state(q, u, t, restore=True)
    assert sim.t == t and sim.step_count == 0
    np.testing.assert_array_equal(sim.q, q)
    sim.step(100)
    np.testing.assert_array_equal(sim.q, after)


# --- panics ---------------------------------------------------------------------------


def test_a_panic_in_a_step_is_an_internal_error(robbit, monkeypatch):
    monkeypatch.setenv("HOPSIM_PANIC_AT_STEP", "7")
    sim = hopsim.Simulation(robbit)
    with pytest.raises(Exception) as info:
        sim.step(100)
    error = info.value
    assert isinstance(error, hopsim.InternalError) and isinstance(error, hopsim.HopsimError)
    assert (error.step, error.t) == (7, pytest.approx(6 * robbit.dt, abs=1e-15))
    assert "This is a bug in hopsim; please report it" in str(error)
    assert "HOPSIM_PANIC_AT_STEP=7" in error.message
    assert sim.step_count == 6, "the steps before the panic stand"
    with pytest.raises(hopsim.InternalError):
        sim.step()

    run = hopsim.Simulation(robbit)
    with pytest.raises(hopsim.InternalError) as info:
        run.run()
    frames = info.value.trajectory
    assert frames.summary is None and list(frames.steps[:2]) == [0, 5]
    assert frames.steps[-1] <= 6


def test_a_panic_in_a_sweep_run_is_a_failed_row(robbit, monkeypatch):
    monkeypatch.setenv("HOPSIM_PANIC_AT_STEP", "7")
    table = hopsim.sweep(short_robbit(robbit), {"controller.torque": [0.1, 0.2]})
    assert table["status"] == ["error", "error"]
    assert all("internal error in step 7" in e for e in table["error"])


requires_hooks = pytest.mark.skipif(
    not hopsim._hopsim._TEST_HOOKS and os.environ.get("HOPSIM_REQUIRE_PYTHON") != "1",
    reason="the wheel was built without the cargo feature test-hooks",
)


@requires_hooks
@pytest.mark.parametrize(
    "binding, call",
    [
        ("lcp.solve", lambda _: hopsim.lcp.solve(np.eye(3), -np.ones(3))),
        ("lcp.solve", lambda _: hopsim.lcp.solve(np.eye(100), -np.ones(100))),
        ("Scene.load", lambda _: hopsim.Scene.load(SCENES / "robbit.toml")),
        ("Simulation.run", lambda scene: hopsim.Simulation(scene).run()),
        ("sweep", lambda scene: hopsim.sweep(scene, {"controller.torque": [0.1]})),
    ],
)
def test_a_panic_in_a_binding_is_an_internal_error(robbit, monkeypatch, binding, call):
    scene = short_robbit(robbit)
    monkeypatch.setenv("HOPSIM_PANIC_IN", binding)
    with pytest.raises(hopsim.InternalError, match=f"internal error in {binding}: "):
        call(scene)
    monkeypatch.delenv("HOPSIM_PANIC_IN")
    call(scene)

"""The GIL is released while Rust runs: a Python thread makes progress meanwhile."""

import threading
import time

import hopsim


class Counter(threading.Thread):
    """Counts in Python until stopped."""

    def __init__(self):
        super().__init__(daemon=True)
        self.count = 0
        self.started = threading.Event()
        self.stop = False

    def run(self):
        self.started.set()
        while not self.stop:
            self.count += 1


def progress_during(work):
    """How far a Python thread counts while `work()` runs, and how long it runs."""
    counter = Counter()
    counter.start()
    counter.started.wait()
    before = counter.count
    started = time.perf_counter()
    work()
    elapsed = time.perf_counter() - started
    during = counter.count - before
    counter.stop = True
    counter.join()
    return during, elapsed


def counts_per_second():
    """How fast the counting thread runs on its own."""
    counted, elapsed = progress_during(lambda: time.sleep(0.2))
    return counted / elapsed


def assert_released(work):
    during, elapsed = progress_during(work)
    assert elapsed > 0.05, "the work is too short to tell"
    # With the GIL held the counter could not run at all while the work is in Rust; a
    # released GIL lets it run for a good share of the time (on one core, about half).
    assert during > 0.05 * counts_per_second() * elapsed, (during, elapsed)


# The work must last well over 0.05 s on a fast build: 60 s of Robbit (300 000 steps),
# 400 000 steps and four 60 s runs on two cores take 0.1–0.3 s each.


def test_run_releases_the_gil(robbit):
    assert_released(lambda: hopsim.Simulation(robbit).run(duration=60.0))


def test_many_steps_release_the_gil(robbit):
    assert_released(lambda: hopsim.Simulation(robbit).step(400_000))


def test_sweep_releases_the_gil(robbit):
    long = robbit.with_overrides({"simulation.duration": 60.0})
    torques = [0.14, 0.16, 0.18, 0.20]
    assert_released(lambda: hopsim.sweep(long, {"controller.torque": torques}))

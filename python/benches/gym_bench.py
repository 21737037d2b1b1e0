#!/usr/bin/env python3
"""Speed of hopsim's Gymnasium vector environment (hopsim.envs.HopsimVectorEnv).

For each thread count: ``num_envs`` copies of ``hopsim/Robbit-v0`` stepped by a numpy
linear policy (one matrix product and a clip per step), in environment steps per second,
against the batch alone (``Batch.step(frame_skip, controls=…)`` with the same controls):
the difference is Python's cost per vector step (actions in, brakes, observations,
rewards and flags out), measured also alone: the vector step with zero simulation steps
(``Batch.step(0)``). Best of ``--repeat`` runs of ``--steps`` vector steps each.

    python python/benches/gym_bench.py --num-envs 256 --threads 1 2
"""

import argparse
import time

import gymnasium
import numpy as np

import hopsim  # noqa: F401  (registers the environments)


def timed(f, repeat):
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - start)
    return best


def measure(env_id, num_envs, threads, steps, repeat, frame_skip):
    keys = {} if frame_skip is None else {"frame_skip": frame_skip}
    venv = gymnasium.make_vec(env_id, num_envs=num_envs, vectorization_mode="vector_entry_point",
                              threads=threads, **keys)
    low, high = venv.single_action_space.low, venv.single_action_space.high
    k = venv.single_observation_space.shape[0]
    w = np.random.default_rng(0).standard_normal((k, low.size)) * 0.1
    obs, _ = venv.reset(seed=0)

    def policy_steps():
        o = obs
        for _ in range(steps):
            o = venv.step(np.clip(o @ w, low, high))[0]

    env_time = timed(policy_steps, repeat)
    batch = venv.unwrapped.batch
    frame_skip = venv.unwrapped.config.frame_skip
    controls = np.clip(obs @ w, low, high)[:, : batch.controls.shape[1]].copy()

    def batch_steps():
        for _ in range(steps):
            batch.step(frame_skip, controls=controls)

    batch_time = timed(batch_steps, repeat)
    config = venv.unwrapped.config
    config.frame_skip = 0  # the vector step without simulation: Python's and the binding's cost
    python_time = timed(policy_steps, repeat)
    config.frame_skip = frame_skip
    return {
        "threads": threads,
        "env_steps_per_s": num_envs * steps / env_time,
        "us_per_vector_step": 1e6 * env_time / steps,
        "us_batch_alone": 1e6 * batch_time / steps,
        "us_python": 1e6 * (env_time - batch_time) / steps,
        "us_python_alone": 1e6 * python_time / steps,
        "frame_skip": frame_skip,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--env", default="hopsim/Robbit-v0")
    parser.add_argument("--num-envs", type=int, nargs="+", default=[256])
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--frame-skip", type=int, nargs="+", default=[None],
                        help="simulation steps per environment step (default: the env's)")
    args = parser.parse_args()
    print(f"{args.env}, best of {args.repeat} x {args.steps} vector steps")
    print("frame_skip copies threads  env steps/s  µs/vector step  µs batch alone"
          "  µs difference  µs Python alone")
    for frame_skip in args.frame_skip:
        for n in args.num_envs:
            for threads in args.threads:
                r = measure(args.env, n, threads, args.steps, args.repeat, frame_skip)
                print(f"{r['frame_skip']:10d} {n:6d} {threads:7d} {r['env_steps_per_s']:12.0f}"
                      f" {r['us_per_vector_step']:15.1f} {r['us_batch_alone']:14.1f}"
                      f" {r['us_python']:14.1f} {r['us_python_alone']:16.1f}")


if __name__ == "__main__":
    main()

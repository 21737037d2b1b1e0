"""Gymnasium environments (hopsim.envs): Gymnasium's checker on every registered id,
reproducible seeding, Hopper-v5's observation, reward and termination against the
definitions written out here (and against gymnasium's own Hopper-v5 when MuJoCo is
installed), the vector environment against single environments, and a short random
search that makes Robbit faster."""

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
import hopsim  # noqa: E402  (registers the environments)
from gymnasium.utils.env_checker import check_env  # noqa: E402

IDS = ["hopsim/Robbit-v0", "hopsim/CaneBot-v0", "hopsim/Hopper-v0"]


@pytest.mark.parametrize("env_id", IDS)
def test_gymnasium_check_env_passes(env_id):
    env = gymnasium.make(env_id)
    check_env(env.unwrapped, skip_render_check=True)
    assert env.spec.vector_entry_point is not None


def rollout(env, seed, steps, action_seed):
    """Observations, rewards and flags of ``steps`` random actions after ``reset(seed)``."""
    obs, _ = env.reset(seed=seed)
    env.action_space.seed(action_seed)
    out = [obs]
    for _ in range(steps):
        obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
        out.append(np.concatenate((obs, [reward, terminated, truncated])))
        if terminated or truncated:
            break
    return np.concatenate(out)


@pytest.mark.parametrize("env_id", IDS)
def test_the_same_seed_gives_the_same_trajectory(env_id):
    env = gymnasium.make(env_id)
    a = rollout(env, 3, 40, 11)
    b = rollout(gymnasium.make(env_id), 3, 40, 11)
    c = rollout(env, 4, 40, 11)
    assert a.tobytes() == b.tobytes()
    assert a.shape != c.shape or not np.array_equal(a, c)
    # The noise moves the start: two seeds start apart, by less than the noise's scale.
    first, _ = env.reset(seed=3)
    second, _ = env.reset(seed=4)
    assert 0 < np.abs(first - second).max() < 0.03


# Hopper-v5 (gymnasium/envs/mujoco/hopper_v5.py), written out from its documentation:
# observation qpos[1:] + clip(qvel, ±10); reward = ẋ + 1·healthy − 1e-3 Σ a²;
# healthy: 0.7 < z, |angle| < 0.2, |(qpos, qvel)[2:]| < 100; dt = 4 × 0.002 s.
def v5_observation(q, u):
    return np.concatenate([q[1:], np.clip(u, -10, 10)])


def v5_healthy(q, u):
    state = np.concatenate([q, u])[2:]
    return bool(q[1] > 0.7 and -0.2 < q[2] < 0.2 and np.all(np.abs(state) < 100))


def hopper_steps(seed, steps):
    """(q before, q, u, action, obs, reward, terminated, info) of random actions."""
    env = gymnasium.make("hopsim/Hopper-v0").unwrapped
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    assert env.dt == pytest.approx(0.008, rel=1e-15)
    assert env.observation_space.shape == (11,)
    assert np.array_equal(env.action_space.low, [-1, -1, -1])
    assert np.array_equal(obs, v5_observation(env.q, env.u))
    out = []
    for _ in range(steps):
        q0 = env.q
        action = rng.uniform(-1, 1, 3)
        obs, reward, terminated, truncated, info = env.step(action)
        out.append((q0, env.q, env.u, action, obs, reward, terminated, info))
        if terminated:
            break
    return out


def test_hopper_observation_reward_and_termination_are_v5s():
    ended = 0
    for seed in range(3):
        steps = hopper_steps(seed, 300)
        for q0, q, u, action, obs, reward, terminated, info in steps:
            assert np.array_equal(obs, v5_observation(q, u))
            healthy = v5_healthy(q, u)
            expected = (q[0] - q0[0]) / 0.008 + healthy - 1e-3 * np.sum(action**2)
            assert reward == pytest.approx(expected, rel=1e-12, abs=1e-12)
            assert terminated == (not healthy)
            assert info["x_velocity"] == pytest.approx((q[0] - q0[0]) / 0.008, rel=1e-12)
        ended += steps[-1][6]
    # Random torques topple the hopper: the unhealthy branch was taken.
    assert ended >= 1


def test_hopper_definitions_equal_gymnasiums_hopper_v5_on_the_same_states():
    """MuJoCo's Hopper-v5 only as an oracle of the definitions, on hopsim's states."""
    pytest.importorskip("mujoco")
    pytest.importorskip("imageio")  # gymnasium's MuJoCo environments import their renderer
    oracle = gymnasium.make("Hopper-v5").unwrapped
    oracle.reset(seed=0)
    for q0, q, u, action, obs, reward, terminated, _ in hopper_steps(1, 300):
        oracle.set_state(q, u)
        assert np.array_equal(oracle._get_obs(), obs)
        assert oracle.is_healthy == (not terminated)
        x_velocity = (q[0] - q0[0]) / oracle.dt
        expected, _ = oracle._get_rew(x_velocity, action)
        assert reward == pytest.approx(expected, rel=1e-12, abs=1e-12)
    assert oracle.dt == pytest.approx(0.008)


@pytest.mark.parametrize("env_id,steps", [("hopsim/Hopper-v0", 25), ("hopsim/Robbit-v0", 30)])
def test_the_vector_env_equals_single_envs(env_id, steps):
    n, seed = 4, 5
    venv = gymnasium.make_vec(
        env_id, num_envs=n, vectorization_mode="vector_entry_point", max_episode_steps=steps,
        threads=2,
    )
    assert isinstance(venv, hopsim.envs.HopsimVectorEnv)
    singles = [gymnasium.make(env_id, max_episode_steps=steps) for _ in range(n)]
    obs, _ = venv.reset(seed=seed)
    single_obs = [env.reset(seed=seed + i)[0] for i, env in enumerate(singles)]
    assert np.array_equal(obs, np.stack(single_obs))
    rng = np.random.default_rng(0)
    ended = [False] * n
    resets = 0
    for _ in range(3 * steps):
        space = venv.single_action_space
        actions = rng.uniform(space.low, space.high, (n, space.shape[0]))
        obs, reward, terminated, truncated, _ = venv.step(actions)
        for i, env in enumerate(singles):
            if ended[i]:  # Gymnasium's NEXT_STEP autoreset
                expected = (env.reset()[0], 0.0, False, False)
                resets += 1
            else:
                expected = env.step(actions[i])[:4]
            assert np.array_equal(obs[i], expected[0]), i
            assert (reward[i], terminated[i], truncated[i]) == expected[1:], i
            ended[i] = bool(expected[2] or expected[3])
    assert resets >= n


def test_vector_env_same_step_autoreset_and_reset_mask():
    venv = hopsim.envs.HopsimVectorEnv(
        3, hopsim.envs.hopper_config(), max_episode_steps=5, autoreset_mode="SameStep"
    )
    obs, _ = venv.reset(seed=1)
    for k in range(5):
        final, _, _, truncated, infos = venv.step(np.zeros((3, 3)))
    assert truncated.all() and infos["_final_obs"].all()
    assert not np.array_equal(infos["final_obs"], final)
    again, _ = venv.reset(seed=1)
    assert np.array_equal(again, obs)  # the reset observation, as at the first reset
    venv.step(np.zeros((3, 3)))
    moved = venv.reset(seed=[None, 2, None], options={"reset_mask": np.array([False, True, False])})[0]
    assert np.array_equal(moved[1], obs[1]) and not np.array_equal(moved[0], obs[0])


def test_a_user_task_and_a_scene_of_ones_own():
    scene = (
        hopsim.Model("wheel")
        .simulation(duration=1.0, dt=1e-3)
        .environment(terrain="none")
        .body("wheel", base="pinned", pivot=[0.0, 1.0], com=[0.0, 0.0], mass=1.0, inertia=0.1)
        .actuator("axle", joint="wheel", kind="motor", ctrl_range=[-2.0, 2.0])
        .initial(q=[0.0], u=[0.0])
        .scene()
    )
    task = hopsim.envs.StateTask(
        reward=lambda v: -np.abs(v.q[:, 0]), terminated=lambda v: np.abs(v.q[:, 0]) > 1.0
    )
    env = hopsim.envs.HopsimEnv(scene, task=task, frame_skip=10)
    check_env(env, skip_render_check=True)
    env.reset(seed=0)
    # A constant torque τ on inertia I turns a wheel pinned at its centre of mass by
    # τ t²/(2I) = 10 t² rad (the midpoint step is exact for a constant acceleration).
    for k in range(100):
        obs, reward, terminated, _, _ = env.step(np.array([2.0]))
        if terminated:
            break
    t = (k + 1) * 0.01
    assert env.q[0] == pytest.approx(2.0 * t**2 / (2 * 0.1), rel=1e-12)
    assert terminated and reward == -abs(env.q[0])
    assert k + 1 == 32  # 10 t² > 1 from t = 0.32 s on


def test_random_search_makes_robbit_faster():
    """Basic random search (Mania et al. 2018) over a linear policy on the vector env:
    a fixed seed, 8 iterations of 8 directions, 0.4 s episodes."""
    directions, steps, iterations = 8, 400, 8
    venv = gymnasium.make_vec(
        "hopsim/Robbit-v0", num_envs=2 * directions, vectorization_mode="vector_entry_point",
        threads=2,
    )
    low, high = venv.single_action_space.low, venv.single_action_space.high
    k, m = venv.single_observation_space.shape[0], low.size
    rng = np.random.default_rng(0)

    def returns(weights):  # weights: (copies, m, k + 1)
        obs, _ = venv.reset(seed=0)
        total = np.zeros(len(weights))
        for _ in range(steps):
            features = np.concatenate([obs, np.ones((len(obs), 1))], axis=1)
            action = np.clip(np.einsum("cmk,ck->cm", weights, features), low, high)
            obs, reward, _, _, _ = venv.step(action)
            total += reward
        return total / steps  # mean forward speed, m/s

    theta = np.zeros((m, k + 1))
    history = []
    for _ in range(iterations):
        delta = rng.standard_normal((directions, m, k + 1)) * 0.3
        r = returns(np.concatenate([theta + delta, theta - delta]))
        history.append(r.mean())
        step = ((r[:directions] - r[directions:])[:, None, None] * delta).sum(0)
        theta = theta + 0.5 * step / (directions * (r.std() + 1e-9))
    final = returns(np.repeat(theta[None], 2 * directions, axis=0))[0]
    assert final > history[0] + 0.05 and final > 0.05, (history, final)

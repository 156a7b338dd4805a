"""xcut.envs.IncisionEnv against the Gymnasium API contract (written out here: gymnasium is not one
of Debian 12's packages, and the env must work without it)."""
import numpy as np
import pytest

from xcut.envs import IncisionEnv


def check_space(space):
    assert isinstance(space.shape, tuple) and space.dtype == np.float64
    assert space.low.shape == space.shape and space.high.shape == space.shape
    x = space.sample()
    assert x.shape == space.shape and x.dtype == space.dtype and space.contains(x)


def check_step_result(env, result):
    assert isinstance(result, tuple) and len(result) == 5
    obs, reward, terminated, truncated, info = result
    assert obs.shape == env.observation_space.shape and obs.dtype == env.observation_space.dtype
    assert env.observation_space.contains(obs) and np.all(np.isfinite(obs))
    assert isinstance(reward, float) and np.isfinite(reward)
    assert isinstance(terminated, bool) and isinstance(truncated, bool)
    assert isinstance(info, dict)
    return result


def test_the_api_contract():
    env = IncisionEnv(max_steps=8)
    check_space(env.action_space)
    check_space(env.observation_space)
    assert env.action_space.shape == (3,) and env.observation_space.shape == (12,)
    with pytest.raises(RuntimeError):
        env.step(np.zeros(3))  # before reset
    reset = env.reset(seed=3)
    assert isinstance(reset, tuple) and len(reset) == 2
    obs, info = reset
    assert obs.shape == (12,) and isinstance(info, dict) and env.observation_space.contains(obs)
    np.testing.assert_allclose(obs[:3], 0.0, atol=1e-12)  # the scalpel starts at the line's start
    assert obs[7] == pytest.approx(0.0, abs=1e-12)
    steps = 0
    while True:  # standing still: never terminated, truncated at max_steps
        obs, reward, terminated, truncated, info = check_step_result(env, env.step(np.zeros(3)))
        steps += 1
        assert not terminated
        if truncated:
            break
    assert steps == 8
    env.close()


def test_same_seed_same_episode_and_cutting_along_the_line_pays():
    def episode(seed):
        env = IncisionEnv(max_steps=120)
        obs, info = env.reset(seed=seed)
        along = np.append(info["line_direction"][:2], 0.0) * 0.03  # 30 mm/s along the target line
        rewards, done = [], False
        while not done:
            obs, reward, terminated, truncated, info = check_step_result(env, env.step(along))
            rewards.append(reward)
            done = terminated or truncated
        return obs, rewards, terminated, info

    a, b = episode(5), episode(5)
    assert np.array_equal(a[0], b[0]) and a[1] == b[1]  # bit for bit
    obs, rewards, terminated, info = a
    assert terminated and info["progress"] >= 1.0  # reached the end of the line
    assert info["elements_split"] > 5  # it cut on its way
    assert sum(rewards) > 90.0  # ~100 for the line, +1 at the end, small time and lateral costs
    c = episode(6)
    assert not np.array_equal(c[0], a[0])  # another seed, another line


def test_leaving_the_line_ends_the_episode_with_a_penalty():
    env = IncisionEnv(max_steps=200)
    obs, info = env.reset(seed=1)
    across = np.append(info["line_direction"][:2], 0.0)
    across = np.array([-across[1], across[0], 0.0]) * 0.05
    for _ in range(200):
        obs, reward, terminated, truncated, info = env.step(across)
        if terminated or truncated:
            break
    assert terminated and abs(info["lateral_m"]) > 0.005 and reward < -0.5


def test_actions_are_clipped_and_depth_is_bounded():
    env = IncisionEnv(max_steps=5)
    env.reset(seed=0)
    obs, *_ = env.step(np.array([0.0, 0.0, 10.0]))  # far above max_speed
    assert obs[9] == pytest.approx(0.05 * env.sim.dt)
    for _ in range(3):
        obs, *_ = env.step(np.array([0.0, 0.0, 0.05]))
    assert obs[9] <= 0.004 + 1e-12
    with pytest.raises(ValueError):
        IncisionEnv(max_speed=0.0)

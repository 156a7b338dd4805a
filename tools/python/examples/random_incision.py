"""A random policy (with a push along the line) on xcut.envs.IncisionEnv: the README's example.

    PYTHONPATH=build/python python3 tools/python/examples/random_incision.py --episodes 2
"""
import argparse

import numpy as np

from xcut.envs import IncisionEnv


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--episodes", type=int, default=2)
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    env = IncisionEnv()
    for episode in range(a.episodes):
        obs, info = env.reset(seed=a.seed + episode)
        total, steps, done = 0.0, 0, False
        while not done:
            # Random, plus half the top speed along the target line so an episode gets somewhere.
            action = env.action_space.sample() + 0.5 * env.max_speed * np.append(info["line_direction"][:2], 0.0)
            obs, reward, terminated, truncated, step_info = env.step(action)
            total, steps, done = total + reward, steps + 1, terminated or truncated
        print(f"episode {episode}: {steps} steps, return {total:.3f}, progress {obs[7]:.2f}, "
              f"lateral {obs[8] * 1e3:.2f} mm, {int(obs[10])} elements split, "
              f"{'terminated' if terminated else 'truncated'}")
    env.close()


if __name__ == "__main__":
    main()

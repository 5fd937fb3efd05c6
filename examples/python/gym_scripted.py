"""A Gymnasium loop with a scripted policy on carfollow/Follow-v0.

    pip install "./sim/python[gym]"
    python examples/python/gym_scripted.py [--scenario NAME] [--episodes N]

The policy reads the estimate observation (see carfollow.env) and commands only the
longitudinal (``action="longitudinal"``: the built-in controller steers): a proportional
law on the range's error from 10 m, and a gentle brake with no estimate. It prints each
episode's return, length and how it ended.
"""

from __future__ import annotations

import argparse
import sys

import gymnasium as gym
import numpy as np

import carfollow  # noqa: F401  (registers carfollow/Follow-v0)


def policy(obs: np.ndarray) -> np.ndarray:
    rng, status, speed = obs[0], obs[3], obs[4]
    if status <= 0.0:  # lost, or nothing yet
        return np.array([-0.2 if speed > 0.5 else 0.0], dtype=np.float32)
    return np.array([np.clip(0.15 * (rng - 10.0), -1.0, 1.0)], dtype=np.float32)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="nist-grounds")
    ap.add_argument("--episodes", type=int, default=2)
    ap.add_argument("--duration", type=float, default=30.0)
    args = ap.parse_args()
    env = gym.make(
        "carfollow/Follow-v0",
        scenario=args.scenario,
        observation="estimate",
        action="longitudinal",
        overrides={"duration_s": args.duration},
    )
    for episode in range(args.episodes):
        obs, info = env.reset(seed=episode)
        total, steps, done = 0.0, 0, False
        while not done:
            obs, reward, terminated, truncated, info = env.step(policy(obs))
            total, steps = total + reward, steps + 1
            done = terminated or truncated
        how = "terminated" if terminated else "truncated (the scenario's end)"
        print(f"episode {episode}: return {total:.1f} over {steps} steps, {how}; "
              f"gap at the end {info['truth']['range_m']:.1f} m")
    env.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Steps per second: carfollow's Gymnasium environment against highway-env, in one process.

    pip install "./sim/python[gym]" highway-env
    python examples/python/bench.py [--rounds 3] [--seconds 10]

Each round times, one after another (alternating, so that a slow moment of the machine
falls on all of them alike), with ``gymnasium.utils.performance.benchmark_step`` and
random actions:

- highway-env's ``highway-v0`` with a 256×242 grey observation at ``policy_frequency`` 15
  (one step, one frame at 15 Hz, as carfollow's);
- ``carfollow/Follow-v0`` with ``observation="camera"`` and with ``observation="estimate"``;
- the native loop: ``carfollow.Simulation(...).run()`` (the built-in tracker and controller,
  what ``carfollow run`` does), in frames per second; and the native loop doing what each
  environment's loop does (one renderer, the frame whole for camera observations, only the
  part the tracker reads for estimate observations), so that what Python itself costs
  shows apart from what the observation costs;
- a reset of each environment, in milliseconds (median of five).

It prints each round and the medians, and the ratios the README quotes.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")

import gymnasium as gym  # noqa: E402
from gymnasium.utils.performance import benchmark_step  # noqa: E402

import carfollow  # noqa: E402

SCENARIO = "nist-grounds"


def highway() -> gym.Env:
    import highway_env  # noqa: F401  (registers highway-v0)

    return gym.make(
        "highway-v0",
        config={
            "observation": {
                "type": "GrayscaleObservation",
                "observation_shape": (256, 242),
                "stack_size": 1,
                "weights": [0.2989, 0.5870, 0.1140],
            },
            "policy_frequency": 15,
            "simulation_frequency": 15,
        },
    )


def follow(observation: str) -> gym.Env:
    return gym.make("carfollow/Follow-v0", scenario=SCENARIO, observation=observation)


def native(**kwargs) -> float:
    """Frames per second of the native loop: the scenario's first 60 s, run to the end."""
    sim = carfollow.Simulation(SCENARIO, overrides={"duration_s": 60.0}, **kwargs)
    started = time.perf_counter()
    summary = sim.run()
    return summary["frames"] / (time.perf_counter() - started)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--seconds", type=float, default=10.0)
    args = ap.parse_args()
    envs = {
        "highway-v0 (grey 256×242)": highway(),
        "Follow-v0 camera": follow("camera"),
        "Follow-v0 estimate": follow("estimate"),
    }
    for env in envs.values():
        env.reset(seed=0)
    natives = {
        "native loop": {},
        "native, as the camera env": {"renderers": 1, "whole_frames": True},
        "native, as the estimate env": {"renderers": 1, "whole_frames": False},
    }
    results: dict[str, list[float]] = {name: [] for name in [*envs, *natives]}
    for r in range(args.rounds):
        for name, env in envs.items():
            sps = benchmark_step(env, target_duration=args.seconds, seed=r)
            results[name].append(sps)
        for name, kwargs in natives.items():
            results[name].append(native(**kwargs))
        print(f"round {r + 1}: " + ", ".join(f"{n} {v[-1]:.0f}/s" for n, v in results.items()),
              flush=True)
    med = {name: statistics.median(v) for name, v in results.items()}
    print("\nmedians (steps or frames per second):")
    for name, v in med.items():
        print(f"  {name:28s} {v:8.1f}")
    hw = med["highway-v0 (grey 256×242)"]
    print(f"\ncamera observations:   {med['Follow-v0 camera'] / hw:.2f}× highway-env")
    print(f"estimate observations: {med['Follow-v0 estimate'] / hw:.2f}× highway-env")
    print(f"Python's cost, estimate env against the native loop: "
          f"{1 - med['Follow-v0 estimate'] / med['native loop']:.0%}"
          f" (against the native loop doing its work: "
          f"{1 - med['Follow-v0 estimate'] / med['native, as the estimate env']:.0%})")
    print(f"Python's cost, camera env against the native loop: "
          f"{1 - med['Follow-v0 camera'] / med['native loop']:.0%}"
          f" (against the native loop doing its work: "
          f"{1 - med['Follow-v0 camera'] / med['native, as the camera env']:.0%})")
    for name, env in envs.items():
        if name.startswith("Follow"):
            times = []
            for k in range(5):
                started = time.perf_counter()
                env.reset(seed=100 + k)
                times.append(time.perf_counter() - started)
            print(f"reset, {name}: {1e3 * statistics.median(times):.0f} ms")
    for env in envs.values():
        env.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())

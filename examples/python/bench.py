"""Steps per second: carfollow's Gymnasium environment against highway-env, in one process.

    pip install "./sim/python[gym]" highway-env
    python examples/python/bench.py [--rounds 3] [--seconds 10]

Each round times, one after another (alternating, so that a slow moment of the machine
falls on all of them alike), with ``gymnasium.utils.performance.benchmark_step`` and
random actions:

- highway-env's ``highway-v0`` with a 256×242 grey observation at ``policy_frequency`` 15
  (one step, one frame at 15 Hz, as carfollow's);
- ``carfollow/Follow-v0`` with ``observation="camera"`` and with ``observation="estimate"``;
- what Python costs, on equal work: each environment driven along the lead's path by a
  following policy (``action="longitudinal"``, the built-in steering, a proportional law on
  the tracker's range), against the native loop doing the same work. Random actions drive
  the chase off the road, where the camera sees other things at another cost, so they
  cannot measure Python's share. The native loop: ``carfollow.Simulation(...).run()``
  (what ``carfollow run`` does: two renderers, only the part of each frame the tracker
  reads), in frames per second; as the estimate environment runs it (one renderer, parts);
  and as the camera environment runs it (one renderer, whole frames, stepped with
  ``Simulation.step()``, since ``run()`` renders only what the tracker reads);
- a reset of each environment, in milliseconds (median of five).

It prints each round and the medians, and the ratios the book quotes
(docs/src/results/python-speed.md).
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


def native_whole() -> float:
    """Frames per second of the native loop rendering every frame whole, as the camera
    environment must: one renderer, stepped frame by frame (``run()`` would render only the
    part the tracker reads)."""
    sim = carfollow.Simulation(SCENARIO, overrides={"duration_s": 60.0}, renderers=1)
    frames = 0
    started = time.perf_counter()
    while sim.step():
        frames += 1
    return frames / (time.perf_counter() - started)


def following(observation: str) -> float:
    """Steps per second of an environment driven along the lead's path: the built-in
    steering, and a proportional law on the tracker's range from 10 m (a gentle brake
    without one), over the scenario's first 60 s."""
    env = gym.make(
        "carfollow/Follow-v0",
        scenario=SCENARIO,
        observation=observation,
        action="longitudinal",
        overrides={"duration_s": 60.0},
    )
    _, info = env.reset(seed=0)
    steps = 0
    started = time.perf_counter()
    while True:
        record = info["record"]
        if record["status"] == "tracking":
            a = min(max(0.15 * (record["est_range_m"] - 10.0), -1.0), 1.0)
        else:
            a = -0.2
        _, _, terminated, truncated, info = env.step([a])
        steps += 1
        if terminated or truncated:
            break
    rate = steps / (time.perf_counter() - started)
    env.close()
    return rate


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
        "native loop": lambda: native(),
        "native, as the camera env": native_whole,
        "native, as the estimate env": lambda: native(renderers=1, whole_frames=False),
        "Follow-v0 camera, following": lambda: following("camera"),
        "Follow-v0 estimate, following": lambda: following("estimate"),
    }
    results: dict[str, list[float]] = {name: [] for name in [*envs, *natives]}
    for r in range(args.rounds):
        for name, env in envs.items():
            sps = benchmark_step(env, target_duration=args.seconds, seed=r)
            results[name].append(sps)
        for name, measure in natives.items():
            results[name].append(measure())
        print(f"round {r + 1}: " + ", ".join(f"{n} {v[-1]:.0f}/s" for n, v in results.items()),
              flush=True)
    med = {name: statistics.median(v) for name, v in results.items()}
    print("\nmedians (steps or frames per second):")
    for name, v in med.items():
        print(f"  {name:30s} {v:8.1f}")
    hw = med["highway-v0 (grey 256×242)"]
    print(f"\ncamera observations:   {med['Follow-v0 camera'] / hw:.2f}× highway-env")
    print(f"estimate observations: {med['Follow-v0 estimate'] / hw:.2f}× highway-env")
    for kind in ("estimate", "camera"):
        env_rate = med[f"Follow-v0 {kind}, following"]
        print(f"Python's cost, {kind} env following the lead: "
              f"{1 - env_rate / med['native loop']:.0%} against the native loop, "
              f"{1 - env_rate / med[f'native, as the {kind} env']:.0%} against the native "
              f"loop doing its work")
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

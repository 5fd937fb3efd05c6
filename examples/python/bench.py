"""Steps per second: carfollow's Gymnasium environment against highway-env, in one process.

    pip install "./sim/python[gym]" highway-env
    python examples/python/bench.py [--rounds 3] [--seconds 10]

Each round times, one after another (alternating, so that a slow moment of the machine
falls on all of them alike), with ``gymnasium.utils.performance.benchmark_step`` and
random actions:

- highway-env's ``highway-v0`` with a 256×242 grey observation at ``policy_frequency`` 15
  (one step, one frame at 15 Hz, as carfollow's), with its default traffic (50 vehicles)
  and with light traffic (``vehicles_count`` 10);
- ``carfollow/Follow-v0`` with ``observation="camera"`` and with ``observation="estimate"``;
- the vector ``carfollow/Follow-v0`` (``gymnasium.make_vec``, ``num_envs`` 8, one process),
  with each observation, in steps per second summed over its sub-environments;
- MetaDrive's camera observation, where ``metadrive-simulator`` is installed (``--metadrive``);
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

It prints each round and the medians, the ratios the book quotes
(docs/src/results/python-speed.md), each rate per core, and the memory (resident set) of
the vector environment with camera observations in a process of its own.
``--no-native`` leaves out the native loop and the following runs.
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


# Sub-environments of the vector environment.
NUM_ENVS = 8


def highway(**config) -> gym.Env:
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
            **config,
        },
    )


def metadrive() -> gym.Env:
    """MetaDrive's camera observation, 256×242 grey-sized, headless, at 15 Hz."""
    from metadrive.component.sensors.rgb_camera import RGBCamera
    from metadrive.envs import MetaDriveEnv

    return MetaDriveEnv(
        {
            "use_render": False,
            "image_observation": True,
            "norm_pixel": False,
            "stack_size": 1,
            "sensors": {"rgb_camera": (RGBCamera, 256, 242)},
            "vehicle_config": {"image_source": "rgb_camera"},
            "decision_repeat": 4,
            "log_level": 50,
        }
    )


def vector(observation: str) -> gym.vector.VectorEnv:
    return gym.make_vec(
        "carfollow/Follow-v0",
        num_envs=NUM_ENVS,
        vectorization_mode="vector_entry_point",
        scenario=SCENARIO,
        observation=observation,
    )


def vector_rate(envs: gym.vector.VectorEnv, seconds: float, seed: int) -> float:
    """Steps per second summed over the sub-environments, with random actions."""
    envs.action_space.seed(seed)
    steps = 0
    started = time.perf_counter()
    while time.perf_counter() - started < seconds:
        envs.step(envs.action_space.sample())
        steps += 1
    return steps * envs.num_envs / (time.perf_counter() - started)


def rss_mib() -> float:
    """This process's resident set, MiB."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    return float("nan")


def vector_memory() -> None:
    """Prints the resident set of a process holding the vector camera environment after
    300 steps, and before it (after the imports)."""
    before = rss_mib()
    envs = vector("camera")
    envs.reset(seed=0)
    for _ in range(300):
        envs.step(envs.action_space.sample())
    print(f"{before:.0f} {rss_mib():.0f}")
    envs.close()


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
    ap.add_argument("--no-native", action="store_true")
    ap.add_argument("--metadrive", action="store_true")
    ap.add_argument("--memory", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.memory:
        vector_memory()
        return 0
    envs = {
        "highway-v0 (grey 256×242)": highway(),
        "highway-v0, light traffic": highway(vehicles_count=10),
        "Follow-v0 camera": follow("camera"),
        "Follow-v0 estimate": follow("estimate"),
    }
    if args.metadrive:
        envs["MetaDrive camera"] = metadrive()
    for env in envs.values():
        env.reset(seed=0)
    vectors = {
        f"Follow-v0 camera, vector N={NUM_ENVS}": vector("camera"),
        f"Follow-v0 estimate, vector N={NUM_ENVS}": vector("estimate"),
    }
    for v in vectors.values():
        v.reset(seed=0)
    natives = {
        "native loop": lambda: native(),
        "native, as the camera env": native_whole,
        "native, as the estimate env": lambda: native(renderers=1, whole_frames=False),
        "Follow-v0 camera, following": lambda: following("camera"),
        "Follow-v0 estimate, following": lambda: following("estimate"),
    }
    if args.no_native:
        natives = {}
    results: dict[str, list[float]] = {name: [] for name in [*envs, *vectors, *natives]}
    for r in range(args.rounds):
        for name, env in envs.items():
            sps = benchmark_step(env, target_duration=args.seconds, seed=r)
            results[name].append(sps)
        for name, v in vectors.items():
            results[name].append(vector_rate(v, args.seconds, seed=r))
        for name, measure in natives.items():
            results[name].append(measure())
        print(f"round {r + 1}: " + ", ".join(f"{n} {v[-1]:.0f}/s" for n, v in results.items()),
              flush=True)
    med = {name: statistics.median(v) for name, v in results.items()}
    cores = len(os.sched_getaffinity(0))
    print(f"\nmedians (steps or frames per second; per core, of {cores}):")
    for name, v in med.items():
        print(f"  {name:36s} {v:8.1f} {v / cores:8.1f}")
    hw = med["highway-v0 (grey 256×242)"]
    light = med["highway-v0, light traffic"]
    print(f"\ncamera observations:   {med['Follow-v0 camera'] / hw:.2f}× highway-env, "
          f"{med['Follow-v0 camera'] / light:.2f}× light highway-env")
    print(f"estimate observations: {med['Follow-v0 estimate'] / hw:.2f}× highway-env, "
          f"{med['Follow-v0 estimate'] / light:.2f}× light highway-env")
    for kind in ("camera", "estimate"):
        v = med[f"Follow-v0 {kind}, vector N={NUM_ENVS}"]
        print(f"vector N={NUM_ENVS}, {kind}: {v / light:.2f}× light highway-env, "
              f"{v / med[f'Follow-v0 {kind}']:.2f}× the single Follow-v0 {kind}")
    for v in vectors.values():
        v.close()
    import subprocess

    memory = subprocess.run(
        [sys.executable, __file__, "--memory"], capture_output=True, text=True, check=True
    ).stdout.split()
    print(f"memory, vector N={NUM_ENVS} camera after 300 steps: {memory[1]} MiB resident "
          f"({memory[0]} MiB after the imports)")
    for kind in ("estimate", "camera") if natives else ():
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

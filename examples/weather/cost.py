#!/usr/bin/env python3
"""What the weather costs the loop: `nist-grounds` in clear air by day against the same road
in fog, in rain and at night, in alternating rounds.

Each round runs every condition once, in an order turned by one each round (so that no
condition always follows another), with `carfollow run --quiet`, and reads the run's
`summary.json`: the loop's time (`timing.step_s`, rendering, tracking and physics, without
set-up and outputs), its real-time factor and its CPU time. The report gives, per
condition, the median and range of the first two over the rounds, and the ratios of the
condition's loop time and CPU time to clear air's in the same round (their medians and
ranges): the figures the weather's cost is judged by (fog at most 1.05, rain and night at
most 1.25).

Usage: python3 examples/weather/cost.py [--carfollow BIN] [--rounds N] [--out DIR]
       [--report FILE]

Only the standard library.
"""

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys

# The conditions: a name, the scenario file, and its `--set` overrides. Fog and night are
# the library's scenarios (each `nist-grounds` with one thing changed: the fog, or the sun
# below the horizon with low beams, the lead's tail lamps and the gain's reach); rain is
# `nist-grounds` with the rain scenario's rate, then with its spray and mirrored lamps on.
# Two more split night's cost: clear air by day with night's camera (the automatic gain,
# whose metering window is rendered whole every frame), then with the low beams on too.
# High beams go with highlight protection: without it the board clips white and the run is
# mostly a search for it (whole frames), which measures the loss, not the light.
CONDITIONS = [
    ("clear", "scenarios/nist-grounds.toml", []),
    ("fog 60 m", "scenarios/fog.toml", []),
    ("rain 16 mm/h", "scenarios/nist-grounds.toml", ["environment.rain.rate_mm_h=16"]),
    (
        "rain 16 mm/h, spray and mirrored lamps",
        "scenarios/nist-grounds.toml",
        [
            "environment.rain.rate_mm_h=16",
            "environment.rain.spray=true",
            "environment.rain.lamp_reflections=true",
        ],
    ),
    (
        "clear, night's camera (automatic gain)",
        "scenarios/nist-grounds.toml",
        ["environment.sensor.auto_gain.max_gain=64"],
    ),
    (
        "clear, night's camera and low beams",
        "scenarios/nist-grounds.toml",
        ["environment.sensor.auto_gain.max_gain=64", "chase.headlamps.beam=low"],
    ),
    ("night, low beams", "scenarios/night.toml", []),
    (
        "night, high beams, highlight protection",
        "scenarios/night.toml",
        [
            "chase.headlamps.beam=high",
            "environment.sensor.auto_gain.max_clipped_share=0.01",
        ],
    ),
]


def cpu_s():
    """The CPU time (user and system) of this process's children so far, in s."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run(carfollow, scenario, sets, out):
    """Runs one condition into `out`; returns (loop time in s, real-time factor, the
    run's CPU time in s)."""
    cmd = [carfollow, "run", scenario, "--quiet", "--out", out]
    for s in sets:
        cmd += ["--set", s]
    before = cpu_s()
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    cpu = cpu_s() - before
    # Exit 1 is a criterion failed: the run completed and its timing stands.
    if done.returncode not in (0, 1):
        sys.exit(f"error: {' '.join(cmd)} exited {done.returncode}: {done.stderr.strip()}")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    return summary["timing"]["step_s"], summary["realtime_factor"], cpu


def spread(values, fmt):
    """'median (min–max)' of `values`, each as `fmt` formats it."""
    return f"{fmt(statistics.median(values))} ({fmt(min(values))}–{fmt(max(values))})"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--carfollow", default=os.environ.get("CARFOLLOW", "carfollow"))
    parser.add_argument("--rounds", type=int, default=8)
    parser.add_argument("--out", default="renders/weather-cost")
    parser.add_argument("--report", default="examples/weather/cost.md")
    args = parser.parse_args()
    if args.rounds < 1:
        sys.exit("error: --rounds must be at least 1")
    n = len(CONDITIONS)
    step = {name: [] for name, _, _ in CONDITIONS}
    rtf = {name: [] for name, _, _ in CONDITIONS}
    cpu = {name: [] for name, _, _ in CONDITIONS}
    for r in range(args.rounds):
        for k in range(n):
            name, scenario, sets = CONDITIONS[(k + r) % n]
            s, f, c = run(args.carfollow, scenario, sets, os.path.join(args.out, str(r)))
            step[name].append(s)
            rtf[name].append(f)
            cpu[name].append(c)
        print(f"round {r + 1} of {args.rounds}", file=sys.stderr, flush=True)
    clear = CONDITIONS[0][0]
    lines = [
        "# What the weather costs the loop",
        "",
        f"Made by `python3 examples/weather/cost.py --rounds {args.rounds}` (its docstring says",
        "how). Per condition over the rounds: the loop's time (`timing.step_s`), the",
        "real-time factor, the ratio of the loop's time to clear air's in the same round,",
        "and the same ratio of the run's CPU time (both cores, set-up included).",
        "",
        "| condition | loop time, s | real-time factor | loop time to clear air's "
        "| CPU time to clear air's |",
        "|---|---|---|---|---|",
    ]
    three = lambda v: f"{v:.3f}"
    for name, _, _ in CONDITIONS:
        ratios = [a / b for a, b in zip(step[name], step[clear])]
        cpu_ratios = [a / b for a, b in zip(cpu[name], cpu[clear])]
        lines.append(
            f"| {name} | {spread(step[name], three)} "
            f"| {spread(rtf[name], lambda v: f'{v:.1f}×')} "
            f"| {spread(ratios, three)} | {spread(cpu_ratios, three)} |"
        )
    with open(args.report, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

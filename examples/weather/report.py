#!/usr/bin/env python3
"""The weather study's report: what fog, rain and the dark do to each tracker mode.

Reads the five sweeps that `examples/weather/run.sh` makes of
`scenarios/sweeps/weather.toml`, one per light (`day`, `dusk`, `night-lit`, `night-low`,
`night-high` under one folder, each with its `results.jsonl`), and writes into `--out`:

- `runs.csv`: the figures it reads, a row per run (so that the report can be made again
  from it alone: give it in place of the folder);
- `report.md`: per road, the seconds lost (by the ground truth) and the range error's 95th
  percentile in every condition, paper mode / robust mode, the mean over the seeds; the
  first condition at which each mode fails along each axis from the clear day, and along
  the visual range in every light and rain; the losses that went unreported (silent);
- with `--frames CARFOLLOW`, `frames.png` (or `--frames-out`): one camera frame of each condition on the paper's
  road (seed 1, robust mode, at 10 s), made with `CARFOLLOW render`: a row per light, a
  column per visual range (no rain), then per rain rate (clear air), at half size.

A run *fails* when the target is lost (by the ground truth) for more than
`FAIL_LOST_S` of its 30 s; a condition fails for a mode when a run of either seed fails.

Usage: python3 examples/weather/report.py renders/sweeps/weather --out examples/weather
       [--frames ./target/release/carfollow [--frames-out renders/gallery/weather.png]]

Only the standard library: the picture's PNGs are read and written here.
"""

import argparse
import csv
import json
import os
import struct
import subprocess
import sys
import tempfile
import zlib

LIGHTS = ["day", "dusk", "night-lit", "night-low", "night-high"]
LIGHT_NAMES = {
    "day": "day",
    "dusk": "dusk, low beams",
    "night-lit": "night, street lights, low beams",
    "night-low": "night, low beams",
    "night-high": "night, high beams",
}
# What each light sets (as run.sh does), for the pictures.
LIGHT_SETS = {
    "day": ["environment.sun.elevation_deg=40"],
    "dusk": ["environment.sun.elevation_deg=-4", "chase.headlamps.beam=low"],
    "night-lit": [
        "environment.sun.elevation_deg=-18",
        "chase.headlamps.beam=low",
        "environment.clutter.street_lights_per_km=30",
    ],
    "night-low": ["environment.sun.elevation_deg=-18", "chase.headlamps.beam=low"],
    "night-high": ["environment.sun.elevation_deg=-18", "chase.headlamps.beam=high"],
}
# The sweep file's common overrides (its `set`), for the pictures.
COMMON_SETS = [
    "duration_s=30",
    "environment.sensor.auto_gain.max_gain=64",
    "expect.min_distance_m=100",
]
VISUAL_RANGES = [100000.0, 200.0, 100.0, 60.0, 40.0, 25.0]
RAIN_RATES = [0.0, 2.0, 8.0, 25.0]
MODES = ["paper", "robust"]
ROADS = ["nist-grounds", "highway-90"]
# A run fails when lost for more than this, seconds: 5 % of a 30 s run.
FAIL_LOST_S = 1.5
# Frames lost without a report longer than this are a silent loss (the 15 frames).
SILENT_FRAMES = 15


def v_name(v):
    return "∞" if v >= 100000.0 else f"{v:g} m"


def load(folder):
    """Every run of the five sweeps: (light, road, seed, V, rain, mode) -> summary."""
    runs = {}
    for light in LIGHTS:
        path = os.path.join(folder, light, "results.jsonl")
        if not os.path.exists(path):
            sys.exit(f"report.py: {path}: no such file (run examples/weather/run.sh)")
        with open(path) as f:
            for line in f:
                row = json.loads(line)
                p = row["params"]
                key = (
                    light,
                    row["scenario"],
                    row["seed"],
                    p["environment.fog.visual_range_m"],
                    p["environment.rain.rate_mm_h"],
                    p["tracker.mode"],
                )
                runs[key] = row["summary"]
    return runs


CSV_FIELDS = [
    "light",
    "road",
    "seed",
    "visual_range_m",
    "rain_mm_h",
    "mode",
    "tracking_lost_s",
    "range_error_p95_abs_m",
    "false_alarm_s",
    "silent_loss_frames",
    "low_contrast_s",
]


def write_csv(runs, path):
    """The figures the report reads, one run a row (the sweeps' results.jsonl are large)."""
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(CSV_FIELDS)
        for key, s in sorted(runs.items()):
            w.writerow(
                list(key)
                + [
                    s["tracking_lost_s"],
                    s["range_error_m"]["p95_abs"],
                    s["false_alarm_s"],
                    s.get("silent_loss_frames", 0),
                    s["lost_by_cause_s"].get("low_contrast", 0.0),
                ]
            )


def load_csv(path):
    """Runs as `write_csv` wrote them, in the shape `load` gives."""
    runs = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            key = (
                row["light"],
                row["road"],
                int(row["seed"]),
                float(row["visual_range_m"]),
                float(row["rain_mm_h"]),
                row["mode"],
            )
            runs[key] = {
                "tracking_lost_s": float(row["tracking_lost_s"]),
                "range_error_m": {"p95_abs": float(row["range_error_p95_abs_m"])},
                "false_alarm_s": float(row["false_alarm_s"]),
                "silent_loss_frames": int(row["silent_loss_frames"]),
                "lost_by_cause_s": {"low_contrast": float(row.get("low_contrast_s") or 0.0)},
            }
    return runs


def seeds_of(runs):
    return sorted({k[2] for k in runs})


def cell(runs, seeds, light, road, v, rain, mode):
    """The seeds' summaries of one condition and mode."""
    return [runs[k] for s in seeds if (k := (light, road, s, v, rain, mode)) in runs]


def mean(xs):
    return sum(xs) / len(xs) if xs else float("nan")


def fails(summaries):
    return any(s["tracking_lost_s"] > FAIL_LOST_S for s in summaries)


def grid_table(runs, seeds, road, figure, fmt):
    """A table of `figure(summary)`, paper / robust, rows light × rain, columns V."""
    head = "| light | rain (mm/h) | " + " | ".join(v_name(v) for v in VISUAL_RANGES) + " |"
    out = [head, "|---|---|" + "---|" * len(VISUAL_RANGES)]
    for light in LIGHTS:
        for rain in RAIN_RATES:
            cells = []
            for v in VISUAL_RANGES:
                pair = []
                for mode in MODES:
                    ss = cell(runs, seeds, light, road, v, rain, mode)
                    value = mean([figure(s) for s in ss])
                    text = fmt(value)
                    if fails(ss):
                        text = f"**{text}**"
                    pair.append(text)
                cells.append(" / ".join(pair))
            out.append(f"| {LIGHT_NAMES[light]} | {rain:g} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def first_failure(runs, seeds, road, mode, conditions):
    """The first of `conditions` ((light, V, rain, name)) at which `mode` fails on `road`."""
    for light, v, rain, name in conditions:
        if fails(cell(runs, seeds, light, road, v, rain, mode)):
            return name
    return "none"


def axes_table(runs, seeds):
    clear = (100000.0, 0.0)
    along = {
        "light (clear air, no rain)": [
            (light, *clear, LIGHT_NAMES[light]) for light in LIGHTS
        ],
        "visual range (day, no rain)": [
            ("day", v, 0.0, v_name(v)) for v in VISUAL_RANGES
        ],
        "rain (day, clear air)": [
            ("day", 100000.0, r, f"{r:g} mm/h") for r in RAIN_RATES
        ],
    }
    out = ["| from the clear day, along | road | paper | robust |", "|---|---|---|---|"]
    for axis, conditions in along.items():
        for road in ROADS:
            firsts = [first_failure(runs, seeds, road, m, conditions) for m in MODES]
            out.append(f"| {axis} | `{road}` | " + " | ".join(firsts) + " |")
    return "\n".join(out)


def range_table(runs, seeds):
    """The longest visual range at which each mode fails, in every light and rain."""
    cols = [(road, mode) for road in ROADS for mode in MODES]
    out = [
        "| light | rain (mm/h) | " + " | ".join(f"`{r}` {m}" for r, m in cols) + " |",
        "|---|---|" + "---|" * len(cols),
    ]
    for light in LIGHTS:
        for rain in RAIN_RATES:
            firsts = []
            for road, mode in cols:
                conditions = [(light, v, rain, v_name(v)) for v in VISUAL_RANGES]
                firsts.append(first_failure(runs, seeds, road, mode, conditions))
            out.append(f"| {LIGHT_NAMES[light]} | {rain:g} | " + " | ".join(firsts) + " |")
    return "\n".join(out)


def silent(runs):
    bad = [
        (k, s["silent_loss_frames"])
        for k, s in sorted(runs.items())
        if s.get("silent_loss_frames", 0) > SILENT_FRAMES
    ]
    if not bad:
        return f"No run lost the target silently for more than {SILENT_FRAMES} frames."
    lines = [
        f"{len(bad)} of {len(runs)} runs lost the target silently for more than "
        f"{SILENT_FRAMES} frames (the tracker still said `tracking`):",
        "",
    ]
    for (light, road, seed, v, rain, mode), n in bad[:40]:
        lines.append(
            f"- `{road}` seed {seed}, {LIGHT_NAMES[light]}, {v_name(v)}, "
            f"{rain:g} mm/h, {mode}: {n} frames"
        )
    if len(bad) > 40:
        lines.append(f"- and {len(bad) - 40} more")
    return "\n".join(lines)


def causes(runs):
    """Per light and mode, over both roads and every condition: the seconds lost, and how
    many of them the truth gives to a target too faint for the paper's threshold."""
    lines = [
        "| light | paper: lost, s | of it `low_contrast` | robust: lost, s | of it `low_contrast` |",
        "|---|---|---|---|---|",
    ]
    for light in LIGHTS:
        cells = []
        for mode in ["paper", "robust"]:
            mine = [s for k, s in runs.items() if k[0] == light and k[5] == mode]
            if not mine:
                cells += ["–", "–"]
                continue
            lost = sum(s["tracking_lost_s"] for s in mine)
            faint = sum(s["lost_by_cause_s"].get("low_contrast", 0.0) for s in mine)
            share = f" ({100 * faint / lost:.0f} %)" if lost > 0 else ""
            cells += [f"{lost:.1f}", f"{faint:.1f}{share}"]
        lines.append(f"| {LIGHT_NAMES[light]} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def report(runs):
    seeds = seeds_of(runs)
    n = len(runs)
    parts = [
        "# The weather study: report",
        "",
        f"{n} runs of 30 s ({len(seeds)} seeds: {', '.join(map(str, seeds))}), made by "
        "`examples/weather/run.sh` and written by `examples/weather/report.py`. Each cell is "
        "paper mode / robust mode, the mean over the seeds; **bold**: a seed lost the target "
        f"for more than {FAIL_LOST_S} s (the condition fails). ∞ is a visual range of "
        "100 km.",
    ]
    for road in ROADS:
        parts += [
            "",
            f"## `{road}`: seconds lost (by the ground truth)",
            "",
            grid_table(runs, seeds, road, lambda s: s["tracking_lost_s"], lambda x: f"{x:.1f}"),
            "",
            f"## `{road}`: range error, 95th percentile (m)",
            "",
            grid_table(
                runs,
                seeds,
                road,
                lambda s: s["range_error_m"]["p95_abs"],
                lambda x: f"{x:.2f}",
            ),
        ]
    parts += [
        "",
        "## The first condition at which each mode fails",
        "",
        "Along each axis alone, from the clear day:",
        "",
        axes_table(runs, seeds),
        "",
        "The longest visual range at which each mode fails, in every light and rain "
        "(from ∞ down; `none`: holds at 25 m):",
        "",
        range_table(runs, seeds),
        "",
        "## Silent losses",
        "",
        silent(runs),
        "",
        "## Why the target was lost",
        "",
        "Seconds lost over both roads, every visual range and rain rate and both seeds, and "
        "how many of them the ground truth gives to a target too faint for the paper's edge "
        "threshold in the pixels the tracker read (`low_contrast`; the rest is out of view, "
        "hidden, or the tracker's own):",
        "",
        causes(runs),
        "",
    ]
    return "\n".join(parts)


# --- The picture: 8-bit grey PNGs read and written with zlib alone. ---


def read_grey_png(path):
    """An 8-bit greyscale PNG's (width, height, rows of bytes)."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, width, height = 8, b"", 0, 0
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            if (depth, colour) != (8, 0):
                sys.exit(f"report.py: {path}: not an 8-bit grey PNG")
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    rows, prev = [], bytearray(width)
    for y in range(height):
        start = y * (width + 1)
        kind, line = raw[start], bytearray(raw[start + 1 : start + 1 + width])
        for x in range(width):
            a = line[x - 1] if x else 0
            b = prev[x]
            c = prev[x - 1] if x else 0
            if kind == 1:
                line[x] = (line[x] + a) & 255
            elif kind == 2:
                line[x] = (line[x] + b) & 255
            elif kind == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[x] = (line[x] + pred) & 255
        rows.append(line)
        prev = line
    return width, height, rows


def write_grey_png(path, rows):
    height, width = len(rows), len(rows[0])

    def chunk(kind, body):
        return (
            struct.pack(">I", len(body))
            + kind
            + body
            + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
        )

    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


def half(rows):
    """A 2 × 2 box average."""
    out = []
    for y in range(0, len(rows) - 1, 2):
        a, b = rows[y], rows[y + 1]
        out.append(
            bytearray(
                (a[x] + a[x + 1] + b[x] + b[x + 1] + 2) // 4 for x in range(0, len(a) - 1, 2)
            )
        )
    return out


def frames(carfollow, out_png, scenario="scenarios/nist-grounds.toml", time_s=10.0):
    """One frame per condition, a row per light: the visual ranges (no rain), then the
    rain rates (clear air)."""
    columns = [(v, 0.0) for v in VISUAL_RANGES] + [(100000.0, r) for r in RAIN_RATES[1:]]
    sheet = []
    gap = 4
    with tempfile.TemporaryDirectory() as tmp:
        for light in LIGHTS:
            tiles = []
            for v, rain in columns:
                png = os.path.join(tmp, "frame.png")
                sets = COMMON_SETS + LIGHT_SETS[light] + [
                    f"environment.fog.visual_range_m={v}",
                    f"environment.rain.rate_mm_h={rain}",
                    "tracker.mode=robust",
                ]
                cmd = [carfollow, "render", scenario, "--time", str(time_s), "--out", png]
                for s in sets:
                    cmd += ["--set", s]
                subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
                _, _, rows = read_grey_png(png)
                tiles.append(half(rows))
            height = len(tiles[0])
            for y in range(height):
                line = bytearray()
                for k, t in enumerate(tiles):
                    if k:
                        line += bytearray([255] * gap)
                    line += t[y]
                sheet.append(line)
            sheet += [bytearray([255] * len(sheet[-1])) for _ in range(gap)]
    write_grey_png(out_png, sheet[:-gap])
    return columns


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument(
        "folder",
        help="the folder run.sh wrote the five sweeps into, or a runs.csv this script wrote",
    )
    ap.add_argument("--out", default="examples/weather", help="where to write the report")
    ap.add_argument("--frames", metavar="CARFOLLOW", help="draw the frames with this binary")
    ap.add_argument(
        "--frames-out",
        metavar="PNG",
        help="where to write the frames (default: OUT/frames.png)",
    )
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    if args.folder.endswith(".csv"):
        runs = load_csv(args.folder)
    else:
        runs = load(args.folder)
        write_csv(runs, os.path.join(args.out, "runs.csv"))
    with open(os.path.join(args.out, "report.md"), "w") as f:
        f.write(report(runs))
    if args.frames:
        frames(args.frames, args.frames_out or os.path.join(args.out, "frames.png"))
    print(f"report.py: {len(runs)} runs; wrote {args.out}/report.md")


if __name__ == "__main__":
    main()

#!/bin/sh
# How far ahead the search first finds a vehicle standing in the chase's lane, by kind,
# paint and lens: scenarios/sweeps/car-acquisition.toml into OUT (default
# renders/sweeps/car-acquisition), then the report into examples/car-acquisition/report.md.
# CARFOLLOW names the binary (default: carfollow on the PATH); JOBS the parallel runs.
set -eu
CARFOLLOW=${CARFOLLOW:-carfollow}
OUT=${OUT:-renders/sweeps/car-acquisition}
JOBS=${JOBS:-2}
"$CARFOLLOW" sweep scenarios/sweeps/car-acquisition.toml --jobs "$JOBS" --out "$OUT"
python3 examples/car-acquisition/report.py "$OUT/results.jsonl" \
  --out examples/car-acquisition/report.md

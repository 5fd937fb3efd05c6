#!/bin/sh
# What the library's false alarms are: every scenario of scenarios/ run in both modes into
# OUT (default renders/library), then examples/false-alarms/classify.py over the runs.
# CARFOLLOW names the binary (default: carfollow on the PATH).
set -eu
CARFOLLOW=${CARFOLLOW:-carfollow}
OUT=${OUT:-renders/library}
for f in scenarios/*.toml; do
  n=$(basename "$f" .toml)
  for m in paper robust; do
    # A run whose criteria fail (exit 1) still wrote its frames.
    "$CARFOLLOW" run "$f" --quiet --out "$OUT/$n-$m" --set tracker.mode=$m >/dev/null || [ $? -eq 1 ]
  done
done
python3 examples/false-alarms/classify.py "$OUT"/*-paper "$OUT"/*-robust

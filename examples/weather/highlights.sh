#!/bin/sh
# What highlight protection changes at night on high beams: the weather study's night on
# high beams (scenarios/sweeps/weather.toml, 192 runs) and the acquisition study's
# (scenarios/sweeps/weather-acquisition.toml, 24 runs), each without and with the automatic
# gain's `max_clipped_share` at 1 %, into OUT (default renders/sweeps/weather-highlights):
# `study-plain`, `study`, `acquisition-plain`, `acquisition`; then the report into
# examples/weather/highlights.md.
# CARFOLLOW names the binary (default: carfollow on the PATH); JOBS the parallel runs.
set -eu
CARFOLLOW=${CARFOLLOW:-carfollow}
OUT=${OUT:-renders/sweeps/weather-highlights}
JOBS=${JOBS:-2}
NIGHT_HIGH="--set environment.sun.elevation_deg=-18 --set chase.headlamps.beam=high"
SHARE="--set environment.sensor.auto_gain.max_clipped_share=0.01"
# shellcheck disable=SC2086
"$CARFOLLOW" sweep scenarios/sweeps/weather.toml --jobs "$JOBS" --out "$OUT/study-plain" \
  $NIGHT_HIGH
# shellcheck disable=SC2086
"$CARFOLLOW" sweep scenarios/sweeps/weather.toml --jobs "$JOBS" --out "$OUT/study" \
  $NIGHT_HIGH $SHARE
# shellcheck disable=SC2086
"$CARFOLLOW" sweep scenarios/sweeps/weather-acquisition.toml --jobs "$JOBS" \
  --out "$OUT/acquisition" $NIGHT_HIGH $SHARE
# shellcheck disable=SC2086
"$CARFOLLOW" sweep scenarios/sweeps/weather-acquisition.toml --jobs "$JOBS" \
  --out "$OUT/acquisition-plain" $NIGHT_HIGH
python3 examples/weather/highlights.py "$OUT" --out examples/weather/highlights.md

#!/bin/sh
# How far ahead the search first holds the lead in fog and in the dark:
# scenarios/sweeps/weather-acquisition.toml in the weather study's lights but the street-lit
# night, each into its own folder under OUT (default renders/sweeps/weather-acquisition),
# then the report into examples/weather/acquisition.md.
# CARFOLLOW names the binary (default: carfollow on the PATH); JOBS the parallel runs.
set -eu
CARFOLLOW=${CARFOLLOW:-carfollow}
OUT=${OUT:-renders/sweeps/weather-acquisition}
JOBS=${JOBS:-2}
sweep() {
  light=$1
  shift
  "$CARFOLLOW" sweep scenarios/sweeps/weather-acquisition.toml --jobs "$JOBS" \
    --out "$OUT/$light" "$@"
}
# The lights of run.sh: day (the sun 40 degrees up, lamps off); dusk (4 degrees below, low
# beams); night (18 degrees below) on low beams, then on high beams.
sweep day --set environment.sun.elevation_deg=40
sweep dusk --set environment.sun.elevation_deg=-4 --set chase.headlamps.beam=low
sweep night-low --set environment.sun.elevation_deg=-18 --set chase.headlamps.beam=low
sweep night-high --set environment.sun.elevation_deg=-18 --set chase.headlamps.beam=high
python3 examples/weather/acquisition.py "$OUT" --out examples/weather/acquisition.md

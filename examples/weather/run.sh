#!/bin/sh
# The weather study: scenarios/sweeps/weather.toml in five lights, each into its own folder
# under OUT (default renders/sweeps/weather), then the report into examples/weather/ and its
# picture into renders/gallery/weather.png.
# CARFOLLOW names the binary (default: carfollow on the PATH); JOBS the parallel runs.
set -eu
CARFOLLOW=${CARFOLLOW:-carfollow}
OUT=${OUT:-renders/sweeps/weather}
JOBS=${JOBS:-2}
sweep() {
  light=$1
  shift
  "$CARFOLLOW" sweep scenarios/sweeps/weather.toml --jobs "$JOBS" --out "$OUT/$light" "$@"
}
# Day: the sun 40 degrees up (the scenarios' own sun), the lamps off.
sweep day --set environment.sun.elevation_deg=40
# Dusk: the sun 4 degrees below the horizon (civil twilight: the sky gives 3.8 % of its
# sunset light, about 15 lux), on low beams.
sweep dusk --set environment.sun.elevation_deg=-4 --set chase.headlamps.beam=low
# Night: the sun 18 degrees below (0.001 lux): on low beams under street lights, 30 a km
# (every 33 m, lighting the road to 5-15 lux), then on low beams alone, then on high beams.
sweep night-lit --set environment.sun.elevation_deg=-18 --set chase.headlamps.beam=low \
  --set environment.clutter.street_lights_per_km=30
sweep night-low --set environment.sun.elevation_deg=-18 --set chase.headlamps.beam=low
sweep night-high --set environment.sun.elevation_deg=-18 --set chase.headlamps.beam=high
python3 examples/weather/report.py "$OUT" --out examples/weather \
  --frames "$CARFOLLOW" --frames-out renders/gallery/weather.png

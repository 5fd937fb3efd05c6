#!/usr/bin/env python3
"""Points for carfollow's Euro NCAP car-to-car rear runs (CCRs, CCRm, CCRb).

Reads the `results.jsonl` that `carfollow sweep scenarios/sweeps/ncap-ccr.toml` writes (or
the `summary.json` of single runs) and prints, as Markdown: each test's impact speed and
points, and the totals by test type, tracker mode and lens, with what decided each loss of
points.

THE SCORING RULE, AND WHAT IT IS NOT. Euro NCAP's AEB car-to-car assessment (Assessment
Protocol - Safety Assist - Collision Avoidance, 2023) gives each test speed its own points
and scores a test by the speed reduction it achieves, with full points for avoidance. Its
tables (the points of each test speed, and the bands of speed reduction) could not be
consulted where this script was written, so this script does NOT reproduce them. It
implements the rule those tables grade, stated here so that it can be checked:

    points = available * (1 - v_impact_rel / v_reference_rel), clamped to 0..available

with every test worth `available` = 1 point (so a total is the share of the points won),
`v_impact_rel` the relative speed at the first contact (0 for an avoided collision: full
points), and `v_reference_rel` the relative speed at which the same test ends without any
braking by the car under test:

  - CCRs, CCRm: the closing speed at the start, v_test - v_target;
  - CCRb (both at v, the target braking at a from a gap d, the car under test holding v):
    sqrt(2 a d) if the contact comes while the target is still moving (sqrt(2 d / a) <= v / a),
    else v (the target has stopped). Plain kinematics of constant deceleration.

Putting the protocol's per-speed points in `AVAILABLE_POINTS` (test type -> test speed ->
points) is all it takes to weight the tests as the protocol does.

What decided a loss (a test with contact), from the run's own figures:

  - "never acquired": the tracker never held the target in the chase's path;
  - "acquisition range": acquired nearer than the chase can stop in from its closing speed
    at the braking it counts on, v^2 / (2 * 7.0 m/s^2) (`own_emergency_decel_mps2`);
  - "latency": acquired beyond that, but nearer than that plus the distance covered while
    the estimate is on its way (the loop's latency, one frame, and half the brake's
    build-up to 7 m/s^2 at 12 m/s^3);
  - "braking": acquired in time, or held from the start (CCRb); the brake came late or
    too softly;
  - "sped up": the contact was faster than the no-braking reference: the gap keeper,
    taking the target for a faster one, accelerated towards it.

A test without contact in which the tracker never held the target (the chase stopped
short for something else) keeps its points by the rule, and is marked "no contact, target
never held".
"""

import argparse
import glob
import json
import math
import os
import sys
import tomllib

#: The braking the chase counts on in an emergency, m/s² (the gap keeper's
#: `own_emergency_decel_mps2` default, 7.0 m/s²).
EMERGENCY_DECEL_MPS2 = 7.0
#: The chase's brake build-up rate, m/s³ (the gap keeper's `max_brake_jerk_mps3`, 12).
BRAKE_JERK_MPS3 = 12.0
#: How much faster than the no-braking reference a contact must be to say that the chase
#: sped up, km/h (1 km/h: well above the speed loop's ripple).
SPED_UP_MARGIN_KPH = 1.0
#: One camera frame, s (15 Hz).
FRAME_S = 1.0 / 15.0
#: Points a test is worth unless `AVAILABLE_POINTS` says otherwise: 1, so that a total is
#: the share of the points won.
DEFAULT_POINTS = 1.0
#: Per test type, test speed (km/h, rounded) -> points: empty, as the protocol's own
#: table is not reproduced (see the module's doc).
AVAILABLE_POINTS = {"CCRs": {}, "CCRm": {}, "CCRb": {}}

KPH_PER_MPS = 3.6
#: The car under test's width (the chase, an HMMWV) and the target's (the lead, a pickup),
#: m: what an overlap is a share of (`vehicle::VehicleParams`).
VUT_WIDTH_M = 2.16
TARGET_WIDTH_M = 2.00
#: The scenario library, whose files a sweep's rows name.
SCENARIOS_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scenarios")


def reference_speed_kph(test_type, v_test_kph, v_target_kph, gap_m=None, decel_mps2=None):
    """The relative speed at contact with no braking by the car under test, km/h."""
    if test_type in ("CCRs", "CCRm"):
        return v_test_kph - v_target_kph
    if test_type == "CCRb":
        v = v_test_kph / KPH_PER_MPS
        t_contact = math.sqrt(2.0 * gap_m / decel_mps2)
        if t_contact <= v / decel_mps2:
            return math.sqrt(2.0 * decel_mps2 * gap_m) * KPH_PER_MPS
        return v_test_kph
    raise ValueError(f"unknown test type {test_type!r}")


def points(v_impact_rel_kph, v_reference_rel_kph, available=DEFAULT_POINTS):
    """Points of one test: all for no contact, none for no speed reduction, linear between."""
    if v_impact_rel_kph is None or v_impact_rel_kph <= 0.0:
        return available
    if v_reference_rel_kph <= 0.0:
        return 0.0
    share = 1.0 - v_impact_rel_kph / v_reference_rel_kph
    return available * min(1.0, max(0.0, share))


def loss_cause(v_rel_kph, acquisition_range_m, latency_s, held_from_start):
    """What decided a test that ended in contact (see the module's doc)."""
    if held_from_start:
        return "braking"
    if acquisition_range_m is None:
        return "never acquired"
    v = v_rel_kph / KPH_PER_MPS
    stop_m = v * v / (2.0 * EMERGENCY_DECEL_MPS2)
    dead_s = latency_s + FRAME_S + 0.5 * EMERGENCY_DECEL_MPS2 / BRAKE_JERK_MPS3
    if acquisition_range_m < stop_m:
        return "acquisition range"
    if acquisition_range_m < stop_m + v * dead_s:
        return "latency"
    return "braking"


def overlap_pct(offset_m):
    """The protocol's overlap, %, of a target `offset_m` to the left of the lane's centre
    (the car under test on it): 100 for none, else the share of the car under test's width
    that overlaps the target, negative with the target to the right, as Vector's
    OSC-NCAP-scenarios place it (|offset| = target width / 2 - VUT width * (|overlap| - 50)
    / 100), to the nearest per cent."""
    if offset_m == 0.0:
        return 100
    share = 50.0 + (TARGET_WIDTH_M / 2.0 - abs(offset_m)) * 100.0 / VUT_WIDTH_M
    return int(round(math.copysign(share, offset_m)))


def test_type_of(scenario_name):
    for t in ("CCRs", "CCRm", "CCRb"):
        if t.lower() in scenario_name.lower():
            return t
    return None


def scenario_of(summary, scenarios_dir):
    """The scenario a run ran, as a dict: its `resolved_scenario` (a single run's
    summary.json), or the library's file of that name with the run's `overrides` applied (a
    sweep's rows, which carry only the overrides)."""
    if "resolved_scenario" in summary:
        return summary["resolved_scenario"]
    with open(os.path.join(scenarios_dir, summary["scenario"] + ".toml"), "rb") as fh:
        sc = tomllib.load(fh)
    for o in summary.get("overrides", []):
        path, value = o.split("=", 1)
        value = tomllib.loads("v = " + value)["v"]
        node = sc
        keys = path.split(".")
        for k in keys[:-1]:
            node = node[int(k)] if isinstance(node, list) else node.setdefault(k, {})
        if isinstance(node, list):
            node[int(keys[-1])] = value
        else:
            node[keys[-1]] = value
    return sc


def row_of(summary, scenarios_dir=None):
    """One test's figures from a run's summary (a summary.json or a sweep row's)."""
    sc = scenario_of(summary, scenarios_dir or SCENARIOS_DIR)
    test_type = test_type_of(sc["name"])
    if test_type is None:
        return None
    chase, lead = sc["chase"], sc["lead"]
    v_target = lead.get("initial_speed_mps", lead["speed_profile"][0][1]) * KPH_PER_MPS
    if chase.get("start_at_cruise_speed"):
        v_test = chase["controller"]["cruise_speed_mps"] * KPH_PER_MPS
    elif chase.get("speed_profile"):
        v_test = chase["speed_profile"][0][1] * KPH_PER_MPS
    else:
        v_test = v_target
    gap_m = decel = None
    if test_type == "CCRb":
        gap_m = chase["initial_gap_m"] - CCRB_GAP_OFFSET_M
        decel = lead["events"][0]["action"]["rate_mps2"]
    traffic = summary.get("traffic") or {}
    collisions = traffic.get("collisions") or []
    v_impact = max(0.0, collisions[0]["closing_kph"]) if collisions else 0.0
    v_ref = reference_speed_kph(test_type, v_test, v_target, gap_m, decel)
    available = AVAILABLE_POINTS[test_type].get(round(v_test), DEFAULT_POINTS)
    got = points(v_impact, v_ref, available)
    tracker = sc.get("tracker", {})
    cause = ""
    if collisions and v_impact > v_ref + SPED_UP_MARGIN_KPH:
        cause = "sped up"
    elif not collisions and traffic.get("acquisition_range_m") is None:
        # Full points by the rule, but not for holding the target: the chase stopped
        # short for something else (a search that fixed on the scenery).
        cause = "no contact, target never held"
    elif collisions:
        cause = loss_cause(
            v_test - v_target,
            traffic.get("acquisition_range_m"),
            sc.get("loop", {}).get("latency_ms", 128.0) / 1000.0,
            held_from_start=tracker.get("start", "operator") != "search",
        )
    return {
        "type": test_type,
        "mode": tracker.get("mode", "paper"),
        "lens_mm": sc["camera"]["focal_length_mm"],
        "overlap_pct": overlap_pct(lead.get("offset_m", 0.0)),
        "v_test_kph": v_test,
        "v_target_kph": v_target,
        "gap_m": gap_m,
        "decel_mps2": decel,
        "seed": summary.get("seed"),
        "acq_m": traffic.get("acquisition_range_m"),
        "impact_kph": v_impact,
        "reference_kph": v_ref,
        "points": got,
        "available": available,
        "cause": cause,
    }


#: Camera-to-target distance less the bumper-to-bumper gap at the start, m: the chase's
#: front bumper ahead of its camera plus the lead's board ahead of its rear bumper, as the
#: library's scenarios place them: `frames.csv`'s `gap_m` less its `path_gap_m` at t = 0).
CCRB_GAP_OFFSET_M = 1.74


def read_summaries(paths):
    for p in paths:
        if os.path.isdir(p):
            files = sorted(glob.glob(os.path.join(p, "results*.jsonl")))
            files += sorted(glob.glob(os.path.join(p, "**", "summary.json"), recursive=True))
        else:
            files = [p]
        for f in files:
            if f.endswith(".jsonl"):
                with open(f) as fh:
                    for line in fh:
                        line = line.strip()
                        if line:
                            yield json.loads(line)["summary"]
            else:
                with open(f) as fh:
                    yield json.load(fh)


def fmt(v, digits=1):
    return "—" if v is None else f"{v:.{digits}f}"


def report(rows):
    out = []
    out.append("| test | mode | lens | test speed | target | acquired at | impact | "
               "no-brake impact | points | lost to, or note |")
    out.append("|---|---|---|---|---|---|---|---|---|---|")
    order = {"CCRs": 0, "CCRm": 1, "CCRb": 2}
    rows = sorted(rows, key=lambda r: (order[r["type"]], r["mode"], r["lens_mm"],
                                       -r.get("overlap_pct", 100), r["v_test_kph"],
                                       r["gap_m"] or 0, r["decel_mps2"] or 0))
    for r in rows:
        target = f"{r['v_target_kph']:.0f} km/h"
        if r["type"] == "CCRb":
            target += f", {r['decel_mps2']:g} m/s² from {r['gap_m']:.0f} m"
        if r.get("overlap_pct", 100) != 100:
            target += f", {r['overlap_pct']} % overlap"
        out.append(
            f"| {r['type']} | {r['mode']} | {r['lens_mm']:g} mm | {r['v_test_kph']:.0f} km/h | "
            f"{target} | {fmt(r['acq_m'])} m | {fmt(r['impact_kph'])} km/h | "
            f"{fmt(r['reference_kph'])} km/h | {r['points']:.2f} / {r['available']:g} | "
            f"{r['cause'] or '—'} |"
        )
    out.append("")
    out.append("| test | mode | lens | tests | avoided | points | share | lost to, and notes |")
    out.append("|---|---|---|---|---|---|---|---|")
    groups = {}
    for r in rows:
        groups.setdefault((r["type"], r["mode"], r["lens_mm"]), []).append(r)
    for (t, mode, lens), rs in sorted(groups.items(), key=lambda kv: (order[kv[0][0]],) + kv[0][1:]):
        got = sum(r["points"] for r in rs)
        avail = sum(r["available"] for r in rs)
        avoided = sum(1 for r in rs if not r["impact_kph"])
        causes = {}
        for r in rs:
            if r["cause"]:
                causes[r["cause"]] = causes.get(r["cause"], 0) + 1
        lost = ", ".join(f"{k} ×{v}" for k, v in sorted(causes.items())) or "—"
        out.append(f"| {t} | {mode} | {lens:g} mm | {len(rs)} | {avoided} | "
                   f"{got:.2f} / {avail:g} | {100.0 * got / avail:.0f} % | {lost} |")
    return "\n".join(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("paths", nargs="+",
                    help="sweep folders (their results*.jsonl), results files or summary.json")
    args = ap.parse_args(argv)
    rows = [r for s in read_summaries(args.paths) if (r := row_of(s)) is not None]
    if not rows:
        print("ncap_score: no CCRs, CCRm or CCRb runs in " + ", ".join(args.paths),
              file=sys.stderr)
        return 1
    print(report(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())

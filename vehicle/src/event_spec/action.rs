//! An event's action checked: exactly one of a lane change, a speed change, a stop and the
//! run's end, with the timing and shape it takes.

use super::MAX_PROFILE_ENTRIES;
use super::{check, invalid, Action, ActionSpec, RelativeSpeed, Shape, Timing, MAX_KEY, MAX_LANES};
use super::{Keep, KeepSide, KeepSpec, KEEP_MAX_ACCEL_MPS2, KEEP_MAX_DECEL_MPS2, MAX_GAP_M};
use super::{MAX_LATERAL_ACCEL_MPS2, MAX_LATERAL_SPEED_MPS, MAX_POSITION_OFFSET_M, MAX_RATE_MPS2};
use crate::error::VehicleError;
use crate::speed_profile::MAX_SPEED_MPS;

/// Refuses each of `fields` (name, whether given) that is given, as not for `what`.
fn refuse(i: usize, what: &str, fields: &[(&str, bool)]) -> Result<(), VehicleError> {
    match fields.iter().find(|f| f.1) {
        Some((name, _)) => Err(invalid(
            i,
            &format!("action.{name}"),
            format!("not for {what}"),
        )),
        None => Ok(()),
    }
}

/// The fields of an action that time or shape a change, or relate it to a vehicle (name,
/// whether given): none is for an action that takes none of them.
fn timings(a: &ActionSpec) -> [(&'static str, bool); 8] {
    [
        ("duration_s", a.duration_s.is_some()),
        ("lateral_speed_mps", a.lateral_speed_mps.is_some()),
        ("lateral_accel_mps2", a.lateral_accel_mps2.is_some()),
        ("rate_mps2", a.rate_mps2.is_some()),
        ("decel_mps2", a.decel_mps2.is_some()),
        ("shape", a.shape.is_some()),
        ("speed_of", a.speed_of.is_some()),
        ("continuous", a.continuous),
    ]
}

/// Event `i`'s `keep` action, checked: its gap or time gap, its vehicle and its limits,
/// and nothing else in the action.
fn keep_action(i: usize, a: &ActionSpec, k: &KeepSpec) -> Result<Action, VehicleError> {
    refuse(i, "a kept gap (its limits are keep's own)", &timings(a))?;
    let f = |name: &str| format!("action.keep.{name}");
    if k.to.trim().is_empty() {
        return Err(invalid(i, &f("to"), "must name a vehicle".into()));
    }
    let (value, time) = match (k.gap_m, k.time_gap_s) {
        (Some(g), None) => (check(i, &f("gap_m"), g, 0.0, MAX_GAP_M, false)?, false),
        (None, Some(t)) => (check(i, &f("time_gap_s"), t, 0.0, 1e3, false)?, true),
        _ => {
            return Err(invalid(
                i,
                "action.keep",
                "takes exactly one of gap_m and time_gap_s".into(),
            ))
        }
    };
    let limit = |name: &str, v: Option<f64>, default: f64, max: f64| match v {
        Some(v) => check(i, &f(name), v, 0.0, max, true),
        None => Ok(default),
    };
    let max_speed = f64::from(MAX_SPEED_MPS);
    Ok(Action::Keep(Keep {
        to: k.to.clone(),
        value,
        time,
        axles: k.between_axles,
        side: k.side.unwrap_or(KeepSide::Behind),
        continuous: k.continuous.unwrap_or(true),
        max_accel_mps2: limit(
            "max_accel_mps2",
            k.max_accel_mps2,
            KEEP_MAX_ACCEL_MPS2,
            MAX_RATE_MPS2,
        )?,
        max_decel_mps2: limit(
            "max_decel_mps2",
            k.max_decel_mps2,
            KEEP_MAX_DECEL_MPS2,
            MAX_RATE_MPS2,
        )?,
        max_jerk_mps3: k
            .max_jerk_mps3
            .map(|j| check(i, &f("max_jerk_mps3"), j, 0.0, 1e3, true))
            .transpose()?,
        max_speed_mps: limit("max_speed_mps", k.max_speed_mps, max_speed, max_speed)?,
    }))
}

/// Event `i`'s `end_run` action (`end`, its value), checked: `true`, with nothing else.
fn end_run_action(i: usize, a: &ActionSpec, end: bool) -> Result<Action, VehicleError> {
    if !end {
        return Err(invalid(
            i,
            "action.end_run",
            "= false: write end_run = true, or leave the event out".into(),
        ));
    }
    refuse(
        i,
        "the run's end (it takes no time and no shape)",
        &timings(a),
    )?;
    Ok(Action::EndRun)
}

/// Event `i`'s action, checked.
pub(super) fn action(i: usize, a: &ActionSpec) -> Result<Action, VehicleError> {
    let kinds = [
        a.lane.is_some(),
        a.offset_m.is_some(),
        a.speed_mps.is_some() || a.speed_factor.is_some(),
        a.profile.is_some(),
        a.stop.is_some(),
        a.end_run.is_some(),
        a.keep.is_some(),
    ];
    if kinds.iter().filter(|&&k| k).count() != 1 {
        return Err(invalid(
            i,
            "action",
            "must give exactly one of lane, offset_m, speed_mps (or speed_factor), profile, \
             stop, keep and end_run"
                .into(),
        ));
    }
    if let Some(keep) = &a.keep {
        return keep_action(i, a, keep);
    }
    if let Some(end) = a.end_run {
        return end_run_action(i, a, end);
    }
    if a.speed_mps.is_none() && a.speed_factor.is_none() {
        refuse(
            i,
            "anything but a speed change",
            &[
                ("speed_of", a.speed_of.is_some()),
                ("continuous", a.continuous),
            ],
        )?;
    }
    if let Some(entries) = &a.profile {
        return profile_action(i, a, entries);
    }
    if a.offset_m.is_none() {
        refuse(
            i,
            "a lane change, a speed change or a stop (it is an offset's)",
            &[("lateral_accel_mps2", a.lateral_accel_mps2.is_some())],
        )?;
    }
    if let Some(offset) = a.offset_m {
        return offset_action(i, a, offset);
    }
    let f = |name: &str| format!("action.{name}");
    let open = |name: &str, v: f64, max: f64| check(i, &f(name), v, 0.0, max, true);
    if let Some(lane) = a.lane {
        refuse(
            i,
            "a lane change",
            &[
                ("rate_mps2", a.rate_mps2.is_some()),
                ("decel_mps2", a.decel_mps2.is_some()),
            ],
        )?;
        if !(1..=MAX_LANES).contains(&lane) {
            return Err(invalid(
                i,
                "action.lane",
                format!("= {lane}: lanes are numbered 1 to {MAX_LANES} from the centre line"),
            ));
        }
        let timing = match (a.duration_s, a.lateral_speed_mps) {
            (Some(d), None) => Timing::Duration(open("duration_s", d, MAX_KEY)?),
            (None, Some(v)) => Timing::Rate(open("lateral_speed_mps", v, MAX_LATERAL_SPEED_MPS)?),
            _ => {
                return Err(invalid(
                    i,
                    "action",
                    "a lane change takes exactly one of duration_s and lateral_speed_mps".into(),
                ))
            }
        };
        return Ok(Action::Lane {
            lane,
            timing,
            shape: lateral_shape(i, a.shape, "a lane change")?,
        });
    }
    if let Some(stop) = a.stop {
        if !stop {
            return Err(invalid(
                i,
                "action.stop",
                "= false: write stop = true, or leave the event out".into(),
            ));
        }
        refuse(
            i,
            "a stop (it slows at decel_mps2)",
            &[
                ("duration_s", a.duration_s.is_some()),
                ("rate_mps2", a.rate_mps2.is_some()),
                ("lateral_speed_mps", a.lateral_speed_mps.is_some()),
                ("shape", a.shape.is_some()),
            ],
        )?;
        let Some(decel) = a.decel_mps2 else {
            return Err(invalid(
                i,
                "action.decel_mps2",
                "missing: a stop needs its deceleration".into(),
            ));
        };
        return Ok(Action::Speed {
            speed_mps: 0.0,
            timing: Timing::Rate(open("decel_mps2", decel, MAX_RATE_MPS2)?),
            shape: Shape::Linear,
            relative: None,
        });
    }
    speed_action(i, a)
}

/// Event `i`'s offset (`offset_m` given), checked.
fn offset_action(i: usize, a: &ActionSpec, offset: f64) -> Result<Action, VehicleError> {
    refuse(
        i,
        "an offset",
        &[
            ("rate_mps2", a.rate_mps2.is_some()),
            ("decel_mps2", a.decel_mps2.is_some()),
        ],
    )?;
    let f = |name: &str| format!("action.{name}");
    let open = |name: &str, v: f64, max: f64| check(i, &f(name), v, 0.0, max, true);
    let offset_m = check(
        i,
        "action.offset_m",
        offset,
        -MAX_POSITION_OFFSET_M,
        MAX_POSITION_OFFSET_M,
        false,
    )?;
    refuse(
        i,
        "an offset: its pace is its peak lateral acceleration, lateral_accel_mps2 \
         (OpenSCENARIO's maxLateralAcc)",
        &[
            ("duration_s", a.duration_s.is_some()),
            ("lateral_speed_mps", a.lateral_speed_mps.is_some()),
        ],
    )?;
    let Some(accel) = a.lateral_accel_mps2 else {
        return Err(invalid(
            i,
            "action.lateral_accel_mps2",
            "missing: an offset moves at a peak lateral acceleration".into(),
        ));
    };
    let timing = Timing::PeakAccel(open("lateral_accel_mps2", accel, MAX_LATERAL_ACCEL_MPS2)?);
    Ok(Action::Offset {
        offset_m,
        timing,
        shape: lateral_shape(i, a.shape, "an offset")?,
    })
}

/// Event `i`'s speed profile (`profile` given), checked.
fn profile_action(
    i: usize,
    a: &ActionSpec,
    entries: &[super::ProfileEntry],
) -> Result<Action, VehicleError> {
    refuse(
        i,
        "a speed profile (each of its changes has its own timing)",
        &[
            ("duration_s", a.duration_s.is_some()),
            ("rate_mps2", a.rate_mps2.is_some()),
            ("decel_mps2", a.decel_mps2.is_some()),
            ("lateral_speed_mps", a.lateral_speed_mps.is_some()),
            ("lateral_accel_mps2", a.lateral_accel_mps2.is_some()),
            ("shape", a.shape.is_some()),
        ],
    )?;
    if entries.is_empty() || entries.len() > MAX_PROFILE_ENTRIES {
        return Err(invalid(
            i,
            "action.profile",
            format!(
                "holds {} changes: 1 to {MAX_PROFILE_ENTRIES}",
                entries.len()
            ),
        ));
    }
    let checked = entries
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let f = |name: &str| format!("action.profile[{k}].{name}");
            let speed = check(
                i,
                &f("speed_mps"),
                e.speed_mps,
                0.0,
                f64::from(MAX_SPEED_MPS),
                false,
            )?;
            let timing = match (e.duration_s, e.rate_mps2) {
                (Some(d), None) => {
                    Timing::Duration(check(i, &f("duration_s"), d, 0.0, MAX_KEY, false)?)
                }
                (None, Some(r)) => {
                    Timing::Rate(check(i, &f("rate_mps2"), r, 0.0, MAX_RATE_MPS2, true)?)
                }
                _ => {
                    return Err(invalid(
                        i,
                        &format!("action.profile[{k}]"),
                        "a change takes exactly one of duration_s and rate_mps2".into(),
                    ))
                }
            };
            Ok((speed, timing))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Action::Profile(checked))
}

/// The shape of a lateral move (`what`): cubic (the default) or sinusoidal.
fn lateral_shape(i: usize, shape: Option<Shape>, what: &str) -> Result<Shape, VehicleError> {
    match shape {
        None | Some(Shape::Cubic) => Ok(Shape::Cubic),
        Some(Shape::Sinusoidal) => Ok(Shape::Sinusoidal),
        Some(other) => Err(invalid(
            i,
            "action.shape",
            format!(
                "{} is not {what}'s shape (cubic or sinusoidal)",
                other.name()
            ),
        )),
    }
}

/// Event `i`'s speed action (`speed_mps` given), checked.
fn speed_action(i: usize, a: &ActionSpec) -> Result<Action, VehicleError> {
    let f = |name: &str| format!("action.{name}");
    let open = |name: &str, v: f64, max: f64| check(i, &f(name), v, 0.0, max, true);
    refuse(
        i,
        "a speed change",
        &[
            ("lateral_speed_mps", a.lateral_speed_mps.is_some()),
            ("decel_mps2", a.decel_mps2.is_some()),
        ],
    )?;
    let max = f64::from(MAX_SPEED_MPS);
    let (speed_mps, relative) = match (&a.speed_of, a.speed_factor, a.speed_mps) {
        (None, None, Some(v)) if !a.continuous => {
            (check(i, "action.speed_mps", v, 0.0, max, false)?, None)
        }
        (None, _, _) => {
            let given = if a.speed_factor.is_some() {
                "speed_factor"
            } else {
                "continuous"
            };
            return Err(invalid(
                i,
                &format!("action.{given}"),
                "only with speed_of, the vehicle whose speed it is relative to".into(),
            ));
        }
        (Some(of), factor, delta) => {
            if of.trim().is_empty() {
                return Err(invalid(i, "action.speed_of", "must not be empty".into()));
            }
            let value = match (factor, delta) {
                (Some(f), None) => check(i, "action.speed_factor", f, 0.0, 10.0, false)?,
                (None, Some(d)) => check(i, "action.speed_mps", d, -max, max, false)?,
                _ => {
                    return Err(invalid(
                        i,
                        "action",
                        "a speed relative to speed_of takes exactly one of speed_mps (a \
                         difference) and speed_factor"
                            .into(),
                    ))
                }
            };
            let relative = RelativeSpeed {
                of: of.clone(),
                factor: factor.is_some(),
                continuous: a.continuous,
            };
            (value, Some(relative))
        }
    };
    let (timing, shape) = match (a.duration_s, a.rate_mps2, a.shape) {
        (None, None, Some(Shape::Step)) => (Timing::Duration(0.0), Shape::Step),
        (Some(_), _, Some(Shape::Step)) | (_, Some(_), Some(Shape::Step)) => {
            return Err(invalid(
                i,
                "action.shape",
                "a step change takes no time: leave duration_s and rate_mps2 out".into(),
            ))
        }
        (Some(_), Some(_), _) | (None, None, _) => {
            return Err(invalid(
                i,
                "action",
                "a speed change takes exactly one of duration_s and rate_mps2, or \
                 shape = \"step\""
                    .into(),
            ))
        }
        (None, Some(r), None | Some(Shape::Linear)) => (
            Timing::Rate(open("rate_mps2", r, MAX_RATE_MPS2)?),
            Shape::Linear,
        ),
        (None, Some(_), Some(_)) => {
            return Err(invalid(
                i,
                "action.shape",
                "a change at rate_mps2 is linear; give duration_s for a cubic one".into(),
            ))
        }
        (Some(d), None, None | Some(Shape::Linear)) => (
            Timing::Duration(open("duration_s", d, MAX_KEY)?),
            Shape::Linear,
        ),
        (Some(d), None, Some(Shape::Cubic)) => (
            Timing::Duration(open("duration_s", d, MAX_KEY)?),
            Shape::Cubic,
        ),
        (Some(_), None, Some(_)) => {
            return Err(invalid(
                i,
                "action.shape",
                "sinusoidal is not a speed change's shape (linear, cubic or step)".into(),
            ))
        }
    };
    Ok(Action::Speed {
        speed_mps,
        timing,
        shape,
        relative,
    })
}

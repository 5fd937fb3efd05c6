//! `[lead]`: where the lead starts and the speed it is driven at.

use super::{check, short, Blame};
use crate::scenario::{LeadFile, ScenarioError};
use vehicle::{ProfileBasis, SpeedProfile};

/// A speed profile from its file form (`SECTION.speed_basis`, `SECTION.speed_profile`);
/// `Err((field, message))` naming what is wrong.
pub(super) fn speed_profile(
    section: &str,
    basis: &str,
    rows: &[[f64; 2]],
) -> Result<SpeedProfile, (String, String)> {
    let basis = match basis {
        "time" => ProfileBasis::Time,
        "distance" => ProfileBasis::Distance,
        other => {
            return Err((
                format!("{section}.speed_basis"),
                format!("= {other:?}: must be \"time\" or \"distance\""),
            ))
        }
    };
    let field = format!("{section}.speed_profile");
    for [k, v] in rows {
        check(
            k.abs() <= 1e7 && (0.0..=40.0).contains(v),
            "knots are [key, speed_mps] with the key within ±1e7 (s or m) and speed 0–40 m/s",
            format!("[{}, {}]", short(k.to_string()), short(v.to_string())),
        )
        .map_err(|m| (field.clone(), m))?;
    }
    let knots: Vec<(f32, f32)> = rows.iter().map(|[k, v]| (*k as f32, *v as f32)).collect();
    SpeedProfile::new(basis, &knots).map_err(|e| (field, format!(": {e}")))
}

/// The lead's speed profile and its speed at t = 0, m/s, on a route `length` metres long.
pub(super) fn lead(
    l: &LeadFile,
    length: f64,
    f: &Blame,
) -> Result<(SpeedProfile, f64), ScenarioError> {
    f.at(
        "lead.start_m",
        check(
            l.start_m.is_finite() && l.start_m >= 0.0 && l.start_m < length,
            &format!("must lie on the route, 0–{length:.0} m"),
            l.start_m,
        ),
    )?;
    let lead_profile = speed_profile("lead", &l.speed_basis, &l.speed_profile)
        .map_err(|(field, message)| f.invalid(&field, message))?;
    let lead_initial_speed_mps = l
        .initial_speed_mps
        .unwrap_or_else(|| l.speed_profile.first().map_or(0.0, |k| k[1]));
    f.at(
        "lead.initial_speed_mps",
        check(
            lead_initial_speed_mps.is_finite() && (0.0..=40.0).contains(&lead_initial_speed_mps),
            "must be 0–40 m/s",
            lead_initial_speed_mps,
        ),
    )?;

    Ok((lead_profile, lead_initial_speed_mps))
}

//! `[expect]`: the criteria's limits.

use super::{check, short, Blame};
use crate::scenario::{Expect, ScenarioError};

/// Every limit finite and at least 0; a gap band's minimum below its maximum.
pub(super) fn expect(x: &Expect, f: &Blame) -> Result<(), ScenarioError> {
    if let Some([lo, hi]) = x.gap_band_m {
        f.at(
            "expect.gap_band_m",
            check(
                lo.is_finite() && hi.is_finite() && 0.0 <= lo && lo < hi,
                "must be [min, max] metres with 0 ≤ min < max",
                format!("[{}, {}]", short(lo.to_string()), short(hi.to_string())),
            ),
        )?;
    }
    for (field, v) in [
        (
            "expect.max_time_outside_gap_band_s",
            x.max_time_outside_gap_band_s,
        ),
        ("expect.max_lost_s", x.max_lost_s),
        ("expect.max_lateral_deviation_m", x.max_lateral_deviation_m),
        ("expect.min_distance_m", x.min_distance_m),
        ("expect.max_range_error_p95_m", x.max_range_error_p95_m),
        ("expect.max_false_alarm_s", x.max_false_alarm_s),
        ("expect.max_impact_speed_kph", x.max_impact_speed_kph),
        ("expect.min_ttc_s", x.min_ttc_s),
        ("expect.max_wrong_vehicle_s", x.max_wrong_vehicle_s),
        ("expect.max_decel_mps2", x.max_decel_mps2),
        ("expect.max_jerk_mps3", x.max_jerk_mps3),
        ("expect.min_acquisition_range_m", x.min_acquisition_range_m),
    ] {
        if let Some(v) = v {
            f.at(field, check(v.is_finite() && v >= 0.0, "must be ≥ 0", v))?;
        }
    }

    Ok(())
}

//! A road that rises and falls: its height along the station ([`RouteSpec::elevation`],
//! OpenDRIVE's cubic per record) and the ground profile the physics and the terrain share.
//!
//! [`RouteSpec::elevation`]: super::route::RouteSpec::elevation

use super::route::Route;
use super::site::ROAD_RUNOUT_M;
use vehicle::GroundProfile;

/// Spacing of the centreline samples a ground profile carries, metres: between samples the
/// height is linear, off a vertical curve of radius R by 1/(8R) m², 0.1 mm at R = 1 km.
pub const PROFILE_STEP_M: f64 = 1.0;
/// The profile's heightfield cell, metres: twice the wheels' radius (0.47 m) is finer than
/// any change of grade a road's vertical curve makes, and a 1.5 km road with its margins
/// needs about a million points (4 MB of heights).
pub const PROFILE_CELL_M: f32 = 1.0;
/// How far the profile's heightfield reaches beyond the centreline (with its 250 m
/// run-outs), metres: past the grass's 250 m margin and its 25 m cells, so that all the
/// grass lies on it.
pub const PROFILE_MARGIN_M: f32 = 300.0;

/// The record of `records` that holds station `s_m` and how far past its start `s_m` is
/// (the first record before its start, at 0).
fn record_at(records: &[[f64; 5]], s_m: f64) -> ([f64; 5], f64) {
    let k = records.partition_point(|r| r[0] <= s_m).saturating_sub(1);
    let r = records[k];
    (r, (s_m - r[0]).max(0.0))
}

/// The road's height at station `s_m`, metres: `a + b·ds + c·ds² + d·ds³` of the record
/// holding it; 0 without records.
pub fn elevation_at(records: &[[f64; 5]], s_m: f64) -> f64 {
    if records.is_empty() {
        return 0.0;
    }
    let ([_, a, b, c, d], ds) = record_at(records, s_m);
    a + ds * (b + ds * (c + ds * d))
}

/// The road's grade at station `s_m` (rise over run, positive climbing): `b + 2c·ds +
/// 3d·ds²` of the record holding it; 0 without records.
pub fn grade_at(records: &[[f64; 5]], s_m: f64) -> f64 {
    if records.is_empty() {
        return 0.0;
    }
    let ([_, _, b, c, d], ds) = record_at(records, s_m);
    b + ds * (2.0 * c + ds * 3.0 * d)
}

/// The ground profile of `route`'s road: its centreline every [`PROFILE_STEP_M`] from the
/// run-out before its start to the one past its end, each sample at the road's height
/// there (level beyond the ends, at the end's height). `None` when the road is level.
pub fn ground_profile(route: &Route) -> Option<GroundProfile> {
    let records = &route.spec().elevation;
    if records.is_empty() {
        return None;
    }
    let length = route.length_m();
    let n = ((length + 2.0 * ROAD_RUNOUT_M) / PROFILE_STEP_M).ceil() as usize;
    let points = (0..=n)
        .map(|k| {
            let s = (-ROAD_RUNOUT_M + k as f64 * PROFILE_STEP_M).min(length + ROAD_RUNOUT_M);
            let [x, z] = route.point(s, 0.0);
            [x, z, elevation_at(records, s.clamp(0.0, length))]
        })
        .collect();
    Some(GroundProfile {
        points,
        cell_m: PROFILE_CELL_M,
        margin_m: PROFILE_MARGIN_M,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_hold_from_their_station_to_the_next() {
        let r = [[0.0, 1.0, 0.1, 0.0, 0.0], [10.0, 2.0, 0.0, 0.01, -0.001]];
        assert_eq!(elevation_at(&r, 5.0), 1.5);
        assert_eq!(elevation_at(&r, 10.0), 2.0);
        let ds: f64 = 3.0;
        assert!(
            (elevation_at(&r, 13.0) - (2.0 + 0.01 * ds * ds - 0.001 * ds.powi(3))).abs() < 1e-12
        );
        assert!((grade_at(&r, 13.0) - (0.02 * ds - 0.003 * ds * ds)).abs() < 1e-12);
        assert_eq!(elevation_at(&[], 13.0), 0.0);
    }
}

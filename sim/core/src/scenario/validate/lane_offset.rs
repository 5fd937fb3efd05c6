//! `route.lane_offset`: a centre line that lies beside the reference line (OpenDRIVE's
//! `<laneOffset>`), checked so that the road it moves is one the vehicles can drive.

use super::elevation::{checkpoints, records_problem};
use super::MIN_ARC_RADIUS_M;
use sim_render::{elevation_at, grade_at, Route, RouteSpec};

/// The farthest the centre line may lie from the reference line either way, metres: a
/// few lanes' widths, beyond which the reference line is no longer the road's.
pub const MAX_LANE_OFFSET_M: f64 = 25.0;
/// The steepest the lane offset may change along the road, metres sideways a metre: a
/// lane's width over 17.5 m, steeper than any taper a road's lanes shift over (1:15 to
/// 1:50), gentle enough that the vehicles' lanes keep a heading within 11° of the road's.
pub const MAX_LANE_OFFSET_SLOPE: f64 = 0.2;
/// The least the reference line's curvature κ may leave of the centre line's length,
/// `1 − κ·offset`: the centre line never folds back on itself inside a tight curve.
const MIN_STRETCH: f64 = 0.5;
/// Spacing of the stations the offset is checked at, metres.
const CHECK_M: f64 = 0.25;

/// What is wrong with the lane offset of `spec` (its records `spec.lane_offset`), if
/// anything: the index of the record to blame and what to say. The records in order as
/// `route.elevation`'s ([`records_problem`]); and at every [`CHECK_M`] (and every record's
/// end) the offset within ±[`MAX_LANE_OFFSET_M`], its slope within
/// ±[`MAX_LANE_OFFSET_SLOPE`], `1 − κ·offset` at least [`MIN_STRETCH`], and the centre
/// line's curvature at most 1/[`MIN_ARC_RADIUS_M`], as every piece of a route.
pub(crate) fn lane_offset_problem(spec: &RouteSpec) -> Option<(usize, String)> {
    let records = &spec.lane_offset;
    if records.is_empty() {
        return None;
    }
    let route = Route::new(spec.clone());
    let length_m = route.length_m();
    if let Some(problem) = records_problem(records, length_m) {
        return Some(problem);
    }
    for (s, k, held) in checkpoints(records, length_m, CHECK_M) {
        let (o, slope) = (elevation_at(held, s), grade_at(held, s));
        if o.abs() > MAX_LANE_OFFSET_M {
            return Some((
                k,
                format!(
                    "the offset at station {s:.2} m is {o:.2} m: at most {MAX_LANE_OFFSET_M} m \
                     either way"
                ),
            ));
        }
        if slope.abs() > MAX_LANE_OFFSET_SLOPE {
            return Some((
                k,
                format!(
                    "the offset changes by {slope:.3} m a metre at station {s:.2} m: at most \
                     {MAX_LANE_OFFSET_SLOPE} either way, as lanes shift along a road"
                ),
            ));
        }
        let stretch = 1.0 - route.reference_curvature_at(s) * o;
        if stretch < MIN_STRETCH {
            return Some((
                k,
                format!(
                    "the offset of {o:.2} m at station {s:.2} m lies too far inside the curve \
                     there (1 − curvature × offset = {stretch:.2}, at least {MIN_STRETCH})"
                ),
            ));
        }
        let curvature = route.curvature_at(s);
        if curvature.abs() > 1.0 / MIN_ARC_RADIUS_M {
            return Some((
                k,
                format!(
                    "it bends the centre line to a radius of {:.1} m at station {s:.2} m: at \
                     least {MIN_ARC_RADIUS_M} m (the vehicles' turning circles)",
                    1.0 / curvature.abs()
                ),
            ));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use sim_render::RouteSegment;

    fn spec(lane_offset: Vec<[f64; 5]>) -> RouteSpec {
        RouteSpec {
            segments: vec![
                RouteSegment::Straight { length_m: 100.0 },
                RouteSegment::Arc {
                    radius_m: 20.0,
                    angle_deg: 90.0,
                },
            ],
            intersections_m: vec![],
            lane_width_m: 3.5,
            lanes: 1,
            elevation: Vec::new(),
            median_m: 0.0,
            lane_widths_m: Vec::new(),
            lane_offset,
        }
    }

    #[test]
    fn a_drivable_offset_passes_and_bad_ones_say_why() {
        assert_eq!(lane_offset_problem(&spec(Vec::new())), None);
        // 1.75 m to the left over the straight's last 50 m (a cubic taper), then constant.
        let taper = [
            [0.0, 0.0, 0.0, 0.0, 0.0],
            [50.0, 0.0, 0.0, 0.0021, -0.000028],
            [100.0, 1.75, 0.0, 0.0, 0.0],
        ];
        assert_eq!(lane_offset_problem(&spec(taper.to_vec())), None);
        let cases: [(Vec<[f64; 5]>, usize, &str); 5] = [
            (vec![[1.0, 0.0, 0.0, 0.0, 0.0]], 0, "station 0"),
            (vec![[0.0, 30.0, 0.0, 0.0, 0.0]], 0, "at most 25 m"),
            (vec![[0.0, 0.0, 0.3, 0.0, 0.0]], 0, "changes by 0.300"),
            // 12 m to the left inside a 20 m left curve: 1 − 12/20 = 0.4.
            (
                vec![[0.0, 12.0, 0.0, 0.0, 0.0]],
                0,
                "too far inside the curve",
            ),
            (
                vec![[0.0, 0.0, 0.0, 0.0, 0.0], [50.0, 1.0, 0.0, 0.0, 0.0]],
                1,
                "a step",
            ),
        ];
        for (records, blamed, says) in cases {
            let (i, message) = lane_offset_problem(&spec(records.clone())).expect("refused");
            assert_eq!(i, blamed, "{records:?}: {message}");
            assert!(message.contains(says), "{records:?}: {message}");
        }
    }

    #[test]
    fn a_centre_line_bent_tighter_than_a_vehicle_turns_is_refused() {
        // A wiggle of 0.15 m over 6 m on the straight: a slope of at most 0.157, within
        // bounds, but a curvature of up to 0.15·(2π/6)² = 0.164, radii down to 6.1 m. Each
        // record is the wiggle's cubic about its start.
        let k = std::f64::consts::TAU / 6.0;
        let a = 0.15;
        let wiggle: Vec<[f64; 5]> = (0..=200)
            .map(|i| {
                let s = 0.25 * f64::from(i);
                let (sin, cos) = (k * s).sin_cos();
                [
                    s,
                    a * sin,
                    a * k * cos,
                    -a * k * k * sin / 2.0,
                    -a * k * k * k * cos / 6.0,
                ]
            })
            .collect();
        let (_, message) = lane_offset_problem(&spec(wiggle)).expect("refused");
        assert!(
            message.contains("radius of") && message.contains("at least 8 m"),
            "{message}"
        );
    }
}

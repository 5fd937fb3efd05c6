//! `route.elevation`: a road that rises and falls, checked so that the vehicles can drive it.

use sim_render::{elevation_at, grade_at};

/// Steepest grade a profile may have, rise over run: 20 %, steeper than any regular road
/// (motorways stay under 6–7 %, mountain passes under 15 %, the steepest streets near 35 %
/// are one-offs); the vehicles' speed controllers, tuned on level ground, hold their speed up
/// such a slope with the engines' force to spare.
pub const MAX_GRADE: f64 = 0.2;
/// Largest height a profile may reach either way, metres: 10 km, beyond any road on Earth.
pub const MAX_HEIGHT_M: f64 = 10_000.0;
/// Largest step where a record meets the one before, metres: 1 cm, below what the wheels
/// (0.47 m radius) feel; a larger step would be a kerb across the road.
pub const MAX_STEP_M: f64 = 0.01;
/// Spacing of the stations the grade and height are checked at, metres.
const GRADE_CHECK_M: f64 = 0.25;

/// What is wrong with the profile `records` of a route `length_m` long, if anything: the
/// index of the record to blame and what to say. Each record's numbers finite, the first at
/// station 0, stations increasing and before the route's end, no step where records meet,
/// and at every [`GRADE_CHECK_M`] (and every record's end) the grade within ±[`MAX_GRADE`]
/// and the height within ±[`MAX_HEIGHT_M`].
pub(crate) fn elevation_problem(records: &[[f64; 5]], length_m: f64) -> Option<(usize, String)> {
    if records.is_empty() {
        return None;
    }
    if let Some(problem) = records_problem(records, length_m) {
        return Some(problem);
    }
    for (s, k, held) in checkpoints(records, length_m, GRADE_CHECK_M) {
        let [g, h] = [grade_at(held, s), elevation_at(held, s)];
        if g.abs() > MAX_GRADE {
            return Some((
                k,
                format!(
                    "its grade at station {s:.2} m is {:.1} %: at most {:.0} % either way, as \
                     a road the vehicles drive",
                    100.0 * g,
                    100.0 * MAX_GRADE
                ),
            ));
        }
        if h.abs() > MAX_HEIGHT_M {
            return Some((
                k,
                format!("its height at station {s:.2} m is {h:.0} m: at most {MAX_HEIGHT_M} m either way"),
            ));
        }
    }
    None
}

/// The stations cubic `records` along a route `length_m` long are checked at: every
/// `step_m` from its start to its end, then each record's end; with each, the index of the
/// record to blame and the records to evaluate there (at a record's end, that record and
/// those before it, so the end is judged on its own cubic).
pub(crate) fn checkpoints(
    records: &[[f64; 5]],
    length_m: f64,
    step_m: f64,
) -> impl Iterator<Item = (f64, usize, &[[f64; 5]])> + '_ {
    let n = (length_m / step_m).ceil() as usize;
    let grid = (0..=n).map(move |k| {
        let s = (k as f64 * step_m).min(length_m);
        let blame = records.partition_point(|r| r[0] <= s).saturating_sub(1);
        (s, blame, records)
    });
    let ends = records
        .iter()
        .skip(1)
        .map(|r| r[0])
        .chain([length_m])
        .enumerate()
        .map(|(i, s)| (s, i, &records[..=i]));
    grid.chain(ends)
}

/// What is wrong with the order of cubic `records` (`[s_m, a, b, c, d]`) along a route
/// `length_m` long, if anything (the index of the record to blame and what to say): each
/// record's numbers finite, the first at station 0, stations increasing and before the
/// route's end, and no step of more than [`MAX_STEP_M`] where a record meets the one before.
/// The rule `route.elevation` and `route.lane_offset` share.
pub(crate) fn records_problem(records: &[[f64; 5]], length_m: f64) -> Option<(usize, String)> {
    for (i, r) in records.iter().enumerate() {
        if !r.iter().all(|v| v.is_finite()) {
            return Some((i, "its numbers must be finite".into()));
        }
        if i == 0 && r[0] != 0.0 {
            return Some((
                i,
                format!("the first record must start at station 0, not {}", r[0]),
            ));
        }
        if i > 0 && r[0] <= records[i - 1][0] {
            return Some((
                i,
                format!("its station {} must be after the one before's", r[0]),
            ));
        }
        if r[0] >= length_m && i > 0 {
            return Some((
                i,
                format!(
                    "its station {} must be before the route's end ({length_m:.1} m)",
                    r[0]
                ),
            ));
        }
        if i > 0 {
            let before = elevation_at(&records[..i], r[0]);
            if (before - r[1]).abs() > MAX_STEP_M {
                return Some((
                    i,
                    format!(
                        "it starts at {:.3} m where the one before ends at {before:.3} m: a step \
                         of more than {MAX_STEP_M} m",
                        r[1]
                    ),
                ));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_drivable_profile_passes_and_bad_ones_say_why() {
        let good = [[0.0, 0.0, 0.05, 0.0, 0.0], [100.0, 5.0, 0.05, -0.0005, 0.0]];
        assert_eq!(elevation_problem(&good, 300.0), None);
        let cases: [(&[[f64; 5]], usize, &str); 5] = [
            (&[[1.0, 0.0, 0.0, 0.0, 0.0]], 0, "station 0"),
            (
                &[[0.0, 0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0, 0.0]],
                1,
                "after",
            ),
            (&[[0.0, 0.0, 0.3, 0.0, 0.0]], 0, "grade"),
            (
                &[[0.0, 0.0, 0.0, 0.0, 0.0], [50.0, 0.5, 0.0, 0.0, 0.0]],
                1,
                "step",
            ),
            (&[[0.0, f64::NAN, 0.0, 0.0, 0.0]], 0, "finite"),
        ];
        for (records, index, word) in cases {
            let (i, message) = elevation_problem(records, 300.0).expect("refused");
            assert_eq!(i, index, "{message}");
            assert!(message.contains(word), "{message}");
        }
        // A cubic whose grade passes the limit between records' stations is found.
        let (_, m) = elevation_problem(&[[0.0, 0.0, 0.0, 0.001, 0.0]], 300.0).unwrap();
        assert!(m.contains("grade at station 100.2"), "{m}");
    }
}

//! A road's lanes as carfollow's `lanes` and `lane_width_m`: the driving lanes on the
//! right (ids −1, −2, ...) of constant, equal width, the left side mirroring them, in every
//! lane section alike.

use super::model::{Lane, LaneSection, Road};
use super::OpenDriveError;
use sim_render::RouteSpec;
use std::path::Path;

/// Narrowest and widest lane carfollow draws, metres (`route.lane_width_m`'s bounds).
const LANE_WIDTH_M: [f64; 2] = [2.0, 6.0];

/// `(lanes, lane_width_m)` of `road`, the same in every lane section.
pub(super) fn lanes(road: &Road, path: &Path) -> Result<(u32, f64), OpenDriveError> {
    let Some(first) = road.lane_sections.first() else {
        return Err(road.at.refuse(path, "the road has no lane section"));
    };
    let wanted = section(first, path)?;
    for s in &road.lane_sections[1..] {
        let got = section(s, path)?;
        if got != wanted {
            return Err(s.at.refuse(
                path,
                format!(
                    "its lanes ({} of {} m) differ from the first section's ({} of {} m): \
                     carfollow's road keeps its lanes along its length",
                    got.0, got.1, wanted.0, wanted.1
                ),
            ));
        }
    }
    Ok(wanted)
}

/// One section's `(lanes, width)`.
fn section(s: &LaneSection, path: &Path) -> Result<(u32, f64), OpenDriveError> {
    if s.single_side {
        return Err(s.at.refuse(path, "single-sided lane sections are refused"));
    }
    let Some(right) = side(&s.right, -1, path)? else {
        return Err(s.at.refuse(
            path,
            "no driving lane −1 on the right: carfollow drives on the right",
        ));
    };
    let Some(left) = side(&s.left, 1, path)? else {
        return Err(s.at.refuse(
            path,
            "no driving lane 1 on the left: one-way roads are refused (carfollow's road has \
             the same lanes each way)",
        ));
    };
    if left != right {
        return Err(s.at.refuse(
            path,
            format!(
                "the left's driving lanes ({} of {} m) differ from the right's ({} of {} m): \
                 carfollow's oncoming side mirrors its own",
                left.0, left.1, right.0, right.1
            ),
        ));
    }
    Ok(right)
}

/// The driving lanes of one side, counted out from the centre (`sign` the ids' sign):
/// `None` when lane ±1 is not a driving lane.
fn side(lanes: &[Lane], sign: i32, path: &Path) -> Result<Option<(u32, f64)>, OpenDriveError> {
    let mut sorted: Vec<&Lane> = lanes.iter().collect();
    sorted.sort_by_key(|l| l.id.abs());
    let (mut count, mut width) = (0u32, None::<f64>);
    let mut beyond = false;
    for (k, lane) in sorted.iter().enumerate() {
        if lane.id != sign * (k as i32 + 1) {
            return Err(lane.at.refuse(
                path,
                format!(
                    "expected lane id {} here: ids count out from the centre",
                    sign * (k as i32 + 1)
                ),
            ));
        }
        if lane.kind != "driving" {
            beyond = true;
            continue;
        }
        if beyond {
            return Err(lane.at.refuse(
                path,
                "a driving lane beyond a lane of another type is refused: carfollow's lanes lie \
                 side by side from the centre line",
            ));
        }
        let w = constant_width(lane, path)?;
        if let Some(first) = width {
            if w != first {
                return Err(lane.at.refuse(
                    path,
                    format!("its width {w} m differs from lane {}'s {first} m: carfollow's lanes are of one width", sign),
                ));
            }
        }
        width = Some(w);
        count += 1;
    }
    if count > RouteSpec::MAX_LANES {
        return Err(sorted[0].at.refuse(
            path,
            format!(
                "{count} driving lanes on one side: at most {}",
                RouteSpec::MAX_LANES
            ),
        ));
    }
    Ok(width.map(|w| (count, w)))
}

/// A driving lane's width, constant along the road (`b = c = d = 0` in every record, one
/// value of `a`) and within carfollow's bounds.
fn constant_width(lane: &Lane, path: &Path) -> Result<f64, OpenDriveError> {
    let Some(first) = lane.widths.first() else {
        return Err(lane.at.refuse(path, "a driving lane needs a width"));
    };
    let w = first.coefficients[0];
    for r in &lane.widths {
        let [a, b, c, d] = r.coefficients;
        if b != 0.0 || c != 0.0 || d != 0.0 || a != w {
            return Err(r.at.refuse(
                path,
                "lane widths that vary along the road are refused: carfollow's lanes keep one width",
            ));
        }
    }
    if !(LANE_WIDTH_M[0]..=LANE_WIDTH_M[1]).contains(&w) {
        return Err(first.at.refuse(
            path,
            format!(
                "a width of {w} m: carfollow's lanes are {}–{} m wide",
                LANE_WIDTH_M[0], LANE_WIDTH_M[1]
            ),
        ));
    }
    Ok(w)
}

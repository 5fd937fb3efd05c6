//! A road's lanes as carfollow's `lanes`, `lane_width_m`, `lane_widths_m` and `median_m`:
//! on the right (ids −1, −2, ...) the non-driving lanes next to the centre (border, median,
//! shoulder, any type but `driving`) make the median, then the driving lanes, each of one
//! constant width, then anything but driving lanes; the left side mirrors the right, in
//! every lane section alike.

use super::model::{Lane, LaneSection, Road};
use super::OpenDriveError;
use sim_render::RouteSpec;
use std::path::Path;

/// Narrowest and widest lane carfollow draws, metres (`route.lane_width_m`'s bounds).
const LANE_WIDTH_M: [f64; 2] = [2.0, 6.0];
/// The widest median carfollow draws, metres (`route.median_m`'s bound).
const MAX_MEDIAN_M: f64 = 10.0;

/// One side's lanes as carfollow draws them.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Layout {
    /// Driving lanes.
    pub lanes: u32,
    /// Lane 1's width, metres (every lane's when `lane_widths_m` is empty).
    pub lane_width_m: f64,
    /// Each driving lane's width, metres, from the centre out, when they differ; else empty.
    pub lane_widths_m: Vec<f64>,
    /// The non-driving lanes inside the driving lanes together, metres.
    pub median_m: f64,
    /// How many lanes those are.
    pub inner_lanes: u32,
}

impl std::fmt::Display for Layout {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.lane_widths_m.is_empty() {
            write!(f, "{} of {} m", self.lanes, self.lane_width_m)?;
        } else {
            let widths: Vec<String> = self.lane_widths_m.iter().map(|w| w.to_string()).collect();
            write!(f, "{} of {} m", self.lanes, widths.join(", "))?;
        }
        if self.median_m != 0.0 {
            write!(f, " beyond {} m of other lanes", self.median_m)?;
        }
        Ok(())
    }
}

/// The lanes of `road`, the same in every lane section.
pub(super) fn lanes(road: &Road, path: &Path) -> Result<Layout, OpenDriveError> {
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
                    "its lanes ({got}) differ from the first section's ({wanted}): \
                     carfollow's road keeps its lanes along its length"
                ),
            ));
        }
    }
    Ok(wanted)
}

/// One section's lanes.
fn section(s: &LaneSection, path: &Path) -> Result<Layout, OpenDriveError> {
    if s.single_side {
        return Err(s.at.refuse(path, "single-sided lane sections are refused"));
    }
    let Some(right) = side(&s.right, -1, path)? else {
        return Err(s.at.refuse(
            path,
            "no driving lane on the right: carfollow drives on the right",
        ));
    };
    let Some(left) = side(&s.left, 1, path)? else {
        return Err(s.at.refuse(
            path,
            "no driving lane on the left: one-way roads are refused (carfollow's road has \
             the same lanes each way)",
        ));
    };
    if left != right {
        return Err(s.at.refuse(
            path,
            format!(
                "the left's driving lanes ({left}) differ from the right's ({right}): \
                 carfollow's oncoming side mirrors its own"
            ),
        ));
    }
    Ok(right)
}

/// The lanes of one side, counted out from the centre (`sign` the ids' sign): `None` when
/// the side has no driving lane.
fn side(lanes: &[Lane], sign: i32, path: &Path) -> Result<Option<Layout>, OpenDriveError> {
    let mut sorted: Vec<&Lane> = lanes.iter().collect();
    sorted.sort_by_key(|l| l.id.abs());
    let mut widths: Vec<f64> = Vec::new();
    let (mut median_m, mut inner_lanes) = (0.0, 0u32);
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
            if widths.is_empty() {
                // Inside the driving lanes: part of the median.
                median_m += constant_width(lane, path)?;
                inner_lanes += 1;
                if median_m > MAX_MEDIAN_M {
                    return Err(lane.at.refuse(
                        path,
                        format!(
                            "the lanes inside the driving lanes make a median of {median_m} m: \
                             carfollow's median is at most {MAX_MEDIAN_M} m"
                        ),
                    ));
                }
            } else {
                beyond = true;
            }
            continue;
        }
        if beyond {
            return Err(lane.at.refuse(
                path,
                "a driving lane beyond the driving lanes' outer edge (past a lane of another \
                 type) is refused: carfollow's lanes lie side by side",
            ));
        }
        widths.push(driving_width(lane, path)?);
    }
    let count = widths.len() as u32;
    if count > RouteSpec::MAX_LANES {
        return Err(sorted[0].at.refuse(
            path,
            format!(
                "{count} driving lanes on one side: at most {}",
                RouteSpec::MAX_LANES
            ),
        ));
    }
    let Some(&first) = widths.first() else {
        return Ok(None);
    };
    let one_width = widths.iter().all(|&w| w == first);
    Ok(Some(Layout {
        lanes: count,
        lane_width_m: first,
        lane_widths_m: if one_width { Vec::new() } else { widths },
        median_m,
        inner_lanes,
    }))
}

/// A driving lane's width: constant along the road and within carfollow's bounds.
fn driving_width(lane: &Lane, path: &Path) -> Result<f64, OpenDriveError> {
    let w = constant_width(lane, path)?;
    if !(LANE_WIDTH_M[0]..=LANE_WIDTH_M[1]).contains(&w) {
        return Err(lane.widths[0].at.refuse(
            path,
            format!(
                "a width of {w} m: carfollow's lanes are {}–{} m wide",
                LANE_WIDTH_M[0], LANE_WIDTH_M[1]
            ),
        ));
    }
    Ok(w)
}

/// A lane's width, constant along the road (`b = c = d = 0` in every record, one value of
/// `a`, at least 0).
fn constant_width(lane: &Lane, path: &Path) -> Result<f64, OpenDriveError> {
    let Some(first) = lane.widths.first() else {
        return Err(lane
            .at
            .refuse(path, format!("a {} lane needs a width", lane.kind)));
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
    if !(w.is_finite() && w >= 0.0) {
        return Err(first.at.refuse(path, format!("a width of {w} m")));
    }
    Ok(w)
}

//! Where a whole-image search may lock on: the image positions a target's centre may take
//! at each scale.
//!
//! Not in the paper, whose start was a person's (2.2). A follower in traffic knows where
//! its own lane lies ahead and where the road is; a target's scale gives its range
//! (eq. 36), and its range gives the columns the lane covers there and the rows a vehicle's
//! back on that road can take. Robust mode's whole-image search
//! ([`crate::Tracker::set_acquire_gate`]) then keeps only fits inside them, so that it
//! acquires the vehicle in the lane rather than the best-fitting one beside it, and scores
//! only the positions a vehicle on the road can take.

use crate::location::Location;

/// The centres a target may take at one scale: columns and rows, pixels, inclusive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GateRow {
    /// The target's scale.
    pub scale: f64,
    /// The least and greatest image x of its centre.
    pub c_x: [f64; 2],
    /// The least and greatest image y of its centre.
    pub c_y: [f64; 2],
}

impl GateRow {
    /// Whether every value is finite, the scale positive and each range in order.
    fn is_valid(&self) -> bool {
        let values = [
            self.scale,
            self.c_x[0],
            self.c_x[1],
            self.c_y[0],
            self.c_y[1],
        ];
        values.iter().all(|v| v.is_finite())
            && self.scale > 0.0
            && self.c_x[0] <= self.c_x[1]
            && self.c_y[0] <= self.c_y[1]
    }
}

/// The image positions a target's centre may take, by scale: a list of [`GateRow`]s,
/// interpolated linearly in scale. No scale outside the list's range is admitted.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AcquireGate {
    rows: Vec<GateRow>,
}

impl AcquireGate {
    /// The gate of these rows, in any order. Rows with a value that is not finite, a scale
    /// that is not positive, or a range out of order are left out; a gate of no rows admits
    /// nothing.
    pub fn new(mut rows: Vec<GateRow>) -> AcquireGate {
        rows.retain(GateRow::is_valid);
        rows.sort_by(|a, b| a.scale.total_cmp(&b.scale));
        AcquireGate { rows }
    }

    /// The gate of the columns `[lo, hi]` at every scale in `scales`, any row.
    pub fn columns(lo: f64, hi: f64, scales: [f64; 2]) -> AcquireGate {
        let row = |scale| GateRow {
            scale,
            c_x: [lo, hi],
            c_y: [f64::MIN, f64::MAX],
        };
        AcquireGate::new(vec![row(scales[0]), row(scales[1])])
    }

    /// The rows kept, by increasing scale.
    pub fn rows(&self) -> &[GateRow] {
        &self.rows
    }

    /// The centres admitted at `scale`, `[[cx_min, cx_max], [cy_min, cy_max]]`, if the
    /// scale is in range.
    pub fn centres(&self, scale: f64) -> Option<[[f64; 2]; 2]> {
        let first = self.rows.first()?;
        let last = self.rows.last()?;
        if !(scale >= first.scale && scale <= last.scale) {
            return None;
        }
        let i = self.rows.partition_point(|r| r.scale < scale);
        if i == 0 {
            return Some([first.c_x, first.c_y]);
        }
        let (a, b) = (self.rows[i - 1], self.rows[i]);
        let t = if b.scale > a.scale {
            (scale - a.scale) / (b.scale - a.scale)
        } else {
            1.0
        };
        let lerp = |p: [f64; 2], q: [f64; 2]| [0, 1].map(|k| p[k] + t * (q[k] - p[k]));
        Some([lerp(a.c_x, b.c_x), lerp(a.c_y, b.c_y)])
    }

    /// Whether a target centred at `at` lies inside the gate.
    pub fn admits(&self, at: Location) -> bool {
        self.centres(at.scale).is_some_and(|[x, y]| {
            at.c_x >= x[0] && at.c_x <= x[1] && at.c_y >= y[0] && at.c_y <= y[1]
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(scale: f64, c_x: [f64; 2], c_y: [f64; 2]) -> GateRow {
        GateRow { scale, c_x, c_y }
    }

    #[test]
    fn interpolates_between_scales_and_refuses_outside_them() {
        let gate = AcquireGate::new(vec![
            row(2.0, [100.0, 160.0], [80.0, 120.0]),
            row(1.0, [110.0, 150.0], [100.0, 110.0]),
        ]);
        assert_eq!(gate.centres(1.0), Some([[110.0, 150.0], [100.0, 110.0]]));
        assert_eq!(gate.centres(1.5), Some([[105.0, 155.0], [90.0, 115.0]]));
        assert_eq!(gate.centres(0.9), None);
        assert_eq!(gate.centres(2.1), None);
        assert!(gate.admits(Location::new(102.0, 100.0, 1.9)));
        assert!(!gate.admits(Location::new(102.0, 100.0, 1.1)));
        assert!(!gate.admits(Location::new(130.0, 70.0, 1.5)));
        assert!(!gate.admits(Location::new(130.0, 121.0, 1.5)));
        assert!(!gate.admits(Location::new(130.0, 100.0, f64::NAN)));
    }

    #[test]
    fn drops_rows_that_are_not_ranges() {
        let gate = AcquireGate::new(vec![
            row(1.0, [10.0, 5.0], [0.0, 1.0]),
            row(1.0, [0.0, 1.0], [3.0, 1.0]),
            row(f64::NAN, [0.0, 1.0], [0.0, 1.0]),
            row(0.0, [0.0, 1.0], [0.0, 1.0]),
            row(1.0, [0.0, 1.0], [0.0, 1.0]),
        ]);
        assert_eq!(gate.rows(), &[row(1.0, [0.0, 1.0], [0.0, 1.0])]);
        assert!(!AcquireGate::default().admits(Location::new(0.0, 0.0, 1.0)));
    }

    #[test]
    fn a_gate_of_columns_admits_any_row() {
        let gate = AcquireGate::columns(10.0, 20.0, [0.5, 2.0]);
        assert!(gate.admits(Location::new(15.0, -1e9, 0.5)));
        assert!(gate.admits(Location::new(15.0, 1e9, 2.0)));
        assert!(!gate.admits(Location::new(21.0, 0.0, 1.0)));
    }
}

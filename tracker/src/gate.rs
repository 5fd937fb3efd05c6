//! Where a whole-image search may lock on: the image columns a target's centre may take
//! at each scale.
//!
//! Not in the paper, whose start was a person's (2.2). A follower in traffic knows where
//! its own lane lies ahead; a target's scale gives its range (eq. 36), and its range gives
//! the columns the lane covers there. Robust mode's whole-image search
//! ([`crate::Tracker::set_acquire_gate`]) then keeps only fits inside them, so that it
//! acquires the vehicle in the lane rather than the best-fitting one beside it.

use crate::location::Location;

/// The image columns a target's centre may take, by scale: a list of `[scale, cx_min,
/// cx_max]` (pixels), interpolated linearly in scale. No scale outside the list's range
/// is admitted.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AcquireGate {
    rows: Vec<[f64; 3]>,
}

impl AcquireGate {
    /// The gate of these `[scale, cx_min, cx_max]` rows, in any order. Rows with a value
    /// that is not finite, a scale that is not positive, or `cx_min > cx_max` are left
    /// out; a gate of no rows admits nothing.
    pub fn new(mut rows: Vec<[f64; 3]>) -> AcquireGate {
        rows.retain(|r| r.iter().all(|v| v.is_finite()) && r[0] > 0.0 && r[1] <= r[2]);
        rows.sort_by(|a, b| a[0].total_cmp(&b[0]));
        AcquireGate { rows }
    }

    /// The rows kept, by increasing scale.
    pub fn rows(&self) -> &[[f64; 3]] {
        &self.rows
    }

    /// The columns admitted at `scale`, `[cx_min, cx_max]`, if the scale is in range.
    pub fn columns(&self, scale: f64) -> Option<[f64; 2]> {
        let first = self.rows.first()?;
        let last = self.rows.last()?;
        if !(scale >= first[0] && scale <= last[0]) {
            return None;
        }
        let i = self.rows.partition_point(|r| r[0] < scale);
        if i == 0 {
            return Some([first[1], first[2]]);
        }
        let (a, b) = (self.rows[i - 1], self.rows[i]);
        let t = if b[0] > a[0] {
            (scale - a[0]) / (b[0] - a[0])
        } else {
            1.0
        };
        Some([a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])])
    }

    /// Whether a target centred at `at` lies inside the gate.
    pub fn admits(&self, at: Location) -> bool {
        self.columns(at.scale)
            .is_some_and(|[lo, hi]| at.c_x >= lo && at.c_x <= hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_between_scales_and_refuses_outside_them() {
        let gate = AcquireGate::new(vec![[2.0, 100.0, 160.0], [1.0, 110.0, 150.0]]);
        assert_eq!(gate.columns(1.0), Some([110.0, 150.0]));
        assert_eq!(gate.columns(1.5), Some([105.0, 155.0]));
        assert_eq!(gate.columns(0.9), None);
        assert_eq!(gate.columns(2.1), None);
        assert!(gate.admits(Location::new(102.0, 50.0, 1.9)));
        assert!(!gate.admits(Location::new(102.0, 50.0, 1.1)));
        assert!(!gate.admits(Location::new(130.0, 50.0, f64::NAN)));
    }

    #[test]
    fn drops_rows_that_are_not_columns() {
        let gate = AcquireGate::new(vec![
            [1.0, 10.0, 5.0],
            [f64::NAN, 0.0, 1.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
        ]);
        assert_eq!(gate.rows(), &[[1.0, 0.0, 1.0]]);
        assert!(!AcquireGate::default().admits(Location::new(0.0, 0.0, 1.0)));
    }
}

//! A held target that closes on the chase faster than the chase drives is not the target.
//!
//! Not in the paper. A vehicle ahead can come towards the chase no faster than the chase
//! drives towards it: none drives backwards, and one that brakes only stops. So over a few
//! frames the range to what is held can shrink by the chase's own travel and no more. A fit
//! whose estimated range shrinks much faster has slid off the target onto something that
//! only looks nearer: the model's outline over a larger outline about the target (the
//! lead's whole back about a board too small to resolve, a van cutting in over the board
//! held), fitted at a larger scale. The tracker's own status cannot see it (the fit lies on
//! strong edges); the chase's odometer can. Measured on the frames of 114 runs (the library
//! but `tape-17min`, and 58 Euro NCAP car-to-car rear runs, both modes): of about 58,500
//! frames held on the target, the most any closed beyond the chase's travel over
//! [`WINDOW_FRAMES`] frames is 0.115 of the range; every frame past [`EXCESS_OF_RANGE`] was
//! held off the target.

/// How many frame intervals the closing is measured over: 0.2 s at 15 Hz, long enough for
/// a slide of the fit to add up, short enough to catch it before the chase brakes for it.
pub const WINDOW_FRAMES: usize = 3;

/// How much faster than the chase's travel the range may shrink over the window, as a
/// share of the range at its start: the estimate's noise at long range and the chase's
/// speed changing within the window, with room to spare (see the module's figures).
pub const EXCESS_OF_RANGE: f64 = 0.2;

/// The last frames' estimated ranges to the target held, with the chase's speed at each.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Closing {
    /// `(time s, estimated range m, chase speed m/s)`, oldest first, `len` of them.
    samples: [(f64, f64, f64); WINDOW_FRAMES + 1],
    len: usize,
}

impl Closing {
    /// Forgets every frame: a new target is held, or the speed is not known.
    pub(crate) fn clear(&mut self) {
        self.len = 0;
    }

    /// Adds a frame's estimate (`range_m` at `t_s`, the chase at `speed_mps`) and says
    /// whether the range, over the last [`WINDOW_FRAMES`] intervals, shrank by more than
    /// the chase's travel at its fastest in them plus [`EXCESS_OF_RANGE`] of the range.
    /// Values that are not finite, or a range not ahead, forget the frames before.
    pub(crate) fn too_fast(&mut self, t_s: f64, range_m: f64, speed_mps: f64) -> bool {
        if !(t_s.is_finite() && range_m.is_finite() && range_m > 0.0 && speed_mps.is_finite()) {
            self.clear();
            return false;
        }
        if self.len == self.samples.len() {
            self.samples.copy_within(1.., 0);
            self.len -= 1;
        }
        self.samples[self.len] = (t_s, range_m, speed_mps);
        self.len += 1;
        if self.len < self.samples.len() {
            return false;
        }
        let (t0, r0, _) = self.samples[0];
        let (t1, r1, _) = self.samples[self.len - 1];
        let fastest = self.samples.iter().map(|s| s.2.abs()).fold(0.0, f64::max);
        r0 - r1 > fastest * (t1 - t0) + EXCESS_OF_RANGE * r0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f64 = 1.0 / 15.0;

    /// Feeds ranges a frame apart at a steady speed; the frames said too fast.
    fn flagged(ranges: &[f64], speed_mps: f64) -> Vec<usize> {
        let mut c = Closing::default();
        (0..ranges.len())
            .filter(|&k| c.too_fast(k as f64 * DT, ranges[k], speed_mps))
            .collect()
    }

    #[test]
    fn closing_at_the_chase_speed_or_slower_is_never_too_fast() {
        // The chase at 20 m/s on a standing car from 60 m: exactly its travel.
        let ranges: Vec<f64> = (0..40).map(|k| 60.0 - 20.0 * DT * k as f64).collect();
        assert!(flagged(&ranges, 20.0).is_empty());
        // A lead drawing away, and one held at a steady gap.
        let away: Vec<f64> = (0..40).map(|k| 10.0 + 0.5 * k as f64).collect();
        assert!(flagged(&away, 15.0).is_empty());
        assert!(flagged(&[10.0; 40], 15.0).is_empty());
    }

    #[test]
    fn a_fit_sliding_to_a_larger_scale_is_caught_within_the_window() {
        // The estimate of a board 50 m ahead slides to 30 m in two frames, the chase at
        // 15 m/s (1 m a frame): caught at the second frame of the slide, the first whose
        // window holds more than the travel and a fifth of the range.
        let ranges = [50.0, 49.0, 48.0, 47.0, 46.0, 38.0, 31.0, 30.0, 29.0];
        assert_eq!(flagged(&ranges, 15.0).first(), Some(&6));
        // At the bound: 3 m of travel over the window and the excess on 50 m.
        let r0 = 50.0;
        let at = |extra: f64| {
            [
                r0,
                r0 - 1.0,
                r0 - 2.0,
                r0 - 3.0 - EXCESS_OF_RANGE * r0 - extra,
            ]
        };
        assert!(flagged(&at(-0.01), 15.0).is_empty());
        assert_eq!(flagged(&at(0.01), 15.0), vec![3]);
    }

    #[test]
    fn the_fastest_speed_in_the_window_counts_and_bad_values_forget() {
        let mut c = Closing::default();
        // The chase braking from 30 to 0 m/s: its travel at 30 m/s counts.
        for (k, (r, v)) in [(40.0, 30.0), (38.0, 20.0), (37.0, 10.0), (32.5, 0.0)]
            .into_iter()
            .enumerate()
        {
            assert!(!c.too_fast(k as f64 * DT, r, v), "frame {k}");
        }
        // A value that is not finite starts the window again.
        let mut c = Closing::default();
        assert!(!c.too_fast(0.0, 50.0, 10.0));
        assert!(!c.too_fast(DT, f64::NAN, 10.0));
        for k in 2..5 {
            assert!(!c.too_fast(k as f64 * DT, 20.0, 10.0));
        }
        assert!(c.too_fast(5.0 * DT, 10.0, 10.0));
    }
}

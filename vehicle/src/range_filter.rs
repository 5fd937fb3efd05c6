//! An alpha–beta filter on the measured range to the lead: smooth range and range rate, with
//! an innovation gate that keeps a single wild measurement out.

/// Range and range rate from noisy, irregular range measurements.
#[derive(Clone, Debug)]
pub struct RangeFilter {
    gains: Gains,
    gate: RangeGate,
    state: Option<RangeState>,
    /// Measurements rejected in a row by the gate.
    rejected_in_a_row: u32,
}

/// How the filter weighs a new measurement.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Gains {
    /// The same gains at every range.
    Fixed {
        /// Gain on position, in (0, 1].
        alpha: f32,
        /// Gain on rate, in [0, 1].
        beta: f32,
    },
    /// The steady-state Kalman gains (Kalata 1984) for the tracking index
    /// `Λ = σ_accel T² / σ_range`, with the range noise growing as the square of the range:
    /// `Λ(r) = index_at_reference × (reference_m / r)²`. The tracker measures range through
    /// its scale (eq. 36), whose error in pixels hardly depends on the range, so the range's
    /// error grows as its square: a filter quick at 5 m is twitchy at 15 m.
    TrackingIndex {
        /// Λ at `reference_m`.
        index_at_reference: f32,
        /// The range where Λ is `index_at_reference`, m.
        reference_m: f32,
    },
}

impl Gains {
    /// `(alpha, beta)` for a measurement predicted at `range_m`.
    pub fn at(&self, range_m: f32) -> (f32, f32) {
        match *self {
            Gains::Fixed { alpha, beta } => (alpha, beta),
            Gains::TrackingIndex {
                index_at_reference,
                reference_m,
            } => {
                let ratio = reference_m / range_m.max(0.1 * reference_m);
                let index = f64::from(index_at_reference * ratio * ratio);
                let r = (4.0 + index - (8.0 * index + index * index).sqrt()) / 4.0;
                let alpha = 1.0 - r * r;
                let beta = 2.0 * (2.0 - alpha) - 4.0 * (1.0 - alpha).sqrt();
                (alpha as f32, beta as f32)
            }
        }
    }
}

/// Which measurements the filter refuses: those further from its prediction than
/// `max(min_m, fraction × predicted range)`, unless [`RangeGate::accept_after`] of them come
/// in a row (then the range really has moved, and the filter follows).
///
/// The tracker's range comes from its scale (eq. 36), so one frame whose features were taken
/// from background edges can move it by metres; closing on a braking lead moves it by
/// centimetres a frame beyond the filter's prediction.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RangeGate {
    /// The gate as a fraction of the predicted range.
    pub fraction: f32,
    /// The smallest gate, m.
    pub min_m: f32,
    /// After this many rejections in a row the next measurement is taken whatever it says.
    pub accept_after: u32,
}

impl RangeGate {
    /// No gate: every measurement is taken.
    pub const OPEN: RangeGate = RangeGate {
        fraction: f32::INFINITY,
        min_m: f32::INFINITY,
        accept_after: 0,
    };

    fn width_m(&self, predicted_m: f32) -> f32 {
        self.min_m.max(self.fraction * predicted_m.abs())
    }
}

/// The filter's estimate at one capture time.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RangeState {
    /// Capture time of the last measurement, s.
    pub time_s: f64,
    /// Range, m.
    pub range_m: f32,
    /// Range rate, m/s (negative when closing).
    pub range_rate_mps: f32,
}

impl RangeFilter {
    /// A filter with gains `alpha` (position) and `beta` (rate), both in (0, 1], that takes
    /// every measurement.
    pub fn new(alpha: f32, beta: f32) -> RangeFilter {
        RangeFilter::gated(Gains::Fixed { alpha, beta }, RangeGate::OPEN)
    }

    /// A filter with `gains` and the innovation gate `gate`.
    pub fn gated(gains: Gains, gate: RangeGate) -> RangeFilter {
        RangeFilter {
            gains,
            gate,
            state: None,
            rejected_in_a_row: 0,
        }
    }

    /// Folds in the range `range_m` measured at `time_s`; returns the new estimate.
    /// Measurements not later than the last are ignored, and so are those the gate refuses.
    pub fn update(&mut self, time_s: f64, range_m: f32) -> RangeState {
        let next = match self.state {
            None => RangeState {
                time_s,
                range_m,
                range_rate_mps: 0.0,
            },
            Some(s) if time_s <= s.time_s => s,
            Some(s) => {
                let dt = (time_s - s.time_s) as f32;
                let predicted = s.range_m + s.range_rate_mps * dt;
                let residual = range_m - predicted;
                if residual.abs() > self.gate.width_m(predicted)
                    && self.rejected_in_a_row < self.gate.accept_after
                {
                    self.rejected_in_a_row += 1;
                    return s;
                }
                self.rejected_in_a_row = 0;
                let (alpha, beta) = self.gains.at(predicted);
                RangeState {
                    time_s,
                    range_m: predicted + alpha * residual,
                    range_rate_mps: s.range_rate_mps + beta * residual / dt,
                }
            }
        };
        self.state = Some(next);
        next
    }

    /// The last estimate.
    pub fn state(&self) -> Option<RangeState> {
        self.state
    }

    /// Forgets everything (after a loss).
    pub fn reset(&mut self) {
        self.state = None;
        self.rejected_in_a_row = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GATE: RangeGate = RangeGate {
        fraction: 0.12,
        min_m: 0.75,
        accept_after: 3,
    };

    #[test]
    fn tracks_a_constant_closing_rate() {
        let mut f = RangeFilter::new(0.6, 0.3);
        let mut s = f.update(0.0, 20.0);
        for i in 1..60 {
            let t = f64::from(i) / 15.0;
            s = f.update(t, 20.0 - 2.0 * t as f32);
        }
        assert!((s.range_rate_mps + 2.0).abs() < 0.01, "{s:?}");
    }

    #[test]
    fn the_gate_passes_a_lead_braking_at_0_85_g() {
        // Both at 10 m/s, 12 m apart; the lead brakes at 8.34 m/s² from t = 1 s.
        let gains = Gains::Fixed {
            alpha: 0.6,
            beta: 0.35,
        };
        let (mut gated, mut open) = (RangeFilter::gated(gains, GATE), RangeFilter::new(0.6, 0.35));
        for i in 0..45 {
            let t = f64::from(i) / 15.0;
            let braking = (t - 1.0).max(0.0) as f32;
            let range = 12.0 - 0.5 * 8.34 * braking * braking;
            assert_eq!(gated.update(t, range), open.update(t, range), "at {t} s");
        }
    }

    #[test]
    fn the_gate_drops_one_wild_measurement_and_follows_a_real_jump() {
        let mut f = RangeFilter::gated(
            Gains::Fixed {
                alpha: 0.6,
                beta: 0.35,
            },
            GATE,
        );
        for i in 0..30 {
            f.update(f64::from(i) / 15.0, 14.0);
        }
        // One frame says 11.5 m: refused, the estimate stays.
        let s = f.update(2.0, 11.5);
        assert_eq!((s.range_m, s.range_rate_mps), (14.0, 0.0));
        let s = f.update(2.0 + 1.0 / 15.0, 14.0);
        assert_eq!((s.range_m, s.range_rate_mps), (14.0, 0.0));
        // Four frames in a row say 11.5 m: the fourth is taken.
        for k in 2..5 {
            let s = f.update(2.0 + f64::from(k) / 15.0, 11.5);
            assert_eq!(s.range_m, 14.0, "frame {k}");
        }
        let s = f.update(2.0 + 5.0 / 15.0, 11.5);
        assert!(s.range_m < 13.0, "{s:?}");
    }

    #[test]
    fn tracking_index_gains_match_kalatas_table_and_soften_with_range() {
        let gains = Gains::TrackingIndex {
            index_at_reference: 1.0,
            reference_m: 10.0,
        };
        // Kalata's closed form at Λ = 1: r = (5 - 3) / 4, α = 0.75, β = 0.5.
        let (a, b) = gains.at(10.0);
        assert!((a - 0.75).abs() < 1e-6 && (b - 0.5).abs() < 1e-6, "{a} {b}");
        let (near, far) = (gains.at(5.0), gains.at(15.0));
        assert!(near.0 > a && near.1 > b, "{near:?}");
        assert!(far.0 < a && far.1 < b, "{far:?}");
    }
}

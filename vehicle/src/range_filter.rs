//! An alpha–beta filter on the lead's motion, from measured ranges and the chase vehicle's
//! own odometry: smooth range and lead speed, with an innovation gate that keeps a single
//! wild measurement out.
//!
//! It filters where the lead is along the way (own distance driven plus range), not the
//! range itself. The range changes as fast as the chase vehicle's own speed does, which the
//! controller sets and the odometry knows exactly; a filter on the range would lag behind
//! the controller's own actions, and the gap keeper that uses it would oscillate. The lead's
//! motion changes only as the lead drives.

use crate::pose_history::OwnMotion;

/// Range and the lead's speed from noisy, irregular range measurements.
#[derive(Clone, Debug)]
pub struct RangeFilter {
    gains: Gains,
    gate: RangeGate,
    state: Option<RangeState>,
    /// Measurements rejected in a row by the gate.
    rejected_in_a_row: u32,
    /// After [`RangeFilter::reset_measuring`]: how many measurements its first estimate
    /// is fitted to (0: the first measurement is the first estimate).
    measure_first: usize,
    /// The measurements so far towards that first estimate: capture time, s, and where
    /// the lead was along the way (own travel plus range), m.
    first: Vec<(f64, f64)>,
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

    /// The standard deviation of the filter's steady-state rate estimate for a measurement
    /// at `range_m`, relative to its value at the gains' reference range, with the range
    /// noise growing as the square of the range (the model [`Gains::TrackingIndex`] is made
    /// for): 1 at the reference, about 1.6 at 2.5 times it for the alarm filter's default
    /// index of 0.6. (For white range noise of σ, an α–β filter's steady-state rate variance
    /// is σ² · 2β² / (α (4 − 2α − β)) / T²; T cancels in the ratio.) Fixed gains: 1.
    pub fn rate_noise_ratio(&self, range_m: f32) -> f32 {
        match *self {
            Gains::Fixed { .. } => 1.0,
            Gains::TrackingIndex { reference_m, .. } => {
                let noise = |r: f32| {
                    let (a, b) = self.at(r);
                    let sigma = r * r;
                    sigma * (2.0 * b * b / (a * (4.0 - 2.0 * a - b))).sqrt()
                };
                let range_m = range_m.max(0.1 * reference_m);
                noise(range_m) / noise(reference_m)
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
    /// Range then, m.
    pub range_m: f32,
    /// The lead's speed then, m/s.
    pub lead_speed_mps: f32,
    /// The chase vehicle's own motion then.
    pub own: OwnMotion,
}

impl RangeState {
    /// Range rate then, m/s (negative when closing).
    pub fn range_rate_mps(&self) -> f32 {
        self.lead_speed_mps - self.own.speed_mps
    }

    /// The range carried forward to a later moment, when the chase vehicle's motion is
    /// `own_now` (the lead keeps its speed).
    pub fn range_at(&self, time_s: f64, own_now: OwnMotion) -> f32 {
        let age = (time_s - self.time_s) as f32;
        self.range_m + self.lead_speed_mps * age - (own_now.travel_m - self.own.travel_m)
    }
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
            measure_first: 0,
            first: Vec::new(),
        }
    }

    /// Folds in the range `range_m` measured at `time_s`, when the chase vehicle's own
    /// motion was `own`; returns the new estimate. The first measurement takes the lead's
    /// speed to be the chase vehicle's, unless the filter measures first
    /// ([`RangeFilter::reset_measuring`]): then there is no estimate until the measurements
    /// it asked for are in. Measurements not later than the last are ignored, and so are
    /// those the gate refuses.
    pub fn update(&mut self, time_s: f64, range_m: f32, own: OwnMotion) -> Option<RangeState> {
        if self.is_measuring() {
            self.state = self.measure(time_s, range_m, own);
            return self.state;
        }
        let next = match self.state {
            None => RangeState {
                time_s,
                range_m,
                lead_speed_mps: own.speed_mps,
                own,
            },
            Some(s) if time_s <= s.time_s => s,
            Some(s) => {
                let dt = (time_s - s.time_s) as f32;
                let predicted = s.range_at(time_s, own);
                let residual = range_m - predicted;
                if residual.abs() > self.gate.width_m(predicted)
                    && self.rejected_in_a_row < self.gate.accept_after
                {
                    self.rejected_in_a_row += 1;
                    return Some(s);
                }
                self.rejected_in_a_row = 0;
                let (alpha, beta) = self.gains.at(predicted);
                RangeState {
                    time_s,
                    range_m: predicted + alpha * residual,
                    lead_speed_mps: s.lead_speed_mps + beta * residual / dt,
                    own,
                }
            }
        };
        self.state = Some(next);
        Some(next)
    }

    /// One measurement towards the first estimate after [`RangeFilter::reset_measuring`]:
    /// once they are all in, the estimate at the last, from the least-squares line through
    /// where the lead was along the way against time (its slope the lead's speed).
    fn measure(&mut self, time_s: f64, range_m: f32, own: OwnMotion) -> Option<RangeState> {
        if self.first.last().is_some_and(|&(t, _)| time_s <= t) {
            return None;
        }
        let along_m = f64::from(own.travel_m) + f64::from(range_m);
        self.first.push((time_s, along_m));
        if self.first.len() < self.measure_first {
            return None;
        }
        let n = self.first.len() as f64;
        let t_mean = self.first.iter().map(|m| m.0).sum::<f64>() / n;
        let p_mean = self.first.iter().map(|m| m.1).sum::<f64>() / n;
        let (mut stt, mut stp) = (0.0, 0.0);
        for &(t, p) in &self.first {
            stt += (t - t_mean) * (t - t_mean);
            stp += (t - t_mean) * (p - p_mean);
        }
        let speed = stp / stt;
        let along_now = p_mean + speed * (time_s - t_mean);
        self.first.clear();
        Some(RangeState {
            time_s,
            range_m: (along_now - f64::from(own.travel_m)) as f32,
            lead_speed_mps: speed as f32,
            own,
        })
    }

    /// Whether the filter is still taking the measurements for its first estimate
    /// ([`RangeFilter::reset_measuring`]).
    pub fn is_measuring(&self) -> bool {
        self.state.is_none() && self.measure_first > 0
    }

    /// Drops the measurements taken so far towards the first estimate (the target they
    /// were of is gone).
    pub fn restart_measuring(&mut self) {
        if self.is_measuring() {
            self.first.clear();
        }
    }

    /// The filter's gains.
    pub fn gains(&self) -> Gains {
        self.gains
    }

    /// The last estimate.
    pub fn state(&self) -> Option<RangeState> {
        self.state
    }

    /// Forgets everything (after a loss).
    pub fn reset(&mut self) {
        self.state = None;
        self.rejected_in_a_row = 0;
        self.measure_first = 0;
        self.first.clear();
    }

    /// Forgets everything, and gives no estimate until `count` measurements (at least 2)
    /// are in, then one fitted to them all: the lead's speed is the slope of the
    /// least-squares line through where it was along the way against time. A target
    /// acquired after a loss may move at any speed (a car standing in the lane, revealed
    /// by a lead that cut out); the first measurement alone says nothing of it, and taking
    /// it to move at the chase's speed, as a filter started behind a known lead does,
    /// leaves the gap keeper closing on a standing car at full speed while the filter's
    /// small gains at long range unlearn it.
    pub fn reset_measuring(&mut self, count: usize) {
        self.reset();
        self.measure_first = count.max(2);
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
    fn the_rate_noise_grows_with_the_range_beyond_the_reference() {
        let g = Gains::TrackingIndex {
            index_at_reference: 0.6,
            reference_m: 10.0,
        };
        assert!((g.rate_noise_ratio(10.0) - 1.0).abs() < 1e-6);
        let at_25 = g.rate_noise_ratio(25.0);
        assert!((1.5..1.7).contains(&at_25), "{at_25}");
        assert!(g.rate_noise_ratio(5.0) < 1.0);
        assert!(g.rate_noise_ratio(40.0) > at_25);
        let fixed = Gains::Fixed {
            alpha: 0.5,
            beta: 0.1,
        };
        assert_eq!(fixed.rate_noise_ratio(25.0), 1.0);
    }

    /// The chase standing still.
    const STILL: OwnMotion = OwnMotion {
        travel_m: 0.0,
        speed_mps: 0.0,
    };

    /// The chase at `t` seconds into a 1.5 m/s² acceleration from 8 m/s.
    fn accelerating(t: f64) -> OwnMotion {
        let t = t as f32;
        OwnMotion {
            travel_m: 8.0 * t + 0.75 * t * t,
            speed_mps: 8.0 + 1.5 * t,
        }
    }

    #[test]
    fn tracks_a_constant_closing_rate() {
        let mut f = RangeFilter::new(0.6, 0.3);
        let mut s = f.update(0.0, 20.0, STILL).unwrap();
        for i in 1..60 {
            let t = f64::from(i) / 15.0;
            s = f.update(t, 20.0 - 2.0 * t as f32, STILL).unwrap();
        }
        assert!((s.range_rate_mps() + 2.0).abs() < 0.01, "{s:?}");
    }

    #[test]
    fn the_chase_vehicles_own_acceleration_does_not_lag() {
        // The lead holds 8 m/s; the chase speeds up from 8 m/s at 1.5 m/s². A filter on the
        // range itself would lag the closing rate by about a second at these gains.
        let mut f = RangeFilter::new(0.3, 0.05);
        f.update(0.0, 12.0, accelerating(0.0));
        for i in 1..30 {
            let t = f64::from(i) / 15.0;
            let own = accelerating(t);
            let s = f
                .update(t, 12.0 + 8.0 * t as f32 - own.travel_m, own)
                .unwrap();
            assert!((s.lead_speed_mps - 8.0).abs() < 1e-3, "at {t} s: {s:?}");
            assert!(
                (s.range_rate_mps() + 1.5 * t as f32).abs() < 1e-3,
                "at {t} s: {s:?}"
            );
        }
    }

    #[test]
    fn the_gate_passes_a_lead_braking_at_0_85_g() {
        // Both at 10 m/s, 12 m apart; the lead brakes at 8.34 m/s² from t = 1 s.
        let gains = Gains::Fixed {
            alpha: 0.6,
            beta: 0.35,
        };
        let (mut gated, mut open) = (RangeFilter::gated(gains, GATE), RangeFilter::new(0.6, 0.35));
        let own = |t: f64| OwnMotion {
            travel_m: 10.0 * t as f32,
            speed_mps: 10.0,
        };
        for i in 0..45 {
            let t = f64::from(i) / 15.0;
            let braking = (t - 1.0).max(0.0) as f32;
            let range = 12.0 - 0.5 * 8.34 * braking * braking;
            assert_eq!(
                gated.update(t, range, own(t)),
                open.update(t, range, own(t)),
                "at {t} s"
            );
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
            f.update(f64::from(i) / 15.0, 14.0, STILL);
        }
        // One frame says 11.5 m: refused, the estimate stays.
        let s = f.update(2.0, 11.5, STILL).unwrap();
        assert_eq!((s.range_m, s.lead_speed_mps), (14.0, 0.0));
        let s = f.update(2.0 + 1.0 / 15.0, 14.0, STILL).unwrap();
        assert_eq!((s.range_m, s.lead_speed_mps), (14.0, 0.0));
        // Four frames in a row say 11.5 m: the fourth is taken.
        for k in 2..5 {
            let s = f.update(2.0 + f64::from(k) / 15.0, 11.5, STILL).unwrap();
            assert_eq!(s.range_m, 14.0, "frame {k}");
        }
        let s = f.update(2.0 + 5.0 / 15.0, 11.5, STILL).unwrap();
        assert!(s.range_m < 13.0, "{s:?}");
    }

    #[test]
    fn measuring_first_fits_the_speed_of_a_standing_target() {
        // The chase at 14 m/s acquires a car standing 35 m ahead; the ranges are noisy.
        let mut f = RangeFilter::gated(
            Gains::TrackingIndex {
                index_at_reference: 0.6,
                reference_m: 10.0,
            },
            GATE,
        );
        f.reset_measuring(10);
        let own = |t: f64| OwnMotion {
            travel_m: 14.0 * t as f32,
            speed_mps: 14.0,
        };
        let noise = [0.8, -0.6, 0.3, -0.9, 0.5, 0.1, -0.4, 0.7, -0.2, -0.3];
        let mut last = None;
        for (i, e) in noise.iter().enumerate() {
            let t = i as f64 / 15.0;
            assert!(f.is_measuring() && last.is_none(), "estimate before {i}");
            last = f.update(t, 35.0 - 14.0 * t as f32 + e, own(t));
        }
        let s = last.expect("an estimate once ten are in");
        assert!(!f.is_measuring());
        // Least squares through these ten: within 1.5 m/s of standing, not 14 m/s.
        assert!(s.lead_speed_mps.abs() < 1.5, "{s:?}");
        let t = 9.0 / 15.0;
        assert!((s.range_m - (35.0 - 14.0 * t as f32)).abs() < 0.6, "{s:?}");
        // A target lost while measuring: its measurements go.
        f.reset_measuring(3);
        f.update(0.0, 20.0, STILL);
        f.update(0.1, 20.0, STILL);
        f.restart_measuring();
        assert_eq!(f.update(0.2, 10.0, STILL), None);
        // A plain reset goes back to taking the first measurement at once.
        f.reset();
        assert!(f.update(0.3, 10.0, STILL).is_some());
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

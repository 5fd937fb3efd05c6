//! An alpha–beta filter on the measured range to the lead: smooth range and range rate.

/// Range and range rate from noisy, irregular range measurements.
#[derive(Clone, Debug)]
pub struct RangeFilter {
    alpha: f32,
    beta: f32,
    state: Option<RangeState>,
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
    /// A filter with gains `alpha` (position) and `beta` (rate), both in (0, 1].
    pub fn new(alpha: f32, beta: f32) -> RangeFilter {
        RangeFilter {
            alpha,
            beta,
            state: None,
        }
    }

    /// Folds in the range `range_m` measured at `time_s`; returns the new estimate.
    /// Measurements not later than the last are ignored.
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
                RangeState {
                    time_s,
                    range_m: predicted + self.alpha * residual,
                    range_rate_mps: s.range_rate_mps + self.beta * residual / dt,
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
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}

//! The chase controller's safety: the stop after a loss or a timeout and the resumption, and
//! the emergency brake's threat from the alarm range filter.

use super::{ChaseController, ChaseMode, CLOSING_CONFIRM_MS, RESUME_MEASUREMENTS};
use crate::clock::{ms_from_steps, steps_from_ms, Step};
use crate::controller_event::ControllerEventKind;
use crate::gap_keeper::Threat;
use crate::lead_estimate::TrackStatus;

impl ChaseController {
    /// Loss handling at step `now` (the controller started at `started`, drives at `v`,
    /// m/s): following, a lost status (or with `stop_on_coasting` a coasting one) or silence
    /// beyond the timeout starts the stop (braking fully if the emergency brake is on, until
    /// a `fresh` tracked estimate arrives); stopping, stopped or cruising, a `fresh` tracked
    /// estimate (one to follow) resumes following once the range filter has measured the
    /// target ([`RESUME_MEASUREMENTS`]).
    pub(super) fn handle_loss(&mut self, now: Step, started: Step, v: f32, fresh: bool) {
        let silent_steps = now.since(self.last_arrival.unwrap_or(started));
        let lost = self.last_status.is_some_and(|s| self.stops_on(s));
        let timed_out = silent_steps > self.timeout_steps;
        match self.mode {
            ChaseMode::Following if lost || timed_out => {
                let kind = if lost {
                    ControllerEventKind::TrackLost
                } else {
                    ControllerEventKind::EstimateTimeout {
                        silent_ms: ms_from_steps(silent_steps),
                    }
                };
                self.log(now, kind);
                self.mode = ChaseMode::Stopping;
                self.stop_ref_mps = v.max(0.0);
                // A loss tells nothing of the threat that called the emergency brake.
                self.stop_in_emergency = self.telemetry.emergency;
                self.range.reset_measuring(RESUME_MEASUREMENTS);
                self.alarm_range.reset_measuring(RESUME_MEASUREMENTS);
            }
            ChaseMode::Stopping | ChaseMode::Stopped | ChaseMode::Cruising
                if fresh
                    && self.last_status == Some(TrackStatus::Tracking)
                    && self.range.state().is_some() =>
            {
                self.log(now, ControllerEventKind::Resumed);
                self.mode = ChaseMode::Following;
                self.gap_keeper.reset(v);
                self.speed.reset();
            }
            // A target held again ends a loss's emergency brake; following waits for its
            // range to be measured.
            ChaseMode::Stopping if fresh && self.last_status == Some(TrackStatus::Tracking) => {
                self.stop_in_emergency = false
            }
            ChaseMode::Stopped => self.resume_cruise_if_due(now, v),
            _ => {}
        }
    }

    /// The emergency brake's threat from `alarm`, the alarm filter's gap and range rate now
    /// (m, m/s), at own speed `v`, m/s.
    pub(super) fn alarm_threat(
        &mut self,
        now: Step,
        alarm: (Option<f32>, Option<f32>),
        v: f32,
    ) -> Threat {
        match alarm {
            (Some(gap), Some(rate)) => {
                let noise = self.alarm_range.gains().rate_noise_ratio(gap);
                let mut t = self.config.gap_keeper.threat_in_noise(gap, rate, v, noise);
                // Beyond the alarm filter's reference range a closing alone must last
                // CLOSING_CONFIRM_MS before it brakes fully: a small, far target's rate
                // noise fakes a closing for a frame or two, a braking lead's lasts.
                if t.closing_only && noise > 1.0 {
                    let since = *self.closing_since.get_or_insert(now);
                    if now.since(since) < steps_from_ms(CLOSING_CONFIRM_MS) {
                        t.emergency = false;
                    }
                } else {
                    self.closing_since = None;
                }
                t
            }
            _ => {
                self.closing_since = None;
                Threat::default()
            }
        }
    }
}

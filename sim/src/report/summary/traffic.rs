//! The traffic's part of `summary.json` (see [`TrafficSummary`]) and its criteria: how close
//! the chase came to the vehicle in its path, what it hit and how hard, when it first held
//! the vehicle in its path, how long it held the wrong one, and how hard it braked.

use serde::Serialize;
use sim_core::{Expect, FrameRecord};

use super::{Criterion, Summary, TIME_TOLERANCE_S};

/// km/h in one m/s.
const KPH_PER_MPS: f64 = 3.6;

/// What the traffic came to, in a run with traffic (other vehicles, or events): left out
/// of `summary.json` otherwise.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct TrafficSummary {
    /// The smallest time to collision with the vehicle in the chase's path (the gap over
    /// the closing speed, at the frames' captures), seconds; `null` when the chase never
    /// closed on one.
    pub min_ttc_s: Option<f64>,
    /// The smallest gap to the vehicle in the chase's path, bumper to bumper along the
    /// road, metres; `null` when nothing was ever in its path.
    pub min_gap_m: Option<f64>,
    /// The chase's speed towards what it hit at its first contact, km/h; `null` with no
    /// contact.
    pub impact_speed_kph: Option<f64>,
    /// Every contact of the chase with another vehicle (its first physics step), in order.
    pub collisions: Vec<CollisionTime>,
    /// The true range to its target when the vehicle in the chase's path was first the one
    /// tracked (the lead's board, or an actor's back), metres; `null` if it never was.
    pub acquisition_range_m: Option<f64>,
    /// Time the tracker held a vehicle that was not the one in the chase's path, seconds.
    pub wrong_vehicle_s: f64,
    /// The chase's hardest deceleration, m/s², from its speed record to record.
    pub max_decel_mps2: f64,
    /// The chase's largest jerk, m/s³, from those accelerations frame to frame.
    pub max_jerk_mps3: f64,
    /// Every event that started or ended, in order.
    pub events: Vec<EventTime>,
}

/// A contact of the chase with another vehicle.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CollisionTime {
    /// The vehicle hit.
    pub vehicle: String,
    /// When, seconds.
    pub t_s: f64,
    /// The chase's speed towards it along the road, km/h.
    pub closing_kph: f64,
}

/// An event's start or end.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EventTime {
    /// The frame whose physics it happened in (it is logged on the next frame's record).
    pub frame: u64,
    /// The capture time of the record that logged it (the next frame's), seconds.
    pub t_s: f64,
    /// `vehicle/event:started` or `vehicle/event:ended`.
    pub event: String,
}

/// The traffic summary built frame by frame.
#[derive(Clone, Debug, Default)]
pub(crate) struct TrafficStats {
    summary: TrafficSummary,
    seen: bool,
    wrong_frames: u64,
    last_speed: Option<(f64, f64)>,
    last_accel: Option<f64>,
}

impl TrafficStats {
    /// Takes the next record.
    pub fn push(&mut self, r: &FrameRecord) {
        if let Some((t0, v0)) = self.last_speed {
            let dt = r.t_s - t0;
            if dt > 0.0 {
                let a = (r.chase_speed_mps - v0) / dt;
                let s = &mut self.summary;
                s.max_decel_mps2 = s.max_decel_mps2.max(-a);
                if let Some(a0) = self.last_accel {
                    s.max_jerk_mps3 = s.max_jerk_mps3.max((a - a0).abs() / dt);
                }
                self.last_accel = Some(a);
            }
        }
        self.last_speed = Some((r.t_s, r.chase_speed_mps));
        let Some(t) = &r.traffic else {
            return;
        };
        self.seen = true;
        let s = &mut self.summary;
        if t.path_vehicle.is_some() {
            if t.path_gap_m.is_finite() {
                s.min_gap_m = Some(s.min_gap_m.map_or(t.path_gap_m, |m| m.min(t.path_gap_m)));
            }
            if t.path_ttc_s.is_finite() {
                s.min_ttc_s = Some(s.min_ttc_s.map_or(t.path_ttc_s, |m| m.min(t.path_ttc_s)));
            }
        }
        if t.tracked_vehicle.is_some() {
            if t.tracked_vehicle == t.path_vehicle {
                if s.acquisition_range_m.is_none() {
                    s.acquisition_range_m = Some(t.path_range_m);
                }
            } else {
                self.wrong_frames += 1;
            }
        }
        for c in &t.contacts {
            let closing_kph = c.closing_mps * KPH_PER_MPS;
            if s.impact_speed_kph.is_none() {
                s.impact_speed_kph = Some(closing_kph.max(0.0));
            }
            s.collisions.push(CollisionTime {
                vehicle: c.vehicle.clone(),
                t_s: c.t_s,
                closing_kph,
            });
        }
        for e in &t.events {
            s.events.push(EventTime {
                frame: r.frame.saturating_sub(1),
                t_s: r.t_s,
                event: e.clone(),
            });
        }
    }

    /// Whether any record carried traffic.
    pub fn seen(&self) -> bool {
        self.seen
    }

    /// The summary, when any record carried traffic or `asked` (the run is judged by a
    /// criterion of this part); `period` is the frame period.
    pub fn finish(mut self, period: f64, asked: bool) -> Option<TrafficSummary> {
        self.summary.wrong_vehicle_s = self.wrong_frames as f64 * period;
        (self.seen || asked).then_some(self.summary)
    }
}

/// Whether `expect` judges the run by a criterion of the traffic's part.
pub(super) fn asked(expect: &Expect) -> bool {
    expect.max_impact_speed_kph.is_some()
        || expect.min_ttc_s.is_some()
        || expect.max_wrong_vehicle_s.is_some()
        || expect.max_decel_mps2.is_some()
        || expect.max_jerk_mps3.is_some()
}

/// The traffic's criteria that `expect` asks for, appended to `out`.
pub(super) fn check(s: &Summary, expect: &Expect, out: &mut Vec<Criterion>) {
    let t = s.traffic.clone().unwrap_or_default();
    if let Some(allowed) = expect.max_impact_speed_kph {
        let v = t.impact_speed_kph.unwrap_or(0.0);
        let hit = t.collisions.first().map_or("no contact".to_string(), |c| {
            format!("hit `{}` at {:.2} s", c.vehicle, c.t_s)
        });
        out.push(Criterion {
            name: "max_impact_speed".into(),
            // 0 allows no contact at all, however slow.
            passed: if allowed == 0.0 {
                t.collisions.is_empty()
            } else {
                v <= allowed
            },
            value: v,
            limit: allowed,
            message: format!("impact speed {v:.1} km/h: {hit} (allowed {allowed:.1} km/h)"),
        });
    }
    if let Some(required) = expect.min_ttc_s {
        let v = t.min_ttc_s.unwrap_or(f64::INFINITY);
        out.push(Criterion {
            name: "min_ttc".into(),
            passed: v >= required,
            value: v,
            limit: required,
            message: format!(
                "the time to collision with the vehicle in the path fell to {} (required at \
                 least {required:.2} s)",
                t.min_ttc_s
                    .map_or("nothing: never closing".into(), |v| format!("{v:.2} s"))
            ),
        });
    }
    if let Some(allowed) = expect.max_wrong_vehicle_s {
        let v = t.wrong_vehicle_s;
        out.push(Criterion {
            name: "max_wrong_vehicle".into(),
            passed: v <= allowed + TIME_TOLERANCE_S,
            value: v,
            limit: allowed,
            message: format!(
                "the tracker held a vehicle not in the chase's path for {v:.2} s (allowed \
                 {allowed:.2} s)"
            ),
        });
    }
    for (name, limit, v, what) in [
        (
            "max_decel",
            expect.max_decel_mps2,
            t.max_decel_mps2,
            ("deceleration", "m/s²"),
        ),
        (
            "max_jerk",
            expect.max_jerk_mps3,
            t.max_jerk_mps3,
            ("jerk", "m/s³"),
        ),
    ] {
        if let Some(allowed) = limit {
            out.push(Criterion {
                name: name.into(),
                passed: v <= allowed,
                value: v,
                limit: allowed,
                message: format!(
                    "the chase's {} reached {v:.2} {} (allowed {allowed:.2})",
                    what.0, what.1
                ),
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::frames_csv::tests::record;
    use sim_core::{Contact, TrafficFrame};

    /// Record `i` with the chase 10 m from `path` closing at 2 m/s, holding `tracked`.
    fn traffic(i: u64, path: Option<&str>, tracked: Option<&str>) -> FrameRecord {
        let mut r = record(i);
        r.traffic = Some(TrafficFrame {
            path_vehicle: path.map(str::to_string),
            path_gap_m: 10.0 - i as f64,
            path_closing_mps: 2.0,
            path_ttc_s: (10.0 - i as f64) / 2.0,
            // Not the record's `true_range_m` (the lead's board's), which an actor held
            // first would not be at.
            path_range_m: 20.0 + i as f64,
            tracked_vehicle: tracked.map(str::to_string),
            ..TrafficFrame::default()
        });
        r
    }

    #[test]
    fn the_traffic_summary_measures_the_path_vehicle_and_the_wrong_one() {
        let mut stats = TrafficStats::default();
        stats.push(&traffic(0, Some("lead"), Some("lead")));
        stats.push(&traffic(1, Some("van"), Some("lead")));
        stats.push(&traffic(2, Some("van"), Some("lead")));
        let mut hit = traffic(3, Some("van"), None);
        hit.traffic.as_mut().unwrap().contacts.push(Contact {
            vehicle: "van".into(),
            t_s: 0.2,
            closing_mps: 2.5,
        });
        stats.push(&hit);
        let s = stats.finish(1.0 / 15.0, false).unwrap();
        assert_eq!(s.min_gap_m, Some(7.0));
        assert_eq!(s.min_ttc_s, Some(3.5));
        assert_eq!(s.acquisition_range_m, Some(20.0));
        assert!((s.wrong_vehicle_s - 2.0 / 15.0).abs() < 1e-12);
        assert_eq!(s.impact_speed_kph, Some(9.0));
        assert_eq!(s.collisions[0].vehicle, "van");
    }

    #[test]
    fn the_acquisition_range_is_that_of_the_vehicle_first_held_in_the_path() {
        let mut stats = TrafficStats::default();
        stats.push(&traffic(0, Some("van"), None));
        stats.push(&traffic(1, Some("van"), Some("van")));
        stats.push(&traffic(2, Some("lead"), Some("lead")));
        let s = stats.finish(1.0 / 15.0, false).unwrap();
        assert_eq!(s.acquisition_range_m, Some(21.0));
    }

    #[test]
    fn without_traffic_there_is_no_traffic_summary_unless_a_criterion_asks() {
        let mut stats = TrafficStats::default();
        stats.push(&record(0));
        stats.push(&record(1));
        assert!(stats.clone().finish(1.0 / 15.0, false).is_none());
        let s = stats.finish(1.0 / 15.0, true).unwrap();
        assert!(s.collisions.is_empty() && s.events.is_empty());
    }

    #[test]
    fn the_impact_criterion_at_zero_refuses_any_contact() {
        let mut stats = TrafficStats::default();
        let mut hit = traffic(0, Some("van"), None);
        hit.traffic.as_mut().unwrap().contacts.push(Contact {
            vehicle: "van".into(),
            t_s: 0.0,
            closing_mps: -1.0,
        });
        stats.push(&hit);
        let expect = Expect {
            max_impact_speed_kph: Some(0.0),
            ..Expect::default()
        };
        let summary = Summary::compute("x", 1, &[hit], &expect, 1.0);
        assert!(!summary.passed, "{:?}", summary.criteria);
        assert!(
            summary.failures[0].contains("`van`"),
            "{:?}",
            summary.failures
        );
    }
}

//! The first acquisition of a run whose tracker started with nothing placed
//! (`tracker.start = "search"`): how long it searched with a target to find, and how far
//! off the target was when it first held it; and `[expect] min_acquisition_range_m`.

use serde::Serialize;
use sim_core::{Expect, FrameRecord, LossCause};

use super::{Criterion, Summary};

/// How long a tracker that started with nothing placed took to find its target.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Acquisition {
    /// Time before the first acquisition with a target to find (frames whose
    /// `loss_cause` is `not_acquired`), seconds.
    pub not_acquired_s: f64,
    /// The capture time of the frame the target (in traffic, the vehicle in the chase's
    /// path) was first held, seconds; `null` if it never was.
    pub acquired_t_s: Option<f64>,
    /// The true range to the target then (the lead's, `true_range_m`; in traffic, the
    /// path vehicle's, `path_range_m`), metres; `null` if never held.
    pub range_m: Option<f64>,
}

/// The first acquisition, followed frame by frame.
#[derive(Clone, Debug, Default)]
pub(super) struct FirstAcquisition {
    /// Whether any frame was not yet acquired.
    seen: bool,
    /// The first acquisition's capture time and true range, once it came.
    at: Option<(f64, f64)>,
}

impl FirstAcquisition {
    /// Takes the next record.
    pub(super) fn push(&mut self, r: &FrameRecord) {
        if r.loss_cause == LossCause::NotAcquired {
            self.seen = true;
        } else if self.seen && self.at.is_none() && !r.lost_truth {
            // Held: without traffic the estimate lies on the target; in traffic on the
            // vehicle in the path (a frame with the road clear holds nothing, and waits).
            // Its range: the lead's target's, or in traffic that of the vehicle in the path.
            let held = match &r.traffic {
                None => Some(r.true_range_m),
                Some(t) => t.tracked_vehicle.as_ref().map(|_| t.path_range_m),
            };
            if let Some(range_m) = held {
                self.at = Some((r.t_s, range_m));
            }
        }
    }

    /// The summary's part, with `not_acquired_s` the time of the `not_acquired` frames;
    /// `None` for a run without any.
    pub(super) fn finish(self, not_acquired_s: f64) -> Option<Acquisition> {
        self.seen.then_some(Acquisition {
            not_acquired_s,
            acquired_t_s: self.at.map(|a| a.0),
            range_m: self.at.map(|a| a.1),
        })
    }
}

/// `min_acquisition_range_m`, when `expect` asks for it, appended to `out`. A run whose
/// tracker held its target from the start (placed on it, or found at once) passes; one that
/// never held it fails.
pub(super) fn check(s: &Summary, expect: &Expect, out: &mut Vec<Criterion>) {
    let Some(required) = expect.min_acquisition_range_m else {
        return;
    };
    let (value, said) = match s.acquisition {
        None => (f64::INFINITY, "held from the start".to_string()),
        Some(Acquisition {
            range_m: Some(r),
            acquired_t_s: Some(t),
            not_acquired_s,
        }) => (
            r,
            format!("first held {r:.1} m off at {t:.2} s, after {not_acquired_s:.2} s searching"),
        ),
        Some(a) => (
            0.0,
            format!("never held, after {:.2} s searching", a.not_acquired_s),
        ),
    };
    out.push(Criterion {
        name: "min_acquisition_range".into(),
        passed: value >= required,
        value,
        limit: required,
        message: format!("the tracker's target was {said} (required at least {required:.1} m off)"),
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::frames_csv::tests::record;
    use sim_core::TrackerStatus;

    /// 30 frames: the first 12 without the target, not yet acquired; frames 20–22 lost by
    /// the tracker after it.
    fn searched() -> Vec<FrameRecord> {
        (0..30)
            .map(|i| {
                let mut r = record(i);
                r.true_range_m = 40.0 - i as f64;
                if i < 12 || (20..23).contains(&i) {
                    r.lost_truth = true;
                    r.status = TrackerStatus::Lost;
                    r.loss_cause = if i < 12 {
                        LossCause::NotAcquired
                    } else {
                        LossCause::Tracker
                    };
                }
                r
            })
            .collect()
    }

    #[test]
    fn the_search_before_the_first_acquisition_is_no_lost_track() {
        let expect = Expect {
            min_acquisition_range_m: Some(28.0),
            ..Expect::default()
        };
        let s = Summary::compute("x", 1, &searched(), &expect, 1.0);
        let a = s.acquisition.expect("searched");
        assert!((a.not_acquired_s - 12.0 / 15.0).abs() < 1e-9, "{a:?}");
        assert_eq!(a.acquired_t_s, Some(12.0 / 15.0));
        assert_eq!(a.range_m, Some(28.0));
        // Only the loss after it counts.
        assert!((s.tracking_lost_s - 3.0 / 15.0).abs() < 1e-9);
        assert_eq!(s.tracking_loss_events, 1);
        assert_eq!(s.loss_events[0].start_frame, 20);
        assert!((s.lost_by_cause_s.tracker - 3.0 / 15.0).abs() < 1e-9);
        assert!(s.passed, "{:?}", s.failures);
        let json = serde_json::to_value(&s).unwrap();
        assert_eq!(json["acquisition"]["range_m"], 28.0);

        let further = Expect {
            min_acquisition_range_m: Some(28.5),
            ..Expect::default()
        };
        let s = Summary::compute("x", 1, &searched(), &further, 1.0);
        assert!(!s.passed);
        assert!(
            s.failures[0].contains("first held 28.0 m off at 0.80 s"),
            "{:?}",
            s.failures
        );
    }

    #[test]
    fn a_target_never_held_fails_and_one_held_from_the_start_passes() {
        let expect = Expect {
            min_acquisition_range_m: Some(10.0),
            ..Expect::default()
        };
        let never: Vec<FrameRecord> = searched().into_iter().take(12).collect();
        let s = Summary::compute("x", 1, &never, &expect, 1.0);
        assert_eq!(s.acquisition.unwrap().acquired_t_s, None);
        assert_eq!(s.tracking_lost_s, 0.0);
        assert!(
            !s.passed && s.failures[0].contains("never held"),
            "{:?}",
            s.failures
        );
        let placed: Vec<FrameRecord> = (0..12).map(record).collect();
        let s = Summary::compute("x", 1, &placed, &expect, 1.0);
        assert!(s.acquisition.is_none());
        assert!(s.passed);
        // Left out of summary.json when there was nothing to acquire.
        let json = serde_json::to_value(&s).unwrap();
        assert!(json.get("acquisition").is_none());
    }

    /// An `unresolved` event of the search before the first acquisition does not explain a
    /// later loss in `max_lost`'s message; one after it does.
    #[test]
    fn an_unresolved_search_is_no_resolution_loss() {
        let expect = Expect {
            max_lost_s: Some(0.0),
            ..Expect::default()
        };
        let mut rs = searched();
        rs[5].tracker_event = "unresolved".into();
        let s = Summary::compute("x", 1, &rs, &expect, 1.0);
        assert_eq!(s.unresolved.len(), 1, "the tracker's event is kept");
        assert!(!s.passed);
        assert!(
            s.failures[0].contains("tracking lost") && !s.failures[0].contains("resolution"),
            "{:?}",
            s.failures
        );
        rs[18].tracker_event = "unresolved".into();
        let s = Summary::compute("x", 1, &rs, &expect, 1.0);
        assert!(
            s.failures[0].contains("beyond the tracker's resolution (`unresolved`) from 1.20 s"),
            "{:?}",
            s.failures
        );
    }
}

//! `summary.json`: what a run came to, and whether it met its scenario's `[expect]`.
//!
//! Everything is a pure function of the records, so the same records give the same summary.
//!
//! **Time.** Each frame stands for the interval from its capture time to the next frame's
//! (so a dropped frame lengthens its predecessor), and the last frame for one frame period.
//! The frame period is the median step between consecutive `t_s`, or 1/15 s with fewer than
//! two frames. `duration_s` is the sum of these intervals: `t_last − t_first + period`.
//! Times spent in a state (outside the gap band, lost, coasting) add up the intervals of the
//! frames in that state; `gap_m.mean` and `lateral_path_error_m.mean_abs` are time-weighted.
//!
//! **Tracking loss** is judged by ground truth (`lost_truth`), whatever the tracker says: a
//! frame is lost when there is no estimate or it is off by the tolerance, wherever the
//! target is (a target partly out of the image but tracked within the tolerance is not
//! lost; the time it spends partly out of view is `partly_out_of_view_s`); an event is a
//! maximal run of consecutive lost frames. A tracker that starts with nothing placed
//! (`tracker.start = "search"`) has not lost a target it has yet to find: until its first
//! acquisition, frames without the target are `not_acquired` and are counted apart
//! (`acquisition.not_acquired_s`), in no loss time or event. The tracker's own `lost` and `coasting`
//! times are reported beside it, and so is how long after each event's start the tracker
//! first said it was not tracking (`loss_events`, `max_loss_report_delay_frames`), and how
//! many lost frames it spent saying `tracking` (`silent_loss_frames`). Its dual, the
//! **false alarm**, is a frame the tracker did not say `tracking` though its estimate was
//! within the tolerance of a target wholly in view and not hidden (`false_alarm_s`,
//! `longest_false_alarm_frames`).
//!
//! **Range error** is `|est_range_m − true_range_m|` over the frames where the target is in view
//! and not lost by the ground-truth judgement (and the estimate is finite): while the tracker is
//! lost its range is not a measurement of anything, and that time is already counted in
//! `tracking_lost_s`. `p95_abs` is the nearest-rank 95th percentile over those frames (the
//! smallest error that at least 95 % of the frames do not exceed); both are `null` when no frame
//! qualifies.

mod acquisition;
mod range_errors;
mod stream;
mod traffic;

use serde::Serialize;

pub use acquisition::Acquisition;
pub(crate) use stream::FramePeriod;
pub use stream::SummaryBuilder;
pub use traffic::{CollisionTime, EventTime, TrafficSummary};

use sim_core::LoopTiming;
use sim_core::{Expect, FrameRecord, LossCause};

/// The frame period used when the records cannot tell it: the loop's 15 Hz.
pub const DEFAULT_FRAME_PERIOD_S: f64 = 1.0 / 15.0;

/// Centre error beyond which a frame counts towards `imprecise_share`, pixels.
pub const IMPRECISE_CENTRE_PX: f64 = 2.0;
/// Relative scale error beyond which a frame counts towards `imprecise_share`.
pub const IMPRECISE_SCALE: f64 = 0.05;

/// Slack when comparing accumulated times with a limit, seconds: sums of 1/15 s steps are not
/// exact in binary.
const TIME_TOLERANCE_S: f64 = 1e-9;

/// The summary of one run, written as `summary.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// The layout of this file: [`SCHEMA_VERSION`], raised when a field changes meaning or
    /// goes away.
    pub schema_version: u32,
    /// The carfollow version that wrote it (`CARGO_PKG_VERSION`).
    pub carfollow_version: String,
    /// The git commit the program was built from, when the build could tell (left out
    /// otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub git_commit: Option<String>,
    /// Scenario name.
    pub scenario: String,
    /// The scenario's seed.
    pub seed: u64,
    /// The tracker that ran: the paper's, with its mode, or a plug-in's own name (left out
    /// when the caller did not say).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tracker: Option<String>,
    /// The controller that ran: the built-in, or a plug-in's own name (left out when the
    /// caller did not say).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub controller: Option<String>,
    /// Simulated time covered by the records, seconds.
    pub duration_s: f64,
    /// Number of frames recorded.
    pub frames: u64,
    /// The event that ended the run before the scenario's `duration_s` (an `end_run`
    /// action: OpenSCENARIO's `StopTrigger`); left out when the run went its whole length.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ended_by: Option<EndedBy>,
    /// Every checked criterion passed (and at least one frame was recorded).
    pub passed: bool,
    /// One sentence per failed criterion, with its value and its limit.
    pub failures: Vec<String>,
    /// Every criterion that `[expect]` asked for, passed or not, in a fixed order.
    pub criteria: Vec<Criterion>,
    /// Following distance over the run, metres.
    pub gap_m: GapStats,
    /// The band from `[expect]`, metres, if any.
    pub gap_band_m: Option<[f64; 2]>,
    /// Time with the gap outside the band, seconds (0 without a band).
    pub time_outside_gap_band_s: f64,
    /// Time lost by the ground-truth judgement, seconds.
    pub tracking_lost_s: f64,
    /// Number of ground-truth loss events (maximal runs of lost frames).
    pub tracking_loss_events: u64,
    /// `tracking_lost_s` by cause, seconds: `out_of_view` (the target outside the image),
    /// `occluded` (hidden by scenery, or in traffic behind the vehicle in the path) and
    /// `tracker` (in view, not hidden, and lost); in traffic also `left_path` and
    /// `wrong_vehicle`.
    pub lost_by_cause_s: LostByCause,
    /// The first acquisition, for a run whose tracker started with nothing placed
    /// (`tracker.start = "search"`) and spent frames without the target
    /// (`LossCause::NotAcquired`: counted here, not in `tracking_lost_s`); left out
    /// otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub acquisition: Option<Acquisition>,
    /// Time with the target partly out of view (some of it in the image, not all),
    /// seconds, whether or not it was lost then.
    pub partly_out_of_view_s: f64,
    /// A tighter measure beside the 25 % of `tracking_lost_s`: the share (0–1) of the frames
    /// with the target in view whose estimate is off by more than
    /// `IMPRECISE_CENTRE_PX` (2 px) in centre or `IMPRECISE_SCALE` (0.05) in scale (or is no
    /// estimate); `null` when the target is never in view.
    pub imprecise_share: Option<f64>,
    /// Time the tracker itself said `lost`, seconds.
    pub tracker_lost_s: f64,
    /// Time the tracker itself said `coasting`, seconds.
    pub tracker_coasting_s: f64,
    /// Frames lost by the ground-truth judgement while the tracker said `tracking`: silent
    /// loss, the kind a car that steers by the tracker cannot see.
    pub silent_loss_frames: u64,
    /// Time the tracker raised a false alarm, seconds: frames it did not say `tracking`
    /// though its estimate was within the ground truth's tolerance of a target wholly in
    /// view and not hidden (`FrameRecord::false_alarm`), the dual of silent loss.
    pub false_alarm_s: f64,
    /// The longest run of consecutive false-alarm frames (0 without any).
    pub longest_false_alarm_frames: u64,
    /// Each ground-truth loss event, with how long the tracker took to say so.
    pub loss_events: Vec<LossEvent>,
    /// The longest delay from a ground-truth loss to the tracker's own report, frames
    /// (`null` without loss events; an unreported event counts its whole length).
    pub max_loss_report_delay_frames: Option<u64>,
    /// Frames on which robust mode found the target again by search after coasting or a
    /// loss (or first found it, with no start given), with their times.
    pub reacquired: Vec<TrackerEventTime>,
    /// Frames on which the tracker found the target beyond its resolution (two parallel
    /// features that compete for edge points closer in the image than association tells
    /// apart: `unresolved` events), with their times.
    pub unresolved: Vec<TrackerEventTime>,
    /// Range estimate error while tracked, metres.
    pub range_error_m: RangeError,
    /// Chase vehicle's distance from the lead's path, metres.
    pub lateral_path_error_m: LateralError,
    /// Number of collision events (maximal runs of frames with contact between the chase
    /// and another vehicle).
    pub collisions: u64,
    /// What the traffic came to (left out for a run without traffic that no traffic
    /// criterion judges).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub traffic: Option<TrafficSummary>,
    /// Distance the chase vehicle drove, metres (the last record's `chase_distance_m`).
    pub distance_m: f64,
    /// Wall-clock time of the run, seconds (given by the caller).
    pub wall_s: f64,
    /// `duration_s / wall_s`; `null` when `wall_s` is not positive.
    pub realtime_factor: Option<f64>,
    /// Where the wall-clock time went, when the caller measured it (`null` otherwise).
    pub timing: Option<LoopTiming>,
    /// The `--set` overrides applied to the scenario file, in order.
    pub overrides: Vec<String>,
    /// The scenario as run: the file with the overrides applied and every default filled
    /// in (left out when the caller did not give it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub resolved_scenario: Option<serde_json::Value>,
}

/// The event that ended a run early.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EndedBy {
    /// The vehicle whose event it is.
    pub vehicle: String,
    /// The event's name.
    pub event: String,
    /// When its action started, seconds: the run's last frame is the one whose physics
    /// holds that step.
    pub t_s: f64,
}

impl EndedBy {
    /// The summary's account of the loop's `end`.
    pub fn of(end: &sim_core::RunEnd) -> EndedBy {
        EndedBy {
            vehicle: end.vehicle.clone(),
            event: end.event.clone(),
            t_s: end.step.seconds(),
        }
    }
}

/// Time lost by the ground truth, by cause (see [`LossCause`]), seconds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct LostByCause {
    /// The target outside the image.
    pub out_of_view: f64,
    /// The target hidden by scenery.
    pub occluded: f64,
    /// The target in view and not hidden, but too faint for the paper's edge threshold
    /// (written only when some frame was).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub low_contrast: Option<f64>,
    /// The target in view and not hidden: the tracker's own loss.
    pub tracker: f64,
    /// In traffic: holding a vehicle that has left the chase's path (written only in
    /// traffic).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub left_path: Option<f64>,
    /// In traffic: holding a vehicle that was never in the chase's path (written only in
    /// traffic).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wrong_vehicle: Option<f64>,
}

impl LostByCause {
    fn get(&self, cause: LossCause) -> f64 {
        match cause {
            LossCause::OutOfView => self.out_of_view,
            LossCause::Occluded => self.occluded,
            LossCause::LowContrast => self.low_contrast.unwrap_or(0.0),
            LossCause::Tracker => self.tracker,
            LossCause::LeftPath => self.left_path.unwrap_or(0.0),
            LossCause::WrongVehicle => self.wrong_vehicle.unwrap_or(0.0),
            LossCause::None | LossCause::NotAcquired => 0.0,
        }
    }

    /// The causes with time lost, largest first (ties in [`LossCause::ALL`]'s order), as
    /// "12.40 s out_of_view, 0.20 s tracker".
    pub fn describe(&self) -> String {
        let mut causes: Vec<LossCause> = LossCause::ALL
            .into_iter()
            .filter(|&c| self.get(c) > 0.0)
            .collect();
        causes.sort_by(|&a, &b| self.get(b).total_cmp(&self.get(a)));
        causes
            .iter()
            .map(|&c| format!("{:.2} s {}", self.get(c), c.as_str()))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// A ground-truth loss event (a maximal run of frames lost by the truth) and the tracker's
/// own report of it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LossEvent {
    /// First frame of the event.
    pub start_frame: u64,
    /// Its capture time, seconds.
    pub start_t_s: f64,
    /// Frames in the event.
    pub frames: u64,
    /// Frames from the event's start to the first in it where the tracker's status was not
    /// `tracking` (0 when it already said so); `null` when it said `tracking` throughout.
    pub report_delay_frames: Option<u64>,
    /// The cause of most of its frames (the first of [`LossCause::ALL`] on a tie).
    pub cause: LossCause,
}

/// A tracker event in the run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TrackerEventTime {
    /// Frame.
    pub frame: u64,
    /// Capture time, seconds.
    pub t_s: f64,
    /// `acquired`, `reacquired` or `unresolved`.
    pub event: String,
}

/// `summary.json`'s `schema_version`. 2: `schema_version`, `carfollow_version`,
/// `git_commit`, `overrides` and `resolved_scenario` added. 3: a frame with the target
/// partly (or wholly) out of view is lost only when the estimate is off, as any other
/// (`tracking_lost_s`, `lost_by_cause_s`, `loss_events` follow); `partly_out_of_view_s`
/// added. 4: `unresolved` added (the tracker's `unresolved` events; `reacquired` keeps
/// acquisitions only).
pub const SCHEMA_VERSION: u32 = 4;

/// Minimum, time-weighted mean and maximum of the gap, metres (zeros without frames).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct GapStats {
    /// Smallest gap, metres.
    pub min: f64,
    /// Time-weighted mean gap, metres.
    pub mean: f64,
    /// Largest gap, metres.
    pub max: f64,
}

/// Range estimate error over the tracked frames (see the module notes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct RangeError {
    /// Mean absolute error, metres.
    pub mean_abs: Option<f64>,
    /// Nearest-rank 95th percentile of the absolute error, metres.
    pub p95_abs: Option<f64>,
    /// Number of frames the error was taken over.
    pub frames: u64,
}

/// Lateral deviation from the lead's path over all frames, metres.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct LateralError {
    /// Time-weighted mean absolute deviation, metres.
    pub mean_abs: f64,
    /// Largest absolute deviation, metres.
    pub max_abs: f64,
}

/// One `[expect]` criterion and how the run did against it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Criterion {
    /// Short stable name: `gap_band`, `max_lost`, `max_lateral_deviation`, `no_collision`,
    /// `min_distance`, `max_range_error_p95`, `max_loss_events`, `max_false_alarm` (or
    /// `frames_recorded`).
    pub name: String,
    /// Whether it held.
    pub passed: bool,
    /// The measured value, in the criterion's unit.
    pub value: f64,
    /// The limit, in the same unit.
    pub limit: f64,
    /// One sentence with the value and the limit.
    pub message: String,
}

impl Summary {
    /// Computes the summary of a run from its records, its scenario's name, seed and
    /// `[expect]`, and the wall-clock time it took (see [`SummaryBuilder`] to build it as
    /// the records come, keeping none).
    pub fn compute(
        scenario: &str,
        seed: u64,
        records: &[FrameRecord],
        expect: &Expect,
        wall_s: f64,
    ) -> Summary {
        let mut builder = SummaryBuilder::new(expect.gap_band_m);
        for r in records {
            builder.push(r);
        }
        Summary::of(builder, scenario, seed, expect, wall_s)
    }

    /// The summary of the records `builder` took, for a scenario of that name, seed and
    /// `[expect]` (whose `gap_band_m` the builder was made with), and the wall-clock time
    /// the run took.
    pub fn of(
        builder: SummaryBuilder,
        scenario: &str,
        seed: u64,
        expect: &Expect,
        wall_s: f64,
    ) -> Summary {
        debug_assert_eq!(builder.gap_band_m(), expect.gap_band_m);
        let mut summary = builder.measured(
            scenario,
            seed,
            expect.gap_band_m,
            wall_s,
            traffic::asked(expect),
        );
        summary.criteria = check(&summary, expect);
        summary.failures = summary
            .criteria
            .iter()
            .filter(|c| !c.passed)
            .map(|c| c.message.clone())
            .collect();
        summary.passed = summary.failures.is_empty();
        summary
    }
}

/// Each criterion `[expect]` asks for, in a fixed order.
fn check(s: &Summary, expect: &Expect) -> Vec<Criterion> {
    let mut out = Vec::new();
    if s.frames == 0 {
        out.push(Criterion {
            name: "frames_recorded".into(),
            passed: false,
            value: 0.0,
            limit: 1.0,
            message: "the run recorded no frames (at least 1 needed)".into(),
        });
    }
    if let Some([lo, hi]) = expect.gap_band_m {
        let allowed = expect.max_time_outside_gap_band_s.unwrap_or(0.0);
        let t = s.time_outside_gap_band_s;
        let passed = t <= allowed + TIME_TOLERANCE_S;
        let verb = if passed { "was outside" } else { "left" };
        out.push(Criterion {
            name: "gap_band".into(),
            passed,
            value: t,
            limit: allowed,
            message: format!(
                "gap {verb} the band [{lo}, {hi}] m for {t:.2} s (allowed {allowed:.2} s; \
                 gap ranged {:.2} to {:.2} m)",
                s.gap_m.min, s.gap_m.max
            ),
        });
    }
    if let Some(allowed) = expect.max_lost_s {
        let t = s.tracking_lost_s;
        let passed = t <= allowed + TIME_TOLERANCE_S;
        out.push(Criterion {
            name: "max_lost".into(),
            passed,
            value: t,
            limit: allowed,
            message: if t > 0.0 {
                // A target beyond the tracker's resolution explains a loss of its own; a
                // searching tracker's `unresolved` before it first held the target judged
                // the model where it searched, not a target it had, and explains nothing.
                let held_from = s.acquisition.map_or(Some(f64::NEG_INFINITY), |a| a.acquired_t_s);
                let after_held = |e: &&TrackerEventTime| held_from.is_some_and(|t| e.t_s >= t);
                let unresolved = s.unresolved.iter().find(after_held).map_or(String::new(), |e| {
                    format!(
                        "; the target was beyond the tracker's resolution (`unresolved`) \
                         from {:.2} s",
                        e.t_s
                    )
                });
                format!(
                    "tracking lost (ground truth) for {t:.2} s in {} event(s) (allowed \
                     {allowed:.2} s): {}{unresolved}",
                    s.tracking_loss_events,
                    s.lost_by_cause_s.describe()
                )
            } else {
                format!(
                    "tracking lost (ground truth) for {t:.2} s in {} event(s) (allowed {allowed:.2} s)",
                    s.tracking_loss_events
                )
            },
        });
    }
    if let Some(allowed) = expect.max_lateral_deviation_m {
        let d = s.lateral_path_error_m.max_abs;
        out.push(Criterion {
            name: "max_lateral_deviation".into(),
            passed: d <= allowed,
            value: d,
            limit: allowed,
            message: format!(
                "lateral deviation from the lead's path reached {d:.2} m (allowed {allowed:.2} m)"
            ),
        });
    }
    if expect.no_collision {
        out.push(Criterion {
            name: "no_collision".into(),
            passed: s.collisions == 0,
            value: s.collisions as f64,
            limit: 0.0,
            message: format!("the vehicles collided {} time(s) (allowed 0)", s.collisions),
        });
    }
    if let Some(required) = expect.min_distance_m {
        let d = s.distance_m;
        out.push(Criterion {
            name: "min_distance".into(),
            passed: d >= required,
            value: d,
            limit: required,
            message: format!(
                "the chase vehicle drove {d:.1} m (required at least {required:.1} m)"
            ),
        });
    }
    if let Some(allowed) = expect.max_range_error_p95_m {
        // No tracked frame at all has no error to bound: the criterion fails (the loss
        // criteria say why).
        let (passed, value, said) = match s.range_error_m.p95_abs {
            Some(e) => (e <= allowed, e, format!("{e:.3} m")),
            None => (
                false,
                f64::INFINITY,
                "not measured (no tracked frame)".into(),
            ),
        };
        out.push(Criterion {
            name: "max_range_error_p95".into(),
            passed,
            value,
            limit: allowed,
            message: format!(
                "the range error's 95th percentile was {said} (allowed {allowed:.3} m)"
            ),
        });
    }
    if let Some(allowed) = expect.max_loss_events {
        let n = s.tracking_loss_events;
        out.push(Criterion {
            name: "max_loss_events".into(),
            passed: n <= allowed,
            value: n as f64,
            limit: allowed as f64,
            message: format!("the target was lost {n} time(s) (allowed {allowed})"),
        });
    }
    if let Some(allowed) = expect.max_false_alarm_s {
        let t = s.false_alarm_s;
        out.push(Criterion {
            name: "max_false_alarm".into(),
            passed: t <= allowed + TIME_TOLERANCE_S,
            value: t,
            limit: allowed,
            message: format!(
                "the tracker raised a false alarm (not `tracking`, its estimate within the \
                 tolerance) for {t:.2} s, {} frames at the longest (allowed {allowed:.2} s)",
                s.longest_false_alarm_frames
            ),
        });
    }
    acquisition::check(s, expect, &mut out);
    traffic::check(s, expect, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::frames_csv::tests::record;
    use sim_core::TrackerStatus;

    /// The median positive step between consecutive capture times of `records`, else 1/15 s.
    fn frame_period(records: &[FrameRecord]) -> f64 {
        let mut period = FramePeriod::default();
        for r in records {
            period.push(r.t_s);
        }
        period.period()
    }

    fn run(n: u64) -> Vec<FrameRecord> {
        (0..n).map(record).collect()
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9
    }

    #[test]
    fn duration_and_frame_period_from_capture_times() {
        let rs = run(30);
        let s = Summary::compute("x", 1, &rs, &Expect::default(), 1.0);
        assert_eq!(s.frames, 30);
        assert!(close(s.duration_s, 2.0), "{}", s.duration_s);
        // 10 Hz records: the period comes from the records, not the 15 Hz default.
        let mut rs = run(10);
        for (i, r) in rs.iter_mut().enumerate() {
            r.t_s = i as f64 * 0.1;
        }
        assert!(close(frame_period(&rs), 0.1));
        let s = Summary::compute("x", 1, &rs, &Expect::default(), 1.0);
        assert!(close(s.duration_s, 1.0), "{}", s.duration_s);
        // One frame: the 15 Hz fallback.
        assert!(close(frame_period(&rs[..1]), 1.0 / 15.0));
    }

    #[test]
    fn the_frame_period_is_the_lower_median_step_however_the_steps_come() {
        // Jittered steps, some repeated, a zero and a backward step among them: the kept
        // counts give what sorting every positive step gives.
        let mut t = 0.0;
        let mut rs = run(200);
        for (i, r) in rs.iter_mut().enumerate() {
            t += match i % 7 {
                0 => 0.0,
                3 => -0.01,
                k => 0.05 + 0.01 * (((i * 31) % 11) as f64) + 0.001 * k as f64,
            };
            r.t_s = t;
        }
        let mut steps: Vec<f64> = rs
            .windows(2)
            .map(|p| p[1].t_s - p[0].t_s)
            .filter(|dt| *dt > 0.0)
            .collect();
        steps.sort_by(f64::total_cmp);
        assert_eq!(frame_period(&rs), steps[(steps.len() - 1) / 2]);
    }

    #[test]
    fn time_partly_out_of_view_is_counted_whether_lost_or_not() {
        // 30 frames at 15 Hz; frames 5..11 partly out of view, of which 9 and 10 lost.
        let mut rs = run(30);
        for r in &mut rs[5..11] {
            r.target_in_view = false;
            r.target_partly_out_of_view = true;
        }
        for r in &mut rs[9..11] {
            r.lost_truth = true;
            r.loss_cause = LossCause::OutOfView;
        }
        let s = Summary::compute("x", 1, &rs, &Expect::default(), 1.0);
        assert!(
            close(s.partly_out_of_view_s, 6.0 / 15.0),
            "{}",
            s.partly_out_of_view_s
        );
        assert!(close(s.tracking_lost_s, 2.0 / 15.0));
        assert!(close(s.lost_by_cause_s.out_of_view, 2.0 / 15.0));
        assert_eq!(s.tracking_loss_events, 1);
    }

    #[test]
    fn a_dropped_frame_lengthens_its_predecessor() {
        // Frames 0..15 with frame 7 missing: frame 6 stands for 2/15 s.
        let mut rs = run(15);
        rs.remove(7);
        for r in rs.iter_mut().filter(|r| r.frame == 6) {
            r.gap_m = 20.0;
        }
        let expect = Expect {
            gap_band_m: Some([5.0, 15.0]),
            ..Expect::default()
        };
        let s = Summary::compute("x", 1, &rs, &expect, 1.0);
        assert!(close(s.duration_s, 1.0), "{}", s.duration_s);
        assert!(close(s.time_outside_gap_band_s, 2.0 / 15.0));
    }

    #[test]
    fn gap_band_time_and_stats() {
        // 30 frames at 15 Hz; frames 10..16 (6 frames = 0.4 s) at 16 m, frame 20 at 4 m.
        let mut rs = run(30);
        for r in &mut rs[10..16] {
            r.gap_m = 16.0;
        }
        rs[20].gap_m = 4.0;
        let expect = Expect {
            gap_band_m: Some([5.0, 15.0]),
            max_time_outside_gap_band_s: Some(0.3),
            ..Expect::default()
        };
        let s = Summary::compute("x", 1, &rs, &expect, 1.0);
        assert!(close(s.time_outside_gap_band_s, 7.0 / 15.0));
        assert_eq!(s.gap_m.min, 4.0);
        assert_eq!(s.gap_m.max, 16.0);
        assert!(close(s.gap_m.mean, (23.0 * 10.0 + 6.0 * 16.0 + 4.0) / 30.0));
        assert!(!s.passed);
        assert_eq!(
            s.failures,
            vec!["gap left the band [5, 15] m for 0.47 s (allowed 0.30 s; gap ranged 4.00 to 16.00 m)"]
        );
        // The band's edges are inside it; with enough allowance it passes.
        let mut rs = run(30);
        rs[3].gap_m = 5.0;
        rs[4].gap_m = 15.0;
        let s = Summary::compute("x", 1, &rs, &expect, 1.0);
        assert_eq!(s.time_outside_gap_band_s, 0.0);
        // A positive zero: summary.json and the messages say "0.00 s", not "-0.00 s".
        assert!(s.time_outside_gap_band_s.is_sign_positive());
        assert!(s.tracking_lost_s.is_sign_positive());
        assert!(s.passed, "{:?}", s.failures);
    }

    #[test]
    fn loss_events_are_maximal_runs_of_lost_frames() {
        let mut rs = run(45);
        for i in [0, 1, 2, 10, 20, 21, 44] {
            rs[i].lost_truth = true;
        }
        // The tracker's own word is counted apart.
        rs[5].status = TrackerStatus::Lost;
        rs[6].status = TrackerStatus::Coasting;
        rs[7].status = TrackerStatus::Coasting;
        let expect = Expect {
            max_lost_s: Some(0.4),
            ..Expect::default()
        };
        let s = Summary::compute("x", 1, &rs, &expect, 1.0);
        assert_eq!(s.tracking_loss_events, 4);
        assert!(close(s.tracking_lost_s, 7.0 / 15.0));
        assert!(close(s.tracker_lost_s, 1.0 / 15.0));
        assert!(close(s.tracker_coasting_s, 2.0 / 15.0));
        assert_eq!(
            s.failures,
            vec!["tracking lost (ground truth) for 0.47 s in 4 event(s) (allowed 0.40 s): 0.47 s tracker"]
        );
        // With causes: each event takes the cause of most of its frames.
        rs[0].loss_cause = LossCause::OutOfView;
        rs[1].loss_cause = LossCause::OutOfView;
        rs[2].loss_cause = LossCause::Tracker;
        rs[10].loss_cause = LossCause::Occluded;
        rs[20].loss_cause = LossCause::Tracker;
        rs[21].loss_cause = LossCause::Tracker;
        rs[44].loss_cause = LossCause::OutOfView;
        let s = Summary::compute("x", 1, &rs, &expect, 1.0);
        let causes: Vec<LossCause> = s.loss_events.iter().map(|e| e.cause).collect();
        assert_eq!(
            causes,
            [
                LossCause::OutOfView,
                LossCause::Occluded,
                LossCause::Tracker,
                LossCause::OutOfView
            ]
        );
        assert!(close(s.lost_by_cause_s.out_of_view, 3.0 / 15.0));
        assert!(close(s.lost_by_cause_s.occluded, 1.0 / 15.0));
        assert!(close(s.lost_by_cause_s.tracker, 3.0 / 15.0));
        assert_eq!(
            s.failures,
            vec!["tracking lost (ground truth) for 0.47 s in 4 event(s) (allowed 0.40 s): 0.20 s out_of_view, 0.20 s tracker, 0.07 s occluded"]
        );
        assert_eq!(stream::count_runs([false, true, true, false, true]), 2);
        assert_eq!(stream::count_runs([false, false]), 0);
    }

    #[test]
    fn a_loss_beyond_the_trackers_resolution_says_so() {
        let mut rs = run(30);
        for r in &mut rs[15..] {
            r.lost_truth = true;
        }
        rs[12].tracker_event = "unresolved".into();
        rs[20].tracker_event = "reacquired".into();
        let expect = Expect {
            max_lost_s: Some(0.0),
            ..Expect::default()
        };
        let s = Summary::compute("x", 1, &rs, &expect, 1.0);
        assert_eq!(s.unresolved.len(), 1);
        assert_eq!(s.reacquired.len(), 1);
        assert_eq!(
            s.failures,
            vec![
                "tracking lost (ground truth) for 1.00 s in 1 event(s) (allowed 0.00 s): 1.00 s \
                  tracker; the target was beyond the tracker's resolution (`unresolved`) from \
                  0.80 s"
            ]
        );
    }

    #[test]
    fn range_error_skips_lost_and_out_of_view_frames() {
        // Errors 1..=20 m on frames 0..20; frames 20..25 lost or out of view with huge errors.
        let mut rs = run(25);
        for (i, r) in rs.iter_mut().enumerate() {
            r.est_range_m = r.true_range_m + (i as f64 + 1.0) * if i % 2 == 0 { 1.0 } else { -1.0 };
        }
        for r in &mut rs[20..23] {
            r.lost_truth = true;
            r.est_range_m = 1000.0;
        }
        for r in &mut rs[23..] {
            r.target_in_view = false;
            r.est_range_m = 1000.0;
        }
        rs[0].est_range_m = f64::NAN; // not counted either
        let s = Summary::compute("x", 1, &rs, &Expect::default(), 1.0);
        // Frames 1..20: errors 2..=20, 19 values; mean 11; rank ceil(0.95*19) = 19 -> 20.
        assert_eq!(s.range_error_m.frames, 19);
        assert!(close(s.range_error_m.mean_abs.unwrap(), 11.0));
        assert_eq!(s.range_error_m.p95_abs, Some(20.0));
        // Nearest rank on 1..=100: the 95th value; on 1..=20: the 19th; on one, that one.
        for (n, want) in [(100, 95.0), (20, 19.0), (1, 1.0)] {
            let mut errors = range_errors::RangeErrors::default();
            for v in 1..=n {
                errors.push(f64::from(v));
            }
            assert_eq!(errors.finish().unwrap().1, Some(want), "{n} values");
        }
        // No tracked frame: null, not NaN.
        for r in &mut rs {
            r.lost_truth = true;
        }
        let s = Summary::compute("x", 1, &rs, &Expect::default(), 1.0);
        assert_eq!(s.range_error_m, RangeError::default());
    }

    #[test]
    fn lateral_collisions_distance_and_realtime_factor() {
        let mut rs = run(30);
        rs[4].lateral_deviation_m = -1.5;
        for i in [8, 9, 10, 15] {
            rs[i].collision = true;
        }
        let expect = Expect {
            max_lateral_deviation_m: Some(1.0),
            no_collision: true,
            min_distance_m: Some(100.0),
            ..Expect::default()
        };
        let s = Summary::compute("x", 1, &rs, &expect, 0.5);
        assert_eq!(s.lateral_path_error_m.max_abs, 1.5);
        assert!(close(
            s.lateral_path_error_m.mean_abs,
            (29.0 * 0.1 + 1.5) / 30.0
        ));
        assert_eq!(s.collisions, 2);
        assert!(close(s.distance_m, 5.0 * 29.0 / 15.0));
        assert!(close(s.realtime_factor.unwrap(), 4.0));
        assert_eq!(
            s.failures,
            vec![
                "lateral deviation from the lead's path reached 1.50 m (allowed 1.00 m)",
                "the vehicles collided 2 time(s) (allowed 0)",
                "the chase vehicle drove 9.7 m (required at least 100.0 m)",
            ]
        );
        let names: Vec<&str> = s.criteria.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(
            names,
            ["max_lateral_deviation", "no_collision", "min_distance"]
        );
        assert_eq!(
            Summary::compute("x", 1, &rs, &expect, 0.0).realtime_factor,
            None
        );
    }

    #[test]
    fn no_criteria_passes_and_no_frames_fails() {
        let s = Summary::compute("x", 1, &run(3), &Expect::default(), 1.0);
        assert!(s.passed);
        assert!(s.criteria.is_empty());
        let s = Summary::compute("x", 1, &[], &Expect::default(), 1.0);
        assert!(!s.passed);
        assert_eq!(s.frames, 0);
        assert_eq!(s.duration_s, 0.0);
        assert_eq!(
            s.failures,
            ["the run recorded no frames (at least 1 needed)"]
        );
    }

    #[test]
    fn false_alarms_are_timed_with_their_longest_run_and_judged() {
        let mut rs = run(30);
        for i in [3, 4, 5, 10, 20, 21] {
            rs[i].false_alarm = true;
        }
        let expect = Expect {
            max_false_alarm_s: Some(0.3),
            ..Expect::default()
        };
        let s = Summary::compute("x", 1, &rs, &expect, 1.0);
        let period = frame_period(&rs);
        assert!(
            (s.false_alarm_s - 6.0 * period).abs() < 1e-9,
            "{}",
            s.false_alarm_s
        );
        assert_eq!(s.longest_false_alarm_frames, 3);
        let c = &s.criteria[0];
        assert_eq!(c.name, "max_false_alarm");
        assert!(!c.passed, "0.4 s of false alarm passed a 0.3 s limit");
        assert!(
            c.message.contains("3 frames at the longest"),
            "{}",
            c.message
        );
        let loose = Expect {
            max_false_alarm_s: Some(0.4),
            ..Expect::default()
        };
        assert!(Summary::compute("x", 1, &rs, &loose, 1.0).passed);
        let none = Summary::compute("x", 1, &run(30), &expect, 1.0);
        assert_eq!(
            (none.false_alarm_s, none.longest_false_alarm_frames),
            (0.0, 0)
        );
    }

    #[test]
    fn range_error_p95_and_loss_event_criteria() {
        let mut rs = run(45);
        for i in [0, 10, 20, 21] {
            rs[i].lost_truth = true;
        }
        let expect = Expect {
            max_range_error_p95_m: Some(0.2),
            max_loss_events: Some(2),
            ..Expect::default()
        };
        let s = Summary::compute("x", 1, &rs, &expect, 1.0);
        assert_eq!(s.tracking_loss_events, 3);
        let p95 = s.range_error_m.p95_abs.unwrap();
        let names: Vec<_> = s.criteria.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["max_range_error_p95", "max_loss_events"]);
        let (r, l) = (&s.criteria[0], &s.criteria[1]);
        assert_eq!((r.passed, r.value, r.limit), (p95 <= 0.2, p95, 0.2));
        assert_eq!((l.passed, l.value, l.limit), (false, 3.0, 2.0));
        assert_eq!(l.message, "the target was lost 3 time(s) (allowed 2)");
        // Loose enough limits pass.
        let expect = Expect {
            max_range_error_p95_m: Some(p95),
            max_loss_events: Some(3),
            ..Expect::default()
        };
        assert!(Summary::compute("x", 1, &rs, &expect, 1.0).passed);
        // No tracked frame: the range criterion cannot pass.
        for r in &mut rs {
            r.lost_truth = true;
        }
        let expect = Expect {
            max_range_error_p95_m: Some(10.0),
            ..Expect::default()
        };
        let s = Summary::compute("x", 1, &rs, &expect, 1.0);
        assert!(!s.passed);
        assert!(s.failures[0].contains("not measured"), "{:?}", s.failures);
    }

    #[test]
    fn json_has_the_documented_keys() {
        let s = Summary::compute("nist-grounds", 7, &run(15), &Expect::default(), 2.0);
        let v = serde_json::to_value(&s).unwrap();
        for key in [
            "scenario",
            "seed",
            "duration_s",
            "frames",
            "passed",
            "failures",
            "gap_m",
            "time_outside_gap_band_s",
            "tracking_lost_s",
            "tracking_loss_events",
            "imprecise_share",
            "tracker_lost_s",
            "tracker_coasting_s",
            "range_error_m",
            "lateral_path_error_m",
            "collisions",
            "distance_m",
            "wall_s",
            "realtime_factor",
            "timing",
            "schema_version",
            "carfollow_version",
            "overrides",
        ] {
            assert!(v.get(key).is_some(), "missing {key}");
        }
        assert_eq!(v["schema_version"], SCHEMA_VERSION);
        assert_eq!(v["carfollow_version"], env!("CARGO_PKG_VERSION"));
        // The commit is there exactly when the build knew it.
        assert_eq!(
            v.get("git_commit").and_then(|c| c.as_str()),
            option_env!("CARFOLLOW_GIT_COMMIT")
        );
        assert!(v.get("resolved_scenario").is_none());
        assert_eq!(v["gap_m"]["min"], 10.0);
        assert_eq!(v["range_error_m"]["p95_abs"], 0.25);
        assert_eq!(v["realtime_factor"], 0.5);
    }
}

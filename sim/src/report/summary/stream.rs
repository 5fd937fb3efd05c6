//! The summary built as the records arrive ([`SummaryBuilder`]), so that a run keeps no
//! record once it is written: what it holds in memory grows with the run only by its loss
//! and tracker events. The range errors of its tracked frames, which the exact 95th
//! percentile needs, go to disk beyond 65 536 of them ([`RangeErrors`]).
//!
//! A frame's weight is the time to the next frame, known only when that frame arrives, or
//! the frame period (the median step, known only at the end) for the last frame and after a
//! step that is not positive. So each time sum is kept in two parts: the sum over the frames
//! whose step is known, and the count (or the sum of values) of the frames that stand for
//! one period; the total is `known + period × periods`.

use std::collections::BTreeMap;

use sim_core::{FrameRecord, LossCause, TrackerStatus};
use tracker::TrackEvent;

use super::acquisition::FirstAcquisition;
use super::range_errors::RangeErrors;
use super::traffic::TrafficStats;
use super::{
    GapStats, LateralError, LossEvent, LostByCause, RangeError, Summary, TrackerEventTime,
    DEFAULT_FRAME_PERIOD_S, IMPRECISE_CENTRE_PX, IMPRECISE_SCALE, SCHEMA_VERSION,
};

/// The median positive step between consecutive capture times, kept as a count of each
/// step: steps are whole numbers of physics steps, so there are few distinct ones.
#[derive(Clone, Debug, Default)]
pub(crate) struct FramePeriod {
    /// Count of each positive finite step, keyed by its bits (for positive floats the bits
    /// order as the values do).
    steps: BTreeMap<u64, u64>,
    count: u64,
    last_t: Option<f64>,
}

impl FramePeriod {
    /// Takes the next frame's capture time.
    pub fn push(&mut self, t_s: f64) {
        if let Some(last) = self.last_t.replace(t_s) {
            let dt = t_s - last;
            if dt.is_finite() && dt > 0.0 {
                *self.steps.entry(dt.to_bits()).or_default() += 1;
                self.count += 1;
            }
        }
    }

    /// The median step (the lower of the two middle ones), else 1/15 s.
    pub fn period(&self) -> f64 {
        if self.count == 0 {
            return DEFAULT_FRAME_PERIOD_S;
        }
        let mut rank = (self.count - 1) / 2;
        for (&bits, &n) in &self.steps {
            if rank < n {
                return f64::from_bits(bits);
            }
            rank -= n;
        }
        unreachable!("the counts add up to count")
    }
}

/// What each frame adds to the time-weighted sums, in [`Weighted`]'s slots.
const OUTSIDE_BAND: usize = 0;
const LOST: usize = 1;
const LOST_OUT_OF_VIEW: usize = 2;
const LOST_OCCLUDED: usize = 3;
const LOST_TRACKER: usize = 4;
const SAYS_LOST: usize = 5;
const SAYS_COASTING: usize = 6;
const PARTLY_OUT: usize = 7;
const GAP: usize = 8;
const LATERAL: usize = 9;
const DURATION: usize = 10;
const FALSE_ALARM: usize = 11;
const LOST_LEFT_PATH: usize = 12;
const LOST_WRONG_VEHICLE: usize = 13;
const NOT_ACQUIRED: usize = 14;
const LOST_LOW_CONTRAST: usize = 15;
const SLOTS: usize = 16;

/// Time-weighted sums: over frames of known step, and over frames that stand for a period.
#[derive(Clone, Debug, Default)]
struct Weighted {
    known: [f64; SLOTS],
    periods: [f64; SLOTS],
}

impl Weighted {
    fn total(&self, slot: usize, period: f64) -> f64 {
        // From +0.0: a sum of nothing prints as "0.0", never "-0.0".
        0.0 + self.known[slot] + period * self.periods[slot]
    }
}

/// A loss event being followed, with its frames per cause (in [`LossCause::ALL`] order).
#[derive(Clone, Copy, Debug)]
struct OpenLoss {
    event: LossEvent,
    counts: [u64; LossCause::ALL.len()],
}

/// The ground-truth loss events, followed frame by frame.
#[derive(Clone, Debug, Default)]
pub(crate) struct LossEvents {
    done: Vec<LossEvent>,
    open: Option<OpenLoss>,
}

impl LossEvents {
    /// Takes the next frame.
    pub fn push(&mut self, r: &FrameRecord) {
        let index = LossCause::ALL.iter().position(|&a| a == r.loss_cause);
        match (&mut self.open, track_lost(r)) {
            (None, true) => {
                let mut counts = [0; LossCause::ALL.len()];
                if let Some(k) = index {
                    counts[k] += 1;
                }
                self.open = Some(OpenLoss {
                    event: LossEvent {
                        start_frame: r.frame,
                        start_t_s: r.t_s,
                        frames: 1,
                        report_delay_frames: (r.status != TrackerStatus::Tracking).then_some(0),
                        cause: LossCause::None,
                    },
                    counts,
                });
            }
            (Some(open), true) => {
                let e = &mut open.event;
                if e.report_delay_frames.is_none() && r.status != TrackerStatus::Tracking {
                    e.report_delay_frames = Some(e.frames);
                }
                e.frames += 1;
                if let Some(k) = index {
                    open.counts[k] += 1;
                }
            }
            (Some(_), false) => self.close(),
            (None, false) => {}
        }
    }

    fn close(&mut self) {
        if let Some(OpenLoss { mut event, counts }) = self.open.take() {
            let most = (0..counts.len()).fold(0, |m, k| if counts[k] > counts[m] { k } else { m });
            // A lost frame without a cause (records from before causes were kept) is the
            // tracker's.
            event.cause = if counts[most] > 0 {
                LossCause::ALL[most]
            } else {
                LossCause::Tracker
            };
            self.done.push(event);
        }
    }

    /// Every event, the open one closed.
    pub fn finish(mut self) -> Vec<LossEvent> {
        self.close();
        self.done
    }
}

/// Whether the frame is a lost track: lost by the ground truth, and not for want of a
/// first acquisition ([`LossCause::is_track_loss`]).
pub(super) fn track_lost(r: &FrameRecord) -> bool {
    r.lost_truth && r.loss_cause.is_track_loss()
}

/// Maximal runs of `true`, counted as they come, with the longest run's length in frames.
#[derive(Clone, Copy, Debug, Default)]
struct RunCount {
    count: u64,
    previous: bool,
    current: u64,
    longest: u64,
}

impl RunCount {
    fn push(&mut self, f: bool) {
        if f && !self.previous {
            self.count += 1;
        }
        self.current = if f { self.current + 1 } else { 0 };
        self.longest = self.longest.max(self.current);
        self.previous = f;
    }
}

/// Maximal runs of `true` in `flags`.
#[cfg(test)]
pub(super) fn count_runs(flags: impl IntoIterator<Item = bool>) -> u64 {
    let mut runs = RunCount::default();
    for f in flags {
        runs.push(f);
    }
    runs.count
}

/// The frame waiting for the next one to know its weight: its time and what it adds.
#[derive(Clone, Copy, Debug)]
struct Pending {
    t_s: f64,
    values: [f64; SLOTS],
}

/// A run's summary, built one record at a time (see the module notes): feed it with
/// [`SummaryBuilder::push`], and [`super::Summary::of`] gives the summary, the same as
/// [`super::Summary::compute`] over the same records.
#[derive(Debug)]
pub struct SummaryBuilder {
    gap_band_m: Option<[f64; 2]>,
    frames: u64,
    period: FramePeriod,
    weighted: Weighted,
    pending: Option<Pending>,
    gap_min: f64,
    gap_max: f64,
    lateral_max: f64,
    lost_runs: RunCount,
    collision_runs: RunCount,
    false_alarm_runs: RunCount,
    loss_events: LossEvents,
    first_acquisition: FirstAcquisition,
    whole_in_view: u64,
    imprecise: u64,
    silent_loss_frames: u64,
    reacquired: Vec<TrackerEventTime>,
    unresolved: Vec<TrackerEventTime>,
    range_errors: RangeErrors,
    distance_m: f64,
    traffic: TrafficStats,
    /// Whether a frame was lost to low contrast (its time is written only then).
    low_contrast: bool,
}

impl SummaryBuilder {
    /// An empty summary, timing the gap outside `gap_band_m` (the scenario's
    /// `expect.gap_band_m`).
    pub fn new(gap_band_m: Option<[f64; 2]>) -> SummaryBuilder {
        SummaryBuilder {
            gap_band_m,
            frames: 0,
            period: FramePeriod::default(),
            weighted: Weighted::default(),
            pending: None,
            gap_min: f64::INFINITY,
            gap_max: f64::NEG_INFINITY,
            lateral_max: 0.0,
            lost_runs: RunCount::default(),
            collision_runs: RunCount::default(),
            false_alarm_runs: RunCount::default(),
            loss_events: LossEvents::default(),
            first_acquisition: FirstAcquisition::default(),
            whole_in_view: 0,
            imprecise: 0,
            silent_loss_frames: 0,
            reacquired: Vec::new(),
            unresolved: Vec::new(),
            range_errors: RangeErrors::default(),
            distance_m: 0.0,
            traffic: TrafficStats::default(),
            low_contrast: false,
        }
    }

    /// The band the builder times the gap outside of.
    pub fn gap_band_m(&self) -> Option<[f64; 2]> {
        self.gap_band_m
    }

    /// Takes the next record (records come in frame order).
    pub fn push(&mut self, r: &FrameRecord) {
        self.frames += 1;
        self.low_contrast |= r.loss_cause == LossCause::LowContrast;
        self.period.push(r.t_s);
        let lost_as = |cause: bool| f64::from(u8::from(track_lost(r) && cause));
        let mut values = [0.0; SLOTS];
        values[OUTSIDE_BAND] = match self.gap_band_m {
            Some([lo, hi]) => f64::from(u8::from(!(lo..=hi).contains(&r.gap_m))),
            None => 0.0,
        };
        values[LOST] = lost_as(true);
        values[LOST_OUT_OF_VIEW] = lost_as(r.loss_cause == LossCause::OutOfView);
        values[LOST_OCCLUDED] = lost_as(r.loss_cause == LossCause::Occluded);
        // A lost frame without a cause (records from before causes were kept) is the
        // tracker's.
        values[LOST_TRACKER] =
            lost_as(matches!(r.loss_cause, LossCause::Tracker | LossCause::None));
        values[LOST_LOW_CONTRAST] = lost_as(r.loss_cause == LossCause::LowContrast);
        values[LOST_LEFT_PATH] = lost_as(r.loss_cause == LossCause::LeftPath);
        values[LOST_WRONG_VEHICLE] = lost_as(r.loss_cause == LossCause::WrongVehicle);
        values[SAYS_LOST] = f64::from(u8::from(r.status == TrackerStatus::Lost));
        values[SAYS_COASTING] = f64::from(u8::from(r.status == TrackerStatus::Coasting));
        values[PARTLY_OUT] = f64::from(u8::from(r.target_partly_out_of_view));
        values[GAP] = r.gap_m;
        values[LATERAL] = r.lateral_deviation_m.abs();
        values[DURATION] = 1.0;
        values[FALSE_ALARM] = f64::from(u8::from(r.false_alarm));
        values[NOT_ACQUIRED] = f64::from(u8::from(r.loss_cause == LossCause::NotAcquired));
        if let Some(p) = self.pending.replace(Pending { t_s: r.t_s, values }) {
            let dt = r.t_s - p.t_s;
            self.weigh(p, (dt.is_finite() && dt > 0.0).then_some(dt));
        }

        self.gap_min = self.gap_min.min(r.gap_m);
        self.gap_max = self.gap_max.max(r.gap_m);
        self.lateral_max = self.lateral_max.max(r.lateral_deviation_m.abs());
        self.lost_runs.push(track_lost(r));
        self.collision_runs.push(r.collision);
        self.false_alarm_runs.push(r.false_alarm);
        self.loss_events.push(r);
        self.first_acquisition.push(r);
        if r.target_in_view {
            self.whole_in_view += 1;
            let centre = (r.est_cx - r.true_cx).hypot(r.est_cy - r.true_cy);
            let scale = (r.est_scale / r.true_scale - 1.0).abs();
            if !(centre <= IMPRECISE_CENTRE_PX && scale <= IMPRECISE_SCALE) {
                self.imprecise += 1;
            }
            if !r.lost_truth {
                let e = (r.est_range_m - r.true_range_m).abs();
                if e.is_finite() {
                    self.range_errors.push(e);
                }
            }
        }
        if track_lost(r) && r.status == TrackerStatus::Tracking {
            self.silent_loss_frames += 1;
        }
        if !r.tracker_event.is_empty() {
            let event = TrackerEventTime {
                frame: r.frame,
                t_s: r.t_s,
                event: r.tracker_event.clone(),
            };
            if r.tracker_event == TrackEvent::Unresolved.as_str() {
                self.unresolved.push(event);
            } else {
                self.reacquired.push(event);
            }
        }
        self.distance_m = r.chase_distance_m;
        self.traffic.push(r);
    }

    /// Adds a frame's values with its weight: `dt`, or one period when `None`.
    fn weigh(&mut self, p: Pending, dt: Option<f64>) {
        for (slot, v) in p.values.into_iter().enumerate() {
            match dt {
                Some(dt) => self.weighted.known[slot] += v * dt,
                None => self.weighted.periods[slot] += v,
            }
        }
    }

    /// What the records came to, before the criteria (`criteria`, `failures` and `passed`
    /// are left empty, and the caller's fields unset): for a scenario of that name and
    /// seed, with the `[expect]` band `gap_band_m`, and the run's wall-clock time.
    pub(super) fn measured(
        mut self,
        scenario: &str,
        seed: u64,
        gap_band_m: Option<[f64; 2]>,
        wall_s: f64,
        traffic_asked: bool,
    ) -> Summary {
        if let Some(p) = self.pending.take() {
            self.weigh(p, None);
        }
        let period = self.period.period();
        let time = |slot| self.weighted.total(slot, period);
        let duration_s = time(DURATION);
        let (gap_m, lateral_path_error_m) = if self.frames == 0 {
            (GapStats::default(), LateralError::default())
        } else {
            (
                GapStats {
                    min: self.gap_min,
                    mean: time(GAP) / duration_s,
                    max: self.gap_max,
                },
                LateralError {
                    mean_abs: time(LATERAL) / duration_s,
                    max_abs: self.lateral_max,
                },
            )
        };
        let loss_events = self.loss_events.finish();
        Summary {
            schema_version: SCHEMA_VERSION,
            carfollow_version: env!("CARGO_PKG_VERSION").to_owned(),
            git_commit: option_env!("CARFOLLOW_GIT_COMMIT").map(str::to_owned),
            overrides: Vec::new(),
            resolved_scenario: None,
            scenario: scenario.to_owned(),
            seed,
            tracker: None,
            controller: None,
            duration_s,
            frames: self.frames,
            passed: false,
            failures: Vec::new(),
            criteria: Vec::new(),
            gap_m,
            gap_band_m,
            time_outside_gap_band_s: time(OUTSIDE_BAND),
            tracking_lost_s: time(LOST),
            tracking_loss_events: self.lost_runs.count,
            lost_by_cause_s: LostByCause {
                out_of_view: time(LOST_OUT_OF_VIEW),
                occluded: time(LOST_OCCLUDED),
                low_contrast: self.low_contrast.then(|| time(LOST_LOW_CONTRAST)),
                tracker: time(LOST_TRACKER),
                left_path: self.traffic.seen().then(|| time(LOST_LEFT_PATH)),
                wrong_vehicle: self.traffic.seen().then(|| time(LOST_WRONG_VEHICLE)),
            },
            acquisition: self.first_acquisition.finish(time(NOT_ACQUIRED)),
            partly_out_of_view_s: time(PARTLY_OUT),
            imprecise_share: (self.whole_in_view > 0)
                .then(|| self.imprecise as f64 / self.whole_in_view as f64),
            tracker_lost_s: time(SAYS_LOST),
            tracker_coasting_s: time(SAYS_COASTING),
            silent_loss_frames: self.silent_loss_frames,
            false_alarm_s: time(FALSE_ALARM),
            longest_false_alarm_frames: self.false_alarm_runs.longest,
            max_loss_report_delay_frames: loss_events
                .iter()
                .map(|e| e.report_delay_frames.unwrap_or(e.frames))
                .max(),
            loss_events,
            reacquired: self.reacquired,
            unresolved: self.unresolved,
            range_error_m: range_error(self.range_errors),
            lateral_path_error_m,
            collisions: self.collision_runs.count,
            distance_m: self.distance_m,
            traffic: self.traffic.finish(period, traffic_asked),
            wall_s,
            realtime_factor: (wall_s > 0.0).then(|| duration_s / wall_s),
            timing: None,
            ended_by: None,
        }
    }
}

fn range_error(errors: RangeErrors) -> RangeError {
    let frames = errors.count();
    match errors.finish() {
        None => RangeError::default(),
        Some((mean, p95)) => RangeError {
            mean_abs: Some(mean),
            p95_abs: p95,
            frames,
        },
    }
}

//! The built-in tracker in traffic: which target it holds, how it acquires one, and when it
//! lets go.
//!
//! Not in the paper, whose teleoperator placed the target once (2.2). In traffic the
//! vehicle in the chase's lane changes: a car cuts in, the lead cuts out. When the tracker
//! holds nothing, it searches the whole image for one model a frame, in turn (the lead's
//! target, then each other kind's back), keeping only fits whose centre lies in the chase's
//! lane ([`LaneAhead`], through [`tracker::AcquireGate`]); this is robust mode's
//! whole-image search, which the paper's mode also takes its start from. It lets go of a
//! target the tracker says is lost, and of one that has left the lane for
//! `vehicle::LEFT_LANE_ARRIVALS` frames, as the chase controller judges a target in its lane. Holding nothing for long, it searches on one frame in three
//! ([`SEARCH_EVERY_FRAME_FOR`]).

use super::LaneAhead;
use tracker::robust::{acquire_scales, ACQUIRE_EVERY_FRAMES};
use tracker::{
    AcquireGate, Camera, GateRow, Status, TargetModel, TrackOutput, Tracker, TrackerConfig,
    TrackerError, TrackerMode,
};

// A held target is out of the lane when its centre lies more than half the lane's width
// and `vehicle::LANE_MARGIN_M` from the lane's centre, and has left it after
// `vehicle::LEFT_LANE_ARRIVALS` frames out in a row: the chase controller's own test of a
// target in its lane, so that the two agree.

/// How many frames in a row the tracker searches once it holds nothing, before it searches
/// on one frame in [`tracker::robust::ACQUIRE_EVERY_FRAMES`] only, as robust mode does after
/// a long loss: 15 frames (1 s), each model searched several times while a target just let
/// go of or hidden may still be near. A whole-image search costs tens of milliseconds.
pub const SEARCH_EVERY_FRAME_FOR: u64 = 15;

/// How many scales the acquisition gate is given at, spaced evenly in log scale across the
/// whole-image search's range.
const GATE_ROWS: usize = 32;

/// The heights above the road a target's centre may take, metres: from a low car's back
/// (its centre about 0.6 m up) to a tall truck's (about 2 m) and a board mounted high on
/// one, with room to spare.
const CENTRE_HEIGHT_M: [f64; 2] = [0.3, 3.0];

/// The margin about the gate's rows, pixels: the road's image is exact, and a target's
/// centre found by the search is within a pixel or two of its own.
const GATE_MARGIN_PX: f64 = 3.0;

/// What the acquisition holds, and how long it has been out of the lane or searching.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Hold {
    /// The model of the target held, if any.
    held: Option<usize>,
    /// The model the next search tries.
    next: usize,
    /// Frames in a row the held target's centre has been out of the lane.
    out_of_lane: u32,
    /// Frames since it last held a target (or since the start).
    idle: u64,
}

/// Which target the built-in tracker holds in traffic, and the searchers that find one.
#[derive(Clone, Debug)]
pub(crate) struct Acquisition {
    /// The targets it may hold: the lead's first, then each other kind's.
    models: Vec<TargetModel>,
    /// One robust-mode tracker a model, searching the whole image.
    searchers: Vec<Tracker>,
    /// The camera.
    camera: Camera,
    /// The tracker's own settings (its mode for a target once acquired).
    config: TrackerConfig,
    /// What it holds.
    hold: Hold,
}

impl Acquisition {
    /// Acquisition over `models` (the lead's target first) through `camera`, for a tracker
    /// with `config`; `held` says whether the tracker starts holding the lead's target.
    pub(crate) fn new(
        models: Vec<TargetModel>,
        camera: Camera,
        config: TrackerConfig,
        held: bool,
    ) -> Result<Acquisition, TrackerError> {
        let searching = TrackerConfig {
            mode: TrackerMode::Robust,
            ..config.clone()
        };
        let searchers = models
            .iter()
            .map(|m| Tracker::new_searching(m.clone(), camera, searching.clone()))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Acquisition {
            models,
            searchers,
            camera,
            config,
            hold: Hold {
                held: held.then_some(0),
                ..Hold::default()
            },
        })
    }

    /// What it holds, for going back to it.
    pub(crate) fn hold(&self) -> Hold {
        self.hold
    }

    /// Goes back to `hold` (taken while a target was held, so the searchers are as then).
    pub(crate) fn restore(&mut self, hold: Hold) {
        self.hold = hold;
    }

    /// The model of the target held, if any.
    pub(crate) fn held(&self) -> Option<usize> {
        self.hold.held
    }

    /// Whether this frame, holding nothing, it rests instead of searching (see
    /// [`SEARCH_EVERY_FRAME_FOR`]).
    pub(crate) fn resting(&self) -> bool {
        self.rests_in(1)
    }

    /// Whether it will rest `ahead` frames on (1: this frame), holding nothing until then.
    pub(crate) fn rests_in(&self, ahead: u64) -> bool {
        let n = self.hold.idle + ahead.saturating_sub(1);
        self.searching()
            && n >= SEARCH_EVERY_FRAME_FOR
            && !(n - SEARCH_EVERY_FRAME_FOR).is_multiple_of(ACQUIRE_EVERY_FRAMES)
    }

    /// A frame rested: counted, nothing stepped.
    pub(crate) fn rest(&mut self) {
        self.hold.idle += 1;
    }

    /// Whether it searches (holds nothing): the step then reads the whole image.
    pub(crate) fn searching(&self) -> bool {
        self.hold.held.is_none()
    }

    /// Judges the held target's step `out` against `lane`: lets go of it when the tracker
    /// says it is lost or its centre has been out of the lane for
    /// `vehicle::LEFT_LANE_ARRIVALS` frames. Returns whether it let go.
    pub(crate) fn judge_held(&mut self, out: &TrackOutput, lane: Option<&LaneAhead>) -> bool {
        let [x, _, z] = out.position_3d;
        let margin_m = f64::from(vehicle::LANE_MARGIN_M);
        let out_now = out.status == Status::Tracking
            && lane.is_some_and(|l| {
                l.offset_m(x, z)
                    .is_some_and(|d| d.abs() > l.half_width_m + margin_m)
            });
        let h = &mut self.hold;
        h.out_of_lane = if out_now { h.out_of_lane + 1 } else { 0 };
        let released = out.status == Status::Lost || h.out_of_lane >= vehicle::LEFT_LANE_ARRIVALS;
        if released {
            (h.held, h.out_of_lane, h.idle) = (None, 0, 0);
        }
        released
    }

    /// One frame's search, with the next model in turn: its output, and the tracker that
    /// holds what it acquired. `step` steps a tracker on the frame.
    pub(crate) fn search(
        &mut self,
        lane: Option<&LaneAhead>,
        step: impl FnOnce(&mut Tracker) -> TrackOutput,
    ) -> Result<(TrackOutput, Option<Tracker>), TrackerError> {
        let k = self.hold.next;
        let gate = lane.map(|l| self.gate(k, l));
        let searcher = &mut self.searchers[k];
        searcher.set_acquire_gate(gate);
        let out = step(searcher);
        self.hold.idle += 1;
        if out.status != Status::Tracking {
            self.hold.next = (k + 1) % self.models.len();
            return Ok((out, None));
        }
        // Acquired: robust mode holds it with the searcher's state; the paper's mode starts
        // its own tracker there, as from a teleoperator's placement.
        let holder = match self.config.mode {
            TrackerMode::Robust => {
                let mut holder = searcher.clone();
                holder.set_acquire_gate(None);
                holder
            }
            TrackerMode::Paper => Tracker::new(
                self.models[k].clone(),
                self.camera,
                self.config.clone(),
                out.estimate,
            )?,
        };
        searcher.release();
        (self.hold.held, self.hold.out_of_lane, self.hold.next) = (Some(k), 0, 0);
        Ok((out, Some(holder)))
    }

    /// Where model `k`'s target may be centred in the image: at each scale, its range (the
    /// model's nominal range over the scale, eq. 36), there the lane's columns, and the rows
    /// of a point [`CENTRE_HEIGHT_M`] above the lane's centre, with [`GATE_MARGIN_PX`] about
    /// them. Above is taken along the camera's −y: the camera's pitch moves those rows by
    /// well under the margin.
    fn gate(&self, k: usize, lane: &LaneAhead) -> AcquireGate {
        let nominal = self.models[k].nominal_range_m();
        let [lo, hi] = acquire_scales(&self.camera);
        let [lo, hi] = [lo / 1.1, hi * 1.1];
        let rows = (0..GATE_ROWS)
            .filter_map(|i| {
                let scale = lo * (hi / lo).powf(i as f64 / (GATE_ROWS - 1) as f64);
                let z = nominal / scale;
                let [x, ground_y] = lane.centre_at(z)?;
                let at = |x: f64, y: f64| self.camera.project([x, y, z]);
                let [left, top] = at(x - lane.half_width_m, ground_y - CENTRE_HEIGHT_M[1])?;
                let [right, bottom] = at(x + lane.half_width_m, ground_y - CENTRE_HEIGHT_M[0])?;
                let m = GATE_MARGIN_PX;
                Some(GateRow {
                    scale,
                    c_x: [left, right],
                    c_y: [top - m, bottom + m],
                })
            })
            .collect();
        AcquireGate::new(rows)
    }
}

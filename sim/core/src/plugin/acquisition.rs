//! The built-in tracker in traffic: which target it holds, how it acquires one, and when it
//! lets go.
//!
//! Not in the paper, whose teleoperator placed the target once (2.2). In traffic the
//! vehicle in the chase's lane changes: a car cuts in, the lead cuts out. When the tracker
//! holds nothing, it searches the whole image for one model a frame, in turn (the lead's
//! target, then each other kind's back), keeping only fits whose centre lies in the chase's
//! lane ([`LaneAhead`], through [`tracker::AcquireGate`]); this is robust mode's
//! whole-image search, which the paper's mode also takes its start from. Of the models that
//! fit one vehicle it holds the one that covers the most of its outline, and while its fit
//! is weak it looks for a better in the lane, of any model, the one held included, at a
//! scale or place the held target is not at ([`Acquisition::recheck`]). It lets go of a
//! target the tracker says is lost, of one that has left the lane for
//! `vehicle::LEFT_LANE_ARRIVALS` frames, as the chase controller judges a target in its
//! lane, and of one whose range shrinks faster than the chase drives, unless a search of
//! the lane on that frame finds the target ([`super::closing`]). Until its first hold it
//! searches every frame; holding nothing for long after a hold, it searches on one frame in
//! three ([`SEARCH_EVERY_FRAME_FOR`]).

use super::closing::Closing;
use super::{LaneAhead, TrackerInput};
use tracker::robust::{
    acquire_scales, ChamferSearch, ACQUIRE_EVERY_FRAMES, SEARCH_BELOW_COVERAGE, SEARCH_MARGIN,
};
use tracker::{
    AcquireGate, Camera, GateRow, Location, Status, TargetModel, TrackOutput, Tracker,
    TrackerConfig, TrackerError, TrackerMode,
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

/// How far from a found target's centre another model's centre may lie on the same
/// vehicle, in the found outline's widths (across) and heights (up and down): a board
/// mounted on a back, the back of a taller or lower kind, with room to spare.
const NEAR_REACH: f64 = 0.75;

/// How far from the found range another model may put the same vehicle: a model fitted to
/// part of another kind's back (a pickup's tailgate for a van's back) errs in range by the
/// ratio of their sizes.
const NEAR_RANGE_FACTOR: f64 = 1.5;

/// The scale ratio within which a fresh fit of the model held, about the held one's
/// centre, is the target held and not another: robust mode's search after a short loss
/// looks as far (a factor of 1.3).
const SAME_TARGET_SCALE: f64 = 1.3;

/// Whether a fresh fit of the model held, `found`, is the target held at `held`, whose
/// outline is `half_width_px` wide each side: a scale within [`SAME_TARGET_SCALE`] of the
/// held one's, and a centre within that half width of its centre.
fn same_target(held: Location, half_width_px: f64, found: Location) -> bool {
    let near = (found.c_x - held.c_x).hypot(found.c_y - held.c_y) <= half_width_px;
    near && (found.scale / held.scale).ln().abs() <= SAME_TARGET_SCALE.ln()
}

/// How much of a fit's outline lies on edges: the lesser of its two orientations'
/// coverages, the measure robust mode judges a fit by.
fn covered(out: &TrackOutput) -> f64 {
    out.coverage[0].min(out.coverage[1])
}

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
    /// Frames the target held has been held.
    held_for: u64,
    /// Whether it has held a target: until then it searches every frame, as robust mode's
    /// search does before its first acquisition (a searching start finds its target as soon
    /// as the search can).
    ever_held: bool,
    /// Whether the last fit judged of the target held was weak (below
    /// [`SEARCH_BELOW_COVERAGE`]): its next frames are likely to be too.
    weak: bool,
    /// The held target's last estimated ranges, against the chase's speed.
    closing: Closing,
    /// Whether the held target's range has just shrunk faster than the chase drives: the
    /// fit has slid off it, and [`Acquisition::recheck`] looks for the target now.
    slid: bool,
}

/// Which target the built-in tracker holds in traffic, and the searchers that find one.
#[derive(Clone, Debug)]
pub(crate) struct Acquisition {
    /// The targets it may hold: the lead's first, then each other kind's.
    models: Vec<TargetModel>,
    /// One robust-mode tracker a model, searching the whole image.
    searchers: Vec<Tracker>,
    /// The whole-image search the searchers share, so that several searching one frame
    /// find its edges once ([`Tracker::swap_search`]).
    shared: ChamferSearch,
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
            shared: ChamferSearch::default(),
            camera,
            config,
            hold: Hold {
                held: held.then_some(0),
                ever_held: held,
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
            && self.hold.ever_held
            && n >= SEARCH_EVERY_FRAME_FOR
            && !(n - SEARCH_EVERY_FRAME_FOR).is_multiple_of(ACQUIRE_EVERY_FRAMES)
    }

    /// A frame rested: counted, nothing stepped.
    pub(crate) fn rest(&mut self) {
        self.hold.idle += 1;
    }

    /// Whether the step `ahead` frames on (1: the next) is likely to read the whole image:
    /// a search, holding nothing and not resting, or, holding a target whose last fit was
    /// weak, a frame [`Acquisition::rechecks`] falls on. A guess, for the loop's rendering:
    /// a frame guessed wrong is drawn in part and drawn again, or drawn whole for nothing.
    pub(crate) fn may_read_whole(&self, ahead: u64) -> bool {
        let h = &self.hold;
        match h.held {
            None => !self.rests_in(ahead),
            Some(_) => h.weak && (h.held_for + ahead).is_multiple_of(ACQUIRE_EVERY_FRAMES),
        }
    }

    /// Whether it searches (holds nothing): the step then reads the whole image.
    pub(crate) fn searching(&self) -> bool {
        self.hold.held.is_none()
    }

    /// Judges the held target's step `out` on `input`'s frame against the chase's lane
    /// and speed: lets go of it when the tracker says it is lost, or when its centre has
    /// been out of the lane for `vehicle::LEFT_LANE_ARRIVALS` frames. Returns whether it let
    /// go. When its estimated range has shrunk faster than the chase drives
    /// ([`super::closing`]: the fit has slid off it), the frame is rechecked
    /// ([`Acquisition::rechecks`]) and, should that find nothing, the target let go of
    /// ([`Acquisition::let_go_of_slid`]).
    pub(crate) fn judge_held(&mut self, out: &TrackOutput, input: &TrackerInput<'_>) -> bool {
        let lane = input.lane;
        let [x, _, z] = out.position_3d;
        let margin_m = f64::from(vehicle::LANE_MARGIN_M);
        let out_now = out.status == Status::Tracking
            && lane.is_some_and(|l| {
                l.offset_m(x, z)
                    .is_some_and(|d| d.abs() > l.half_width_m + margin_m)
            });
        let h = &mut self.hold;
        h.held_for += 1;
        h.weak = covered(out) < SEARCH_BELOW_COVERAGE;
        h.out_of_lane = if out_now { h.out_of_lane + 1 } else { 0 };
        h.slid = match input.speed_mps {
            Some(v) if out.status != Status::Lost => h.closing.too_fast(input.t_s, z, v),
            _ => {
                h.closing.clear();
                false
            }
        };
        let released = out.status == Status::Lost || h.out_of_lane >= vehicle::LEFT_LANE_ARRIVALS;
        if released {
            (h.held, h.out_of_lane, h.idle, h.slid) = (None, 0, 0, false);
        }
        released
    }

    /// After a recheck of a target whose fit slid off it found nothing
    /// ([`Acquisition::judge_held`]): lets go of it. Returns whether it did.
    pub(crate) fn let_go_of_slid(&mut self) -> bool {
        let h = &mut self.hold;
        if !(h.slid && h.held.is_some()) {
            return false;
        }
        (h.held, h.out_of_lane, h.idle, h.slid) = (None, 0, 0, false);
        true
    }

    /// One frame's search, with the next model in turn: its output, what `step` returned
    /// with it, and the tracker that holds what it acquired. `step` steps a tracker on the
    /// frame. When a model acquires, each other model searches about the same place
    /// ([`Acquisition::near`]) on the same frame, and the model whose fit covers more of
    /// its outline is held: one vehicle's back may fit another kind's model in part (a van's
    /// plain back fits a pickup's tailgate and board), and its own model covers it best.
    pub(crate) fn search<E>(
        &mut self,
        lane: Option<&LaneAhead>,
        mut step: impl FnMut(&mut Tracker) -> (TrackOutput, E),
    ) -> Result<(TrackOutput, E, Option<Tracker>), TrackerError> {
        let k = self.hold.next;
        let gate = lane.map(|l| self.gate(k, l));
        self.searchers[k].set_acquire_gate(gate);
        let (out, extra) = self.step_searcher(k, &mut step);
        self.hold.idle += 1;
        if out.status != Status::Tracking {
            self.hold.next = (k + 1) % self.models.len();
            return Ok((out, extra, None));
        }
        let (k, out, extra) = match self.best_near(k, out.estimate, covered(&out), &mut step) {
            Some(better) => {
                self.searchers[k].release();
                better
            }
            None => (k, out, extra),
        };
        // The nearer search steps model `k`'s searcher too (a nearer vehicle of the same
        // kind): its acquisition is kept for the hold should that find nothing nearer.
        let acquired = self.searchers[k].clone();
        let (k, out, extra) = match lane.and_then(|l| self.nearer(k, out.estimate, l, &mut step)) {
            Some(nearer) => nearer,
            None => {
                self.searchers[k] = acquired;
                (k, out, extra)
            }
        };
        let holder = self.take_hold(k, &out)?;
        Ok((out, extra, Some(holder)))
    }

    /// Searches the chase's `lane` with every model, on this frame, for a vehicle nearer
    /// than the one model `k` found at `at` by more than [`NEAR_RANGE_FACTOR`] (so not the
    /// same vehicle at another model's range): the best such fit, as
    /// [`Acquisition::best_of`] chooses, if any. The vehicle in the chase's path is the
    /// nearest in its lane: a car's back low in the image hides little of a board or a tall
    /// back beyond it, which the search may find first.
    fn nearer<E>(
        &mut self,
        k: usize,
        at: Location,
        lane: &LaneAhead,
        step: &mut impl FnMut(&mut Tracker) -> (TrackOutput, E),
    ) -> Option<(usize, TrackOutput, E)> {
        let within_m = self.models[k].nominal_range_m() / at.scale / NEAR_RANGE_FACTOR;
        let gates: Vec<_> = (0..self.models.len())
            .map(|j| {
                let least_scale = self.models[j].nominal_range_m() / within_m;
                let rows: Vec<GateRow> = self
                    .gate_rows(j, lane)
                    .into_iter()
                    .filter(|r| r.scale >= least_scale)
                    .collect();
                (!rows.is_empty()).then(|| Some(AcquireGate::new(rows)))
            })
            .collect();
        let reach = self.size_px(k, at).map(|s| NEAR_REACH * s);
        let apart = |_: usize, o: &TrackOutput| {
            (o.estimate.c_x - at.c_x).abs() > reach[0] || (o.estimate.c_y - at.c_y).abs() > reach[1]
        };
        self.best_of(gates, 0.0, apart, step)
    }

    /// Whether the held target, whose step this frame is `out`, is checked against the
    /// other models ([`Acquisition::recheck`]): when its fit covers less of its outline
    /// than `tracker::robust::SEARCH_BELOW_COVERAGE` (a weak fit, by robust mode's test),
    /// on one frame in [`tracker::robust::ACQUIRE_EVERY_FRAMES`], the rate of robust mode's
    /// whole-image search after a long loss; and at once when its fit has slid off it
    /// ([`Acquisition::judge_held`]).
    pub(crate) fn rechecks(&self, out: &TrackOutput) -> bool {
        let h = &self.hold;
        h.held.is_some()
            && (h.slid
                || (h.held_for.is_multiple_of(ACQUIRE_EVERY_FRAMES)
                    && covered(out) < SEARCH_BELOW_COVERAGE))
    }

    /// Holding a target whose fit `out` is weak, when [`Acquisition::rechecks`]: searches
    /// the chase's lane for every model, as when holding nothing, and returns the best
    /// whose fit covers [`tracker::robust::SEARCH_MARGIN`] more of its outline (its output,
    /// `step`'s return and the tracker to hold it), now held; of the held model, only a fit
    /// that is not the target held ([`Acquisition::same_target`]). A vehicle first found in
    /// part by another kind's model is held by its own once that resolves (the lead's
    /// board, found nearer than a car's back, is one); a model held at a scale it fits by
    /// self-similarity (the board's at twice its own, its inner frame on the board's outer)
    /// gives way to the target at its own scale once the search reaches it; and a target
    /// coasting on nothing gives way to one that is there. The caller tells the controller
    /// that what it followed was let go of, so that it measures the new target first.
    pub(crate) fn recheck<E>(
        &mut self,
        out: &TrackOutput,
        lane: Option<&LaneAhead>,
        mut step: impl FnMut(&mut Tracker) -> (TrackOutput, E),
    ) -> Result<Option<(TrackOutput, E, Tracker)>, TrackerError> {
        let Some(k) = self.hold.held else {
            return Ok(None);
        };
        if !self.rechecks(out) {
            return Ok(None);
        }
        // A fit that slid off its target gives way to any fit of a target in the lane.
        let floor = if self.hold.slid {
            0.0
        } else {
            covered(out) + SEARCH_MARGIN
        };
        let held = out.estimate;
        let gates = (0..self.models.len())
            .map(|j| Some(lane.map(|l| self.gate(j, l))))
            .collect();
        let half_width_px = self.half_width_px(k, held);
        // Beyond the vehicle held (by more than one vehicle's models' disagreement), only
        // once its fit has slid off it: the vehicle in the path is the nearest.
        let held_m = self.models[k].nominal_range_m() / held.scale;
        let slid = self.hold.slid;
        let nominal: Vec<f64> = self
            .models
            .iter()
            .map(TargetModel::nominal_range_m)
            .collect();
        let admit = |j: usize, o: &TrackOutput| {
            let range_m = nominal[j] / o.estimate.scale;
            (slid || range_m <= held_m * NEAR_RANGE_FACTOR)
                && (j != k || !same_target(held, half_width_px, o.estimate))
        };
        let Some((j, out, extra)) = self.best_of(gates, floor, admit, &mut step) else {
            return Ok(None);
        };
        let holder = self.take_hold(j, &out)?;
        Ok(Some((out, extra, holder)))
    }

    /// Half the width of model `k`'s outline at `at`, pixels.
    fn half_width_px(&self, k: usize, at: Location) -> f64 {
        0.5 * self.size_px(k, at)[0]
    }

    /// The width and height of model `k`'s outline at `at`, pixels: its size in metres at
    /// the range the scale gives (eq. 36).
    fn size_px(&self, k: usize, at: Location) -> [f64; 2] {
        let m = &self.models[k];
        let range_m = m.nominal_range_m() / at.scale;
        let [fx, fy] = self.camera.focal_px();
        let [w, h] = m.size_m();
        [w * fx / range_m, h * fy / range_m]
    }

    /// Searches each model but `k` about `at`, where model `k` has a fit, on this frame
    /// ([`Acquisition::best_of`]).
    fn best_near<E>(
        &mut self,
        k: usize,
        at: Location,
        floor: f64,
        step: &mut impl FnMut(&mut Tracker) -> (TrackOutput, E),
    ) -> Option<(usize, TrackOutput, E)> {
        let gates = (0..self.models.len())
            .map(|j| (j != k).then(|| Some(self.near(k, at, j))))
            .collect();
        self.best_of(gates, floor, |_, _| true, step)
    }

    /// Searches with each model `j` whose `gates[j]` is given, within that gate, on this
    /// frame: the model whose fit covers the most of its outline, above `floor`, with its
    /// output and `step`'s return, of the fits `admit` takes. Every other searcher is
    /// released.
    fn best_of<E>(
        &mut self,
        gates: Vec<Option<Option<AcquireGate>>>,
        floor: f64,
        admit: impl Fn(usize, &TrackOutput) -> bool,
        step: &mut impl FnMut(&mut Tracker) -> (TrackOutput, E),
    ) -> Option<(usize, TrackOutput, E)> {
        let mut best: Option<(usize, TrackOutput, E)> = None;
        for (j, gate) in gates.into_iter().enumerate() {
            let Some(gate) = gate else { continue };
            self.searchers[j].set_acquire_gate(gate);
            let (o, e) = self.step_searcher(j, step);
            if o.status != Status::Tracking {
                continue;
            }
            if !admit(j, &o) {
                self.searchers[j].release();
                continue;
            }
            let bar = best.as_ref().map_or(floor, |b| covered(&b.1).max(floor));
            if covered(&o) > bar {
                if let Some((i, ..)) = best {
                    self.searchers[i].release();
                }
                best = Some((j, o, e));
            } else {
                self.searchers[j].release();
            }
        }
        best
    }

    /// Steps searcher `j` with `step`, lent the shared search.
    fn step_searcher<E>(
        &mut self,
        j: usize,
        step: &mut impl FnMut(&mut Tracker) -> (TrackOutput, E),
    ) -> (TrackOutput, E) {
        let searcher = &mut self.searchers[j];
        searcher.swap_search(&mut self.shared);
        let stepped = step(searcher);
        searcher.swap_search(&mut self.shared);
        stepped
    }

    /// Holds model `k`'s fit `out`, just acquired by its searcher: robust mode holds it
    /// with the searcher's state; the paper's mode starts its own tracker there, as from a
    /// teleoperator's placement. The searcher is released to search again later.
    fn take_hold(&mut self, k: usize, out: &TrackOutput) -> Result<Tracker, TrackerError> {
        let searcher = &mut self.searchers[k];
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
        let h = &mut self.hold;
        (h.held, h.out_of_lane, h.next, h.held_for) = (Some(k), 0, 0, 0);
        h.closing.clear();
        h.slid = false;
        h.ever_held = true;
        Ok(holder)
    }

    /// Where model `j`'s target may be centred on the vehicle whose back model `k` found at
    /// `at`: a centre within [`NEAR_REACH`] of the found outline's size from its centre, at
    /// the scales that put model `j` at the found range (eq. 36) within a factor of
    /// [`NEAR_RANGE_FACTOR`].
    fn near(&self, k: usize, at: Location, j: usize) -> AcquireGate {
        let range_m = self.models[k].nominal_range_m() / at.scale;
        let reach = self.size_px(k, at).map(|s| NEAR_REACH * s);
        let scale = self.models[j].nominal_range_m() / range_m;
        let row = |scale| GateRow {
            scale,
            c_x: [at.c_x - reach[0], at.c_x + reach[0]],
            c_y: [at.c_y - reach[1], at.c_y + reach[1]],
        };
        AcquireGate::new(vec![
            row(scale / NEAR_RANGE_FACTOR),
            row(scale * NEAR_RANGE_FACTOR),
        ])
    }

    /// Where model `k`'s target may be centred in the image: at each scale, its range (the
    /// model's nominal range over the scale, eq. 36), there the lane's columns, and the rows
    /// of a point [`CENTRE_HEIGHT_M`] above the lane's centre, with [`GATE_MARGIN_PX`] about
    /// them. Above is taken along the camera's −y: the camera's pitch moves those rows by
    /// well under the margin.
    fn gate(&self, k: usize, lane: &LaneAhead) -> AcquireGate {
        AcquireGate::new(self.gate_rows(k, lane))
    }

    /// The rows of [`Acquisition::gate`], from the least scale to the greatest.
    fn gate_rows(&self, k: usize, lane: &LaneAhead) -> Vec<GateRow> {
        let nominal = self.models[k].nominal_range_m();
        let [lo, hi] = acquire_scales(&self.camera);
        let [lo, hi] = [lo / 1.1, hi * 1.1];
        (0..GATE_ROWS)
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
            .collect()
    }
}

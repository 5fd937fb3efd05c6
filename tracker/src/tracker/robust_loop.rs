//! Robust mode's loop ([`crate::robust`] says what it adds to the paper's): its
//! prediction from two banks of motion models, its searches, and one frame's step.

use super::{Measured, Tracker};
use crate::edges::EdgeDiagnostic;
use crate::gray::GrayView;
use crate::location::Location;
use crate::object_location::Measurement;
use crate::robust::{acquire_scales, search_threshold};
use crate::robust::{
    ACQUIRE_EVERY_FRAMES, CHAMFER_ACCEPT_PX, LOCAL_SEARCH_GROWTH_PX, LOCAL_SEARCH_PX,
    MAX_SCALE_STEP, MODEL_ERROR_DECAY, NESTED_FIT_RATIO, NESTED_FIT_REACH, REACQUIRE_MIN_COVERAGE,
    SCALE_NOISE_PX, SEARCH_BELOW_COVERAGE, SEARCH_MARGIN, SURPRISE_FORGETTING,
};
use crate::step_io::{EgoMotion, Status, TrackEvent, TrackOutput};
use crate::window::Window;

impl Tracker {
    /// Robust mode's prediction: both banks aged, the camera's rotation applied, and each
    /// parameter from the bank whose recent prediction errors are smaller.
    fn predict_robust(&mut self, cycles: u32, ego: Option<EgoMotion>) -> Location {
        if !self.motion[0].has_information() {
            return self.init;
        }
        for m in self.motion.iter_mut().chain(self.banks.fast.iter_mut()) {
            m.age(cycles);
        }
        let mut p = [0.0; 3];
        for (k, out) in p.iter_mut().enumerate() {
            let slow = self.motion[k].predict(0.0);
            let fast = self.banks.fast[k].predict(0.0);
            self.banks.predicted[k] = [slow, fast];
            *out = if self.use_fast(k) { fast } else { slow };
        }
        let mut predicted = Location::new(p[0], p[1], p[2]);
        if let Some(ego) = ego {
            let [dx, dy] = ego.image_shift(&self.camera, predicted);
            for (k, d) in [(0, dx), (1, dy)] {
                self.motion[k].shift(d);
                self.banks.fast[k].shift(d);
                for v in &mut self.banks.predicted[k] {
                    *v += d;
                }
            }
            predicted.c_x += dx;
            predicted.c_y += dy;
        }
        predicted
    }

    /// Whether parameter `k` is predicted by the fast model: its recent prediction errors
    /// are smaller, and the tracker is not coasting (coasting, the slower model extrapolates
    /// more calmly).
    fn use_fast(&self, k: usize) -> bool {
        let [e_slow, e_fast] = self.banks.error[k];
        e_fast < e_slow && self.coast_cycles == 0
    }

    /// Adds a trusted measurement to both banks, after the surprise test, and updates the
    /// running errors that choose between them.
    fn learn(&mut self, meas: &Measurement, predicted: Location, fresh: bool, strong: bool) {
        let z = meas.location.to_array();
        if !fresh {
            for (k, zk) in z.iter().enumerate() {
                for (b, p) in self.banks.predicted[k].iter().enumerate() {
                    let e = zk - p;
                    let err = &mut self.banks.error[k][b];
                    *err = MODEL_ERROR_DECAY * *err + (1.0 - MODEL_ERROR_DECAY) * e * e;
                }
            }
            let jump = (meas.location.c_x - predicted.c_x)
                .abs()
                .max((meas.location.c_y - predicted.c_y).abs());
            let zoom = (meas.location.scale / predicted.scale - 1.0).abs();
            // Only a strong measurement may say the motion changed.
            if strong && (jump > self.config.zeta_px || zoom > 0.1) {
                for m in self.motion.iter_mut().chain(self.banks.fast.iter_mut()) {
                    m.forget(SURPRISE_FORGETTING);
                }
            }
        }
        for (k, w) in meas.confidence.iter().enumerate() {
            self.motion[k].add(z[k], *w);
            self.banks.fast[k].add(z[k], *w);
        }
    }

    /// The region a search covers: the whole image when `around` is `None`; otherwise
    /// room for the target (its size at `around`'s scale, 25 % larger) with its centre up to
    /// `reach_px` from `around`'s.
    fn search_region(
        &self,
        around: Option<Location>,
        reach_px: f64,
        width: usize,
        height: usize,
    ) -> Window {
        let whole = Window {
            x0: 1,
            y0: 1,
            x1: width.saturating_sub(1),
            y1: height.saturating_sub(1),
            size_index: self.config.window_scales.len() - 1,
        };
        let Some(at) = around else { return whole };
        let hw = self.half_extent_px[0] * at.scale * 1.25 + reach_px;
        let hh = self.half_extent_px[1] * at.scale * 1.25 + reach_px;
        let clip = |lo: f64, hi: f64, n: usize| {
            let a = lo.floor().clamp(1.0, (n - 1) as f64) as usize;
            let b = hi.ceil().clamp(1.0, (n - 1) as f64) as usize;
            (a, b.max(a))
        };
        let (x0, x1) = clip(at.c_x - hw, at.c_x + hw, width);
        let (y0, y1) = clip(at.c_y - hh, at.c_y + hh, height);
        Window {
            x0,
            y0,
            x1,
            y1,
            size_index: whole.size_index,
        }
    }

    /// How far from the prediction a search looks, and a measurement may lie, pixels:
    /// [`LOCAL_SEARCH_PX`], and [`LOCAL_SEARCH_GROWTH_PX`] more for every frame coasted.
    fn reach_px(&self) -> f64 {
        LOCAL_SEARCH_PX + LOCAL_SEARCH_GROWTH_PX * self.coast_cycles as f64
    }

    /// Searches `region` at scales `scales` (within the acquisition gate when `gated`) and
    /// measures at the best fit; the measurement when the fit and the measurement both pass
    /// their checks, the measurement's the strong one (REACQUIRE_MIN_COVERAGE, on a peak of
    /// coverage). A whole-image search's fit (`gated`) must also not be a nested one
    /// ([`NESTED_FIT_RATIO`]).
    ///
    /// Not in the paper, whose start was a person's (2.2).
    fn search_and_measure(
        &mut self,
        image: GrayView<'_>,
        region: Window,
        scales: [f64; 2],
        gated: bool,
        diagnostics: Option<&mut Vec<EdgeDiagnostic>>,
    ) -> Option<Measured> {
        self.note_read(region, image.width(), image.height());
        let mut config = self.config.clone();
        let sigma = self.noise.sigma(image, region);
        config.edge_threshold = search_threshold(self.config.edge_threshold, sigma);
        let gate = self.gate.as_ref().filter(|_| gated);
        let hit = self.search.search(
            image,
            region,
            &self.features,
            self.half_extent_px,
            scales,
            &config,
            gate,
        )?;
        if hit.score > CHAMFER_ACCEPT_PX {
            return None;
        }
        // A candidate's measurement judges resolution, and the judgement is sticky: one the
        // search does not keep must leave no trace on the target's.
        let judged_before = self.resolvability.clone();
        let m = self.measure(image, hit.location, true, false, diagnostics);
        let nested = || {
            let s = hit.location.scale;
            let smaller = [s / NESTED_FIT_REACH, s / NESTED_FIT_RATIO];
            self.search
                .best_about(hit.location, self.half_extent_px, smaller)
                .is_some_and(|h| h.score < hit.score)
        };
        let kept = m.passes(REACQUIRE_MIN_COVERAGE, 0.0) && !(gated && nested());
        if !kept {
            self.resolvability = judged_before;
        }
        kept.then_some(m)
    }

    /// Robust mode's loop.
    pub(super) fn run_robust(
        &mut self,
        image: GrayView<'_>,
        t_s: f64,
        frame: u64,
        cycles: u32,
        ego: Option<EgoMotion>,
        mut diagnostics: Option<&mut Vec<EdgeDiagnostic>>,
    ) -> TrackOutput {
        let (width, height) = (image.width(), image.height());
        if !self.locked {
            // Searching: around the last location for a short loss, else everywhere.
            let lost_long = self.coast_cycles as f64 / self.config.rate_hz
                >= 2.0 * self.config.lost_after_s.max(1.0 / self.config.rate_hz);
            // The acquisition gate, when set, holds for the whole-image search only.
            let (region, scales, gated) = if self.ever_locked && !lost_long {
                let s = self.last_good.scale;
                (
                    self.search_region(Some(self.last_good), self.reach_px(), width, height),
                    [s / 1.3, s * 1.3],
                    false,
                )
            } else {
                (
                    self.search_region(None, 0.0, width, height),
                    acquire_scales(&self.camera),
                    true,
                )
            };
            // A whole-image search costs tens of milliseconds: after a long loss, one frame in
            // ACQUIRE_EVERY_FRAMES.
            let skip = self.ever_locked && lost_long && !frame.is_multiple_of(ACQUIRE_EVERY_FRAMES);
            let found = if skip {
                None
            } else {
                self.search_and_measure(image, region, scales, gated, diagnostics.as_deref_mut())
            };
            if let Some(m) = found {
                let meas = m.measurement.expect("a trusted measurement exists");
                self.last_good = meas.location;
                let event = if self.ever_locked {
                    TrackEvent::Reacquired
                } else {
                    TrackEvent::Acquired
                };
                self.restart_motion(meas.location);
                self.learn(&meas, meas.location, true, true);
                self.locked = true;
                self.ever_locked = true;
                let status = self.judge(true, cycles);
                let next = meas.location;
                return self.finish(
                    frame,
                    t_s,
                    status,
                    meas.location,
                    meas.location,
                    next,
                    m,
                    true,
                    Some(event),
                );
            }
            let status = if self.ever_locked {
                self.judge(false, cycles)
            } else {
                Status::Lost
            };
            let held = self.last_estimate;
            let empty = Measured::none(region, self.config.edge_threshold);
            return self.finish(frame, t_s, status, held, held, held, empty, !skip, None);
        }

        let predicted = self.predict_robust(cycles, ego);
        let fresh = !self.motion[0].has_information();
        let viewable = predicted.is_valid()
            && !Window::around(predicted, self.half_extent_px, &self.config, width, height)
                .is_empty();
        if !viewable {
            // The prediction left the image or stopped being a location: search from the
            // last trusted location.
            self.locked = false;
            self.coast_cycles = self.coast_cycles.max(1);
            return self.run_robust(image, t_s, frame, 0, None, diagnostics);
        }
        let mut m = self.measure(image, predicted, true, true, diagnostics.as_deref_mut());
        let mut searched = false;
        let mut from_search = false;
        let mut event = None;
        let reach = self.reach_px();
        // (Not for features found merged: no search resolves them. One that errs by the
        // prediction's error is measured again from the search's fit, free of it.)
        let weak = m.coverage() < SEARCH_BELOW_COVERAGE
            || !m.trusted_but_for_resolution(&self.coverage_reference);
        let mispredicted =
            !m.trusted(&self.coverage_reference) && !self.resolvability.is_unresolved();
        if weak || mispredicted {
            // A failed or weak check: search near the prediction, and keep what the search
            // finds if its outline is clearly better covered.
            searched = true;
            let region = self.search_region(Some(predicted), reach, width, height);
            let s = predicted.scale;
            let step = 1.0 + MAX_SCALE_STEP;
            // Only a strong fit will do (REACQUIRE_MIN_COVERAGE, on a peak of coverage).
            if let Some(found) =
                self.search_and_measure(image, region, [s / step, s * step], false, diagnostics)
            {
                if found.coverage() > m.coverage() + SEARCH_MARGIN {
                    if !m.trusted(&self.coverage_reference) && self.coast_cycles > 0 {
                        event = Some(TrackEvent::Reacquired);
                    }
                    m = found;
                    from_search = true;
                }
            }
        }
        // The innovation gate: a measurement beyond the search's reach, or whose scale moved
        // by more than MAX_SCALE_STEP a frame, is not the target moving.
        if let Some(meas) = &m.measurement {
            let l = meas.location;
            let frames = 1.0 + self.coast_cycles.min(1) as f64;
            let jump = (l.c_x - predicted.c_x)
                .abs()
                .max((l.c_y - predicted.c_y).abs());
            let zoom = (l.scale / predicted.scale).ln().abs();
            let noise = SCALE_NOISE_PX / (self.half_extent_px[0] * predicted.scale).max(1.0);
            if !fresh && (jump > reach || zoom > frames * (1.0 + MAX_SCALE_STEP).ln() + noise) {
                m.gain = f64::INFINITY;
                event = None;
            }
        }
        let trusted = m.trusted(&self.coverage_reference);
        // A measurement on the target's edges whose features are not resolved is not
        // trusted, but it is still the best word on where the target is: robust mode keeps
        // measuring, as the paper's mode does, rather than freezing on the prediction.
        let measuring = trusted || m.trusted_but_for_resolution(&self.coverage_reference);
        if !from_search {
            self.learn_prediction_error(&m, predicted);
        }
        if measuring {
            let meas = m.measurement.expect("a measurement on the target exists");
            let strong = trusted && m.passes(REACQUIRE_MIN_COVERAGE, 0.0);
            self.learn(&meas, predicted, fresh, strong);
            if strong {
                self.last_good = meas.location;
            }
        }
        let status = self.judge(trusted, cycles);
        if status == Status::Lost && !measuring {
            self.locked = false;
        }
        let next = if measuring {
            let p = [0, 1, 2].map(|k| {
                if self.use_fast(k) {
                    self.banks.fast[k].predict(1.0)
                } else {
                    self.motion[k].predict(1.0)
                }
            });
            Location::new(p[0], p[1], p[2])
        } else {
            predicted
        };
        let estimate = match (&m.measurement, measuring) {
            (Some(meas), true) => meas.location,
            _ if status == Status::Lost => self.last_estimate,
            _ => predicted,
        };
        self.finish(
            frame, t_s, status, predicted, estimate, next, m, searched, event,
        )
    }
}

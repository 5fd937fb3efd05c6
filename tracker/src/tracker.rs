//! The tracker: the loop of paper Figure 1, stages 1–7 on each image, plus stage 8.
//!
//! Both modes check every measurement against the image ([`EdgeMaps::coverage`]): a
//! measurement whose located outline is not covered by edges, or covered far less than the
//! track's own outline was ([`CoverageReference`]), is not trusted, and the status leaves
//! `tracking`, so a loss is never silent. In the paper's mode the check counts edges at the
//! paper's threshold raised with the noise ([`noise_raised_threshold`]), so that noise edges
//! cannot make a fit that left the target look covered; the paper's measurement itself takes
//! the paper's edges. The paper's mode otherwise runs the paper's stages as written; robust
//! mode adds what [`crate::robust`] describes.

use crate::association::{associate, Association};
use crate::camera::Camera;
use crate::config::{TrackerConfig, TrackerMode};
use crate::edges::{EdgeDiagnostic, EdgeExtractor, Edges};
use crate::feature_location::{locate_features, FeatureLocation};
use crate::gate::AcquireGate;
use crate::gray::GrayView;
use crate::householder::Row;
use crate::location::Location;
use crate::model::{Feature, Orientation, TargetModel};
use crate::motion::MotionModel;
use crate::object_location::{locate_object, Measurement};
use crate::pixel_rect::PixelRect;
use crate::prediction::{predict_features, predict_location, PredictedFeature};
use crate::resolvability::Resolvability;
use crate::robust::{
    adaptive_threshold, alias_spacing, coverage_gain, coverage_gain_window, noise_raised_threshold,
    ChamferSearch, CoverageReference, EdgeMaps, NoiseEstimator, SpreadMaps, COVERAGE_TOLERANCE_PX,
    FAST_LAMBDA, MAX_COVERAGE_GAIN, MIN_COVERAGE, NOISE_THRESHOLD_FACTOR, PEAK_PROBE_PX,
    SEARCH_BELOW_COVERAGE,
};
use crate::window::Window;

mod robust_loop;

pub use crate::step_io::{EgoMotion, Status, TrackEvent, TrackOutput, TrackerError};

/// The motion models of robust mode: the paper's λ and a fast one, per parameter, with the
/// running mean squared prediction error of each.
#[derive(Clone, Copy, Debug)]
struct Banks {
    fast: [MotionModel; 3],
    /// [parameter][slow, fast].
    error: [[f64; 2]; 3],
    /// The predictions of this frame, [parameter][slow, fast].
    predicted: [[f64; 2]; 3],
}

/// The paper's tracker: a target model, a camera, settings, and the state carried from
/// frame to frame (the three motion models). Initialised with a location (c_x, c_y,
/// scale), as the paper's teleoperator does (2.2); robust mode can also find it itself.
#[derive(Clone, Debug)]
pub struct Tracker {
    config: TrackerConfig,
    model: TargetModel,
    camera: Camera,
    features: Vec<Feature>,
    half_extent_px: [f64; 2],
    /// The smallest spacing of parallel features at scale 1, `[x, y]`, pixels.
    alias_px: [f64; 2],
    target_width_px: f64,
    /// TargetSize of eq. 36: the model's width, metres.
    target_width_m: f64,
    /// The paper's motion models (robust mode: the slow bank).
    motion: [MotionModel; 3],
    /// Robust mode's fast bank and model choice.
    banks: Banks,
    init: Location,
    frame: u64,
    last_t_s: Option<f64>,
    coast_cycles: u64,
    /// Robust mode: whether the tracker holds the target (else it searches).
    locked: bool,
    /// Robust mode: whether it has ever held it.
    ever_locked: bool,
    last_estimate: Location,
    /// The paper's mode: the last location measured, whatever the status, where its window
    /// goes when the prediction is not a location.
    last_measured: Location,
    /// The last location a trusted measurement gave.
    last_trusted: Location,
    /// The coverage of the trusted measurements, which a measurement must stay near.
    coverage_reference: CoverageReference,
    /// Whether the model's features are resolved, and the prediction's recent error.
    resolvability: Resolvability,
    /// Robust mode: the last location measured with a strong check, where a search after a
    /// loss starts.
    last_good: Location,
    /// Diagnostics list only the fates association gives (see
    /// [`Tracker::set_association_fates_only`]).
    association_fates_only: bool,
    /// The pixels the current (or last) step has read: see [`Tracker::last_read`].
    read: PixelRect,
    // Scratch, kept between frames so that a step allocates little.
    extractor: EdgeExtractor,
    edges: Edges,
    predicted: Vec<PredictedFeature>,
    associations: Vec<Association>,
    rows: Vec<Row>,
    maps: EdgeMaps,
    spread: SpreadMaps,
    check: Vec<PredictedFeature>,
    check_edges: Edges,
    noise: NoiseEstimator,
    search: ChamferSearch,
    /// Robust mode: where a whole-image search may lock on (none: anywhere).
    gate: Option<AcquireGate>,
}

/// What stages 1–4 made of one window.
struct Measured {
    window: Window,
    measurement: Option<Measurement>,
    located: Vec<FeatureLocation>,
    coverage: [f64; 2],
    gain: f64,
    threshold: f64,
    /// Whether the model's parallel features are resolved at the measured scale (see
    /// [`Resolvability::judge`]); true without a measurement.
    resolved: bool,
}

impl Measured {
    /// Nothing measured, in `window`.
    fn none(window: Window, threshold: f64) -> Measured {
        Measured {
            window,
            measurement: None,
            located: Vec::new(),
            coverage: [0.0; 2],
            gain: 0.0,
            threshold,
            resolved: true,
        }
    }

    /// The smaller of the two orientations' coverage (0 without a measurement).
    fn coverage(&self) -> f64 {
        if self.measurement.is_some() {
            self.coverage[0].min(self.coverage[1])
        } else {
            0.0
        }
    }

    /// The check of both modes: enough of the outline on edges ([`MIN_COVERAGE`]), on a
    /// peak of coverage ([`MAX_COVERAGE_GAIN`]), the target resolved
    /// ([`Resolvability::judge`]), and not far below the track's own `reference`
    /// coverage ([`CoverageReference`]).
    fn trusted(&self, reference: &CoverageReference) -> bool {
        self.resolved && self.trusted_but_for_resolution(reference)
    }

    /// Every check of [`Measured::trusted`] but resolution: the outline lies on the
    /// target's edges, whether or not its features are resolved.
    fn trusted_but_for_resolution(&self, reference: &CoverageReference) -> bool {
        self.covered(MIN_COVERAGE, MAX_COVERAGE_GAIN) && reference.admits(self.coverage())
    }

    /// At least `min_coverage` covered, no move covering more than `max_gain` more (a
    /// gain not computed (−∞), for a well-covered fit, passes), and the target resolved
    /// ([`Resolvability::judge`]).
    fn passes(&self, min_coverage: f64, max_gain: f64) -> bool {
        self.covered(min_coverage, max_gain) && self.resolved
    }

    /// [`Measured::passes`] but for resolution.
    fn covered(&self, min_coverage: f64, max_gain: f64) -> bool {
        self.coverage() >= min_coverage && self.gain <= max_gain
    }
}

impl Tracker {
    /// A tracker for `model` seen through `camera`, starting at `init`.
    pub fn new(
        model: TargetModel,
        camera: Camera,
        config: TrackerConfig,
        init: Location,
    ) -> Result<Self, TrackerError> {
        let mut tracker = Self::build(model, camera, config, init)?;
        tracker.reinitialize(init)?;
        Ok(tracker)
    }

    /// A robust-mode tracker with no start: its first frames search the whole image over
    /// scale for the target. The paper's mode refuses ([`TrackerError::NeedsInit`]).
    pub fn new_searching(
        model: TargetModel,
        camera: Camera,
        config: TrackerConfig,
    ) -> Result<Self, TrackerError> {
        if config.mode != TrackerMode::Robust {
            return Err(TrackerError::NeedsInit);
        }
        let somewhere = Location::new(0.0, 0.0, 1.0);
        let mut tracker = Self::build(model, camera, config, somewhere)?;
        tracker.reinitialize(somewhere)?;
        tracker.release();
        Ok(tracker)
    }

    fn build(
        model: TargetModel,
        camera: Camera,
        config: TrackerConfig,
        init: Location,
    ) -> Result<Self, TrackerError> {
        config.validate()?;
        let features = model.features_px(&camera);
        let mut half = [0.0_f64; 2];
        for f in &features {
            let (along, across) = match f.orientation {
                Orientation::Horizontal => (0, 1),
                Orientation::Vertical => (1, 0),
            };
            half[along] = half[along]
                .max(f.extent_px[0].abs())
                .max(f.extent_px[1].abs());
            half[across] = half[across].max(f.offset_px.abs());
        }
        let target_width_m = model.size_m()[0];
        let target_width_px = target_width_m * camera.focal_px()[0] / model.nominal_range_m();
        let lambda = config.lambda;
        let alias_px = alias_spacing(&features);
        let resolvability = Resolvability::new(&features);
        Ok(Tracker {
            association_fates_only: false,
            read: PixelRect::whole(0, 0),
            config,
            model,
            camera,
            features,
            half_extent_px: half,
            alias_px,
            target_width_px,
            target_width_m,
            motion: [MotionModel::new(lambda); 3],
            banks: Banks {
                fast: [MotionModel::new(FAST_LAMBDA.min(lambda)); 3],
                error: [[0.0; 2]; 3],
                predicted: [[0.0; 2]; 3],
            },
            init,
            frame: 0,
            last_t_s: None,
            coast_cycles: 0,
            locked: true,
            ever_locked: true,
            last_estimate: init,
            last_measured: init,
            last_trusted: init,
            coverage_reference: CoverageReference::default(),
            resolvability,
            last_good: init,
            extractor: EdgeExtractor::default(),
            edges: Edges::default(),
            predicted: Vec::new(),
            associations: Vec::new(),
            rows: Vec::new(),
            maps: EdgeMaps::default(),
            spread: SpreadMaps::default(),
            check: Vec::new(),
            check_edges: Edges::default(),
            noise: NoiseEstimator::default(),
            search: ChamferSearch::default(),
            gate: None,
        })
    }

    /// Starts again from `init`, with zero motion information (2.2: the target is taken
    /// to be still, at the location the teleoperator set).
    pub fn reinitialize(&mut self, init: Location) -> Result<(), TrackerError> {
        if !init.is_valid() {
            return Err(TrackerError::BadInit(init));
        }
        self.init = init;
        self.frame = 0;
        self.last_t_s = None;
        self.coast_cycles = 0;
        self.locked = true;
        self.ever_locked = true;
        self.last_estimate = init;
        self.last_measured = init;
        self.last_trusted = init;
        self.coverage_reference.clear();
        self.resolvability.clear();
        self.last_good = init;
        self.restart_motion(init);
        Ok(())
    }

    /// Zero motion information, the target taken to be still at `at` (2.2).
    fn restart_motion(&mut self, at: Location) {
        self.init = at;
        self.motion = [MotionModel::new(self.config.lambda); 3];
        self.banks.fast = [MotionModel::new(FAST_LAMBDA.min(self.config.lambda)); 3];
        self.banks.error = [[0.0; 2]; 3];
    }

    /// Robust mode: lets go of the target (its motion and last estimate kept), so that the
    /// next frames search the whole image (within the acquisition gate) for a target, as
    /// after [`Tracker::new_searching`]. The paper's mode, which always holds its target
    /// (2.2), is not changed.
    pub fn release(&mut self) {
        if self.config.mode == TrackerMode::Robust {
            self.locked = false;
            self.ever_locked = false;
            self.coast_cycles = 0;
            self.coverage_reference.clear();
            self.resolvability.clear();
        }
    }

    /// Exchanges the tracker's whole-image search (its scratch, and the edges it last
    /// found) with `search`: trackers of several models that search one frame one after
    /// another, sharing one, find its edges once. Changes no result.
    pub fn swap_search(&mut self, search: &mut ChamferSearch) {
        std::mem::swap(&mut self.search, search);
    }

    /// Robust mode: where a whole-image search may lock on (`None`: anywhere, the
    /// default). Not in the paper; see [`crate::gate`]. Searches near a held or lately
    /// lost target are not gated.
    pub fn set_acquire_gate(&mut self, gate: Option<AcquireGate>) {
        self.gate = gate;
    }

    /// Robust mode: whether the tracker holds a target (else it searches). The paper's
    /// mode always does.
    pub fn is_locked(&self) -> bool {
        self.locked
    }

    /// The settings.
    pub fn config(&self) -> &TrackerConfig {
        &self.config
    }

    /// The target model.
    pub fn model(&self) -> &TargetModel {
        &self.model
    }

    /// The camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// The model's features at scale 1, pixels.
    pub fn features(&self) -> &[Feature] {
        &self.features
    }

    /// The target's width in the image at scale 1, pixels (TargetSizeImage of eq. 36 is
    /// this times the scale).
    pub fn target_width_px(&self) -> f64 {
        self.target_width_px
    }

    /// The three motion models, [c_x, c_y, scale] (robust mode: the slow ones, at λ).
    pub fn motion_models(&self) -> &[MotionModel; 3] {
        &self.motion
    }

    /// Stage 8 (eq. 36) for a location: its position in the camera frame, metres.
    pub fn position_3d(&self, location: Location) -> [f64; 3] {
        self.camera.position_3d(
            location.c_x,
            location.c_y,
            location.scale * self.target_width_px,
            self.target_width_m,
        )
    }

    /// Processes one frame taken at `t_s` seconds (stages 1–8). Frames are expected in time
    /// order; the gap since the previous frame, in whole camera cycles (at least one), ages
    /// the motion models, so a dropped frame is allowed for.
    pub fn step(&mut self, image: GrayView<'_>, t_s: f64) -> TrackOutput {
        self.run(image, t_s, None, None)
    }

    /// As [`Tracker::step`], with the camera's own rotation since the previous frame (used
    /// by robust mode to predict; ignored by the paper's).
    pub fn step_aided(&mut self, image: GrayView<'_>, t_s: f64, ego: EgoMotion) -> TrackOutput {
        self.run(image, t_s, Some(ego), None)
    }

    /// With `true`, the diagnostics of [`Tracker::step_with_diagnostics`] list only the
    /// classified edge points with their fates from association (associated with a feature,
    /// or too far from any), not the weak or wrongly oriented pixels. Edge extraction then
    /// takes its fast path, so a run that draws or records the overlay pays little for it;
    /// the estimates are the same either way.
    pub fn set_association_fates_only(&mut self, only: bool) {
        self.association_fates_only = only;
    }

    /// The bounding box of every pixel the last step read from its image (an empty
    /// rectangle before the first step). The step's output depends on no pixel outside it:
    /// the same state stepped on any image that agrees inside it gives the same output, so a
    /// renderer may draw only that much of a frame (and draw the rest, and step again from a
    /// copy of the state, when a step read more than was drawn).
    pub fn last_read(&self) -> PixelRect {
        self.read
    }

    /// Records that this step reads `window` of an image `width × height` with the pixel
    /// operators.
    fn note_read(&mut self, window: Window, width: usize, height: usize) {
        if !window.is_empty() {
            self.read = self.read.union(&PixelRect::read_by(window, width, height));
        }
    }

    /// As [`Tracker::step`], and also returns every edge point in the window with its fate.
    pub fn step_with_diagnostics(
        &mut self,
        image: GrayView<'_>,
        t_s: f64,
    ) -> (TrackOutput, Vec<EdgeDiagnostic>) {
        let mut diagnostics = Vec::new();
        let out = self.run(image, t_s, None, Some(&mut diagnostics));
        (out, diagnostics)
    }

    /// As [`Tracker::step_aided`], and also returns every edge point in the window with its
    /// fate.
    pub fn step_aided_with_diagnostics(
        &mut self,
        image: GrayView<'_>,
        t_s: f64,
        ego: EgoMotion,
    ) -> (TrackOutput, Vec<EdgeDiagnostic>) {
        let mut diagnostics = Vec::new();
        let out = self.run(image, t_s, Some(ego), Some(&mut diagnostics));
        (out, diagnostics)
    }

    fn run(
        &mut self,
        image: GrayView<'_>,
        t_s: f64,
        ego: Option<EgoMotion>,
        diagnostics: Option<&mut Vec<EdgeDiagnostic>>,
    ) -> TrackOutput {
        let cycles = match self.last_t_s {
            None => 0,
            Some(last) => (((t_s - last) * self.config.rate_hz).round().max(1.0)) as u32,
        };
        self.last_t_s = Some(t_s);
        self.read = PixelRect::whole(0, 0);
        let frame = self.frame;
        self.frame += 1;
        match self.config.mode {
            TrackerMode::Paper => self.run_paper(image, t_s, frame, cycles, diagnostics),
            TrackerMode::Robust => self.run_robust(image, t_s, frame, cycles, ego, diagnostics),
        }
    }

    /// Stages 7 and 1–4 at `at`: the window, the edges, association, feature and object
    /// location, and the coverage check of the result. `robust` selects robust mode's
    /// adaptive threshold and M-estimators. `predicted`: `at` is the motion models'
    /// prediction, whose recent error then bears on resolution (a search's fit is not).
    fn measure(
        &mut self,
        image: GrayView<'_>,
        at: Location,
        robust: bool,
        predicted: bool,
        diagnostics: Option<&mut Vec<EdgeDiagnostic>>,
    ) -> Measured {
        let window = Window::around(
            at,
            self.half_extent_px,
            &self.config,
            image.width(),
            image.height(),
        );
        let (w, h) = (image.width(), image.height());
        self.note_read(window, w, h);
        let mut config = self.config.clone();
        if robust {
            let sigma = self.noise.sigma(image, window);
            config.edge_threshold = adaptive_threshold(self.config.edge_threshold, sigma);
        }
        let mut diagnostics = diagnostics;
        if let Some(d) = diagnostics.as_deref_mut() {
            d.clear();
        }
        // Stage 7 (for this image), then stages 1–4.
        predict_features(&self.features, at, &mut self.predicted);
        let extraction_diagnostics = if self.association_fates_only {
            None
        } else {
            diagnostics.as_deref_mut()
        };
        self.extractor.extract(
            image,
            window,
            &config,
            &mut self.edges,
            extraction_diagnostics,
        );
        associate(
            &self.edges,
            &self.predicted,
            config.zeta_px,
            &mut self.associations,
            diagnostics,
        );
        let mut located = Vec::with_capacity(self.predicted.len());
        locate_features(&self.predicted, &self.associations, &config, &mut located);
        let measurement = locate_object(&self.features, &located, &config, &mut self.rows);
        // The check, in both modes: does the located outline lie on edges of its class?
        // Its edges are the measurement's, unless noise raises its threshold: robust mode's
        // threshold is noise-adaptive already, and the paper's is raised only where σ
        // exceeds threshold / NOISE_THRESHOLD_FACTOR (σ from every 4th pixel each way: about
        // 5 % of the step, where every 2nd pixel took 18 %).
        let raised = if !robust && measurement.is_some() {
            let floor = config.edge_threshold / NOISE_THRESHOLD_FACTOR;
            self.noise
                .sigma_above(image, window, floor, 4)
                .map(|sigma| TrackerConfig {
                    edge_threshold: noise_raised_threshold(config.edge_threshold, sigma),
                    ..config.clone()
                })
        } else {
            None
        };
        let check_config = raised.as_ref().unwrap_or(&config);
        let (coverage, gain) = match &measurement {
            Some(m) => {
                predict_features(&self.features, m.location, &mut self.check);
                if raised.is_some() {
                    self.extractor.extract(
                        image,
                        window,
                        check_config,
                        &mut self.check_edges,
                        None,
                    );
                    self.maps.build(&self.check_edges, window);
                } else {
                    self.maps.build(&self.edges, window);
                }
                let coverage = self.maps.coverage(&self.check);
                let gain = if coverage[0].min(coverage[1]) >= SEARCH_BELOW_COVERAGE {
                    // A fit this well covered is on the target: no other fit of it covers
                    // so much (a fit a feature spacing off covers 0.55–0.7).
                    f64::NEG_INFINITY
                } else {
                    // The edges of every move the gain test makes: the window grown by the
                    // largest move.
                    let alias = self.alias_px.map(|a| a * m.location.scale);
                    let reach = [0, 1].map(|k| {
                        let a = if alias[k].is_finite() { alias[k] } else { 0.0 };
                        (a.max(PEAK_PROBE_PX) + COVERAGE_TOLERANCE_PX as f64 + 1.0).ceil() as usize
                    });
                    let grown = Window {
                        x0: window.x0.saturating_sub(reach[0]).max(1),
                        y0: window.y0.saturating_sub(reach[1]).max(1),
                        x1: (window.x1 + reach[0]).min(w.saturating_sub(1)),
                        y1: (window.y1 + reach[1]).min(h.saturating_sub(1)),
                        size_index: window.size_index,
                    };
                    // Only the pixels the moves look at, within the grown window.
                    let looked = coverage_gain_window(&self.check, alias, grown);
                    self.note_read(looked, w, h);
                    self.extractor.extract(
                        image,
                        looked,
                        check_config,
                        &mut self.check_edges,
                        None,
                    );
                    self.maps.build(&self.check_edges, looked);
                    coverage_gain(&self.maps, &self.check, alias, &mut self.spread)
                };
                (coverage, gain)
            }
            None => ([0.0; 2], 0.0),
        };
        let mut m = Measured {
            window,
            measurement,
            located,
            coverage,
            gain,
            threshold: config.edge_threshold,
            resolved: true,
        };
        self.judge_resolution(&mut m, predicted);
        m
    }

    /// The spacing below which two parallel features that compete for edge points (their
    /// extents overlap, eq. 8 and 10) are confused now, `[x, y]`, pixels: see
    /// [`Resolvability::limit_px`].
    pub fn resolution_px(&self) -> [f64; 2] {
        self.resolvability.limit_px()
    }

    /// The judgement of whether the model's features are resolved, with the prediction's
    /// recent error.
    pub fn resolvability(&self) -> &Resolvability {
        &self.resolvability
    }

    /// Whether `m`'s target is resolved, in both modes ([`Resolvability::judge`]), judged
    /// by a measurement that passes the coverage checks; `predicted`: whether it was made
    /// from the prediction.
    fn judge_resolution(&mut self, m: &mut Measured, predicted: bool) {
        let Some(meas) = &m.measurement else {
            return;
        };
        let checks = m.covered(MIN_COVERAGE, MAX_COVERAGE_GAIN);
        m.resolved = self
            .resolvability
            .judge(meas.location.scale, checks, predicted);
    }

    /// Takes this frame's prediction error into the resolvability's, from a measurement
    /// that passed the coverage checks, against `from`, where association worked.
    fn learn_prediction_error(&mut self, m: &Measured, from: Location) {
        if let Some(meas) = &m.measurement {
            if m.covered(MIN_COVERAGE, MAX_COVERAGE_GAIN) {
                self.resolvability.learn(from, meas.location);
            }
        }
    }

    /// The paper's loop. Its estimates are the paper's: every measurement updates the motion
    /// models, trusted or not. The paper has no loss state (a teleoperator watched), so this
    /// loop never stops measuring: the status is a report only, judged by the check both
    /// modes share ([`Measured::trusted`]). A frame without a trusted measurement is
    /// reported as `coasting`, so a loss is never silent; `lost_after_s` without one is
    /// reported as `lost` (a fit that stays beside the target is lost as surely as no fit);
    /// and as soon as the features return within the window, their measurement is trusted
    /// and the status is `tracking` again.
    ///
    /// One guard the paper does not need: if the motion models extrapolate to an invalid
    /// location (a scale at or below zero, after a long time without a measurement), the
    /// window is placed on the last location measured instead, where the target was last
    /// seen, so that measuring can go on. It is the last one measured whatever the status:
    /// the status never steers the estimates. (It was the last estimate before a reported
    /// loss, so a loss declared sooner or later placed the window elsewhere.)
    fn run_paper(
        &mut self,
        image: GrayView<'_>,
        t_s: f64,
        frame: u64,
        cycles: u32,
        diagnostics: Option<&mut Vec<EdgeDiagnostic>>,
    ) -> TrackOutput {
        // Stage 6 of the previous cycle: where the target should be in this image.
        let predicted = if self.motion[0].has_information() {
            predict_location(&self.motion, f64::from(cycles))
        } else {
            self.init
        };
        for m in &mut self.motion {
            m.age(cycles);
        }
        let look_at = if predicted.is_valid() {
            predicted
        } else {
            self.last_measured
        };
        let m = self.measure(image, look_at, false, predicted.is_valid(), diagnostics);
        // Stage 5: each parameter's model takes the measurement with its eq. 17 confidence.
        if let Some(meas) = &m.measurement {
            let l = meas.location.to_array();
            for ((model, z), w) in self.motion.iter_mut().zip(l).zip(meas.confidence) {
                model.add(z, w);
            }
        }
        let trusted = m.trusted(&self.coverage_reference);
        self.learn_prediction_error(&m, look_at);
        let status = self.judge(trusted, cycles);
        // Stage 6: the prediction for the next frame (eq. 34).
        let next = if self.motion[0].has_information() {
            predict_location(&self.motion, 1.0)
        } else {
            predicted
        };
        let estimate = match &m.measurement {
            Some(meas) => meas.location,
            None => look_at,
        };
        if let Some(meas) = &m.measurement {
            self.last_measured = meas.location;
        }
        self.finish(
            frame, t_s, status, predicted, estimate, next, m, false, None,
        )
    }

    /// Tracking, coasting or lost, from whether this frame's measurement is trusted.
    fn judge(&mut self, trusted: bool, cycles: u32) -> Status {
        if trusted {
            self.coast_cycles = 0;
            Status::Tracking
        } else {
            self.coast_cycles += u64::from(cycles.max(1));
            let coasted_s = self.coast_cycles as f64 / self.config.rate_hz;
            if coasted_s + 1e-9 >= self.config.lost_after_s {
                Status::Lost
            } else {
                Status::Coasting
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn finish(
        &mut self,
        frame: u64,
        t_s: f64,
        status: Status,
        predicted: Location,
        estimate: Location,
        next: Location,
        m: Measured,
        searched: bool,
        event: Option<TrackEvent>,
    ) -> TrackOutput {
        let coverage_reference = self.coverage_reference.value();
        let event = if self.resolvability.take_event() {
            Some(TrackEvent::Unresolved)
        } else {
            event
        };
        if status == Status::Tracking {
            self.last_trusted = estimate;
            self.coverage_reference.learn(m.coverage());
        }
        if status != Status::Lost {
            self.last_estimate = estimate;
        }
        TrackOutput {
            frame,
            t_s,
            status,
            measurement: m.measurement,
            predicted,
            estimate,
            next,
            position_3d: self.position_3d(estimate),
            window: m.window,
            features: m.located,
            coverage: m.coverage,
            coverage_reference,
            coverage_gain: m.gain,
            edge_threshold: m.threshold,
            searched,
            event,
        }
    }
}

//! The tracker: the loop of paper Figure 1, stages 1–7 on each image, plus stage 8.

use crate::association::{associate, Association};
use crate::camera::Camera;
use crate::config::{ConfigError, TrackerConfig};
use crate::edges::{EdgeDiagnostic, EdgeExtractor, Edges};
use crate::feature_location::{locate_features, FeatureLocation};
use crate::gray::GrayView;
use crate::householder::Row;
use crate::location::Location;
use crate::model::{Feature, Orientation, TargetModel};
use crate::motion::MotionModel;
use crate::object_location::{locate_object, Measurement};
use crate::prediction::{predict_features, predict_location, PredictedFeature};
use crate::window::Window;
use thiserror::Error;

/// What the tracker says of its own state after a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Status {
    /// This frame gave a usable stage-4 measurement.
    Tracking,
    /// No usable measurement this frame; the prediction carries on.
    Coasting,
    /// No usable measurement for `lost_after_s` (or the prediction became meaningless): the
    /// estimate is not to be trusted. Sticky until [`Tracker::reinitialize`].
    Lost,
}

impl Status {
    /// Lower-case name, as written in tables.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Tracking => "tracking",
            Status::Coasting => "coasting",
            Status::Lost => "lost",
        }
    }
}

/// Everything the tracker made of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackOutput {
    /// Frame index, from 0 since the last (re)initialisation.
    pub frame: u64,
    /// The frame's time, seconds, as given to [`Tracker::step`].
    pub t_s: f64,
    /// Tracking, coasting or lost.
    pub status: Status,
    /// The stage-4 measurement with its confidences, when there was one.
    pub measurement: Option<Measurement>,
    /// The location predicted for this frame (stage 6 of the previous cycle), against which
    /// the edges were associated.
    pub predicted: Location,
    /// The best estimate of the target in this frame: the measurement when there was one,
    /// otherwise the prediction.
    pub estimate: Location,
    /// Stage 6: the location predicted for the next frame (eq. 34).
    pub next: Location,
    /// Stage 8 (eq. 36): the target's position in the camera frame (metres: x right, y down,
    /// z forward), from `estimate`.
    pub position_3d: [f64; 3],
    /// The window of interest used for stage 1.
    pub window: Window,
    /// Stages 3 and 7 for every feature, in the model's segment order.
    pub features: Vec<FeatureLocation>,
}

/// A tracker that cannot be built.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum TrackerError {
    /// A setting is out of range.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// The initial location is not finite or has a non-positive scale.
    #[error("initial location ({}, {}, scale {}) is not valid: the position must be finite and the scale positive", .0.c_x, .0.c_y, .0.scale)]
    BadInit(Location),
}

/// The paper's tracker: a target model, a camera, settings, and the state carried from
/// frame to frame (the three motion models). Initialised with a location (c_x, c_y,
/// scale), as the paper's teleoperator does (2.2).
#[derive(Clone, Debug)]
pub struct Tracker {
    config: TrackerConfig,
    model: TargetModel,
    camera: Camera,
    features: Vec<Feature>,
    half_extent_px: [f64; 2],
    target_width_px: f64,
    /// TargetSize of eq. 36: the model's width, metres.
    target_width_m: f64,
    motion: [MotionModel; 3],
    init: Location,
    frame: u64,
    last_t_s: Option<f64>,
    coast_cycles: u64,
    lost: bool,
    last_estimate: Location,
    // Scratch, kept between frames so that a step allocates little.
    extractor: EdgeExtractor,
    edges: Edges,
    predicted: Vec<PredictedFeature>,
    associations: Vec<Association>,
    rows: Vec<Row>,
}

impl Tracker {
    /// A tracker for `model` seen through `camera`, starting at `init`.
    pub fn new(
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
        let mut tracker = Tracker {
            config,
            model,
            camera,
            features,
            half_extent_px: half,
            target_width_px,
            target_width_m,
            motion: [MotionModel::new(lambda); 3],
            init,
            frame: 0,
            last_t_s: None,
            coast_cycles: 0,
            lost: false,
            last_estimate: init,
            extractor: EdgeExtractor::default(),
            edges: Edges::default(),
            predicted: Vec::new(),
            associations: Vec::new(),
            rows: Vec::new(),
        };
        tracker.reinitialize(init)?;
        Ok(tracker)
    }

    /// Starts again from `init`, with zero motion information (2.2: the target is taken
    /// to be still, at the location the teleoperator set).
    pub fn reinitialize(&mut self, init: Location) -> Result<(), TrackerError> {
        if !init.is_valid() {
            return Err(TrackerError::BadInit(init));
        }
        self.init = init;
        self.motion = [MotionModel::new(self.config.lambda); 3];
        self.frame = 0;
        self.last_t_s = None;
        self.coast_cycles = 0;
        self.lost = false;
        self.last_estimate = init;
        Ok(())
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

    /// The three motion models, [c_x, c_y, scale].
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
        self.run(image, t_s, None)
    }

    /// As [`Tracker::step`], and also returns every edge point in the window with its fate.
    pub fn step_with_diagnostics(
        &mut self,
        image: GrayView<'_>,
        t_s: f64,
    ) -> (TrackOutput, Vec<EdgeDiagnostic>) {
        let mut diagnostics = Vec::new();
        let out = self.run(image, t_s, Some(&mut diagnostics));
        (out, diagnostics)
    }

    fn run(
        &mut self,
        image: GrayView<'_>,
        t_s: f64,
        mut diagnostics: Option<&mut Vec<EdgeDiagnostic>>,
    ) -> TrackOutput {
        let cycles = match self.last_t_s {
            None => 0,
            Some(last) => (((t_s - last) * self.config.rate_hz).round().max(1.0)) as u32,
        };
        self.last_t_s = Some(t_s);
        let frame = self.frame;
        self.frame += 1;

        // Stage 6 of the previous cycle: where the target should be in this image.
        let predicted = if self.motion[0].has_information() {
            predict_location(&self.motion, f64::from(cycles))
        } else {
            self.init
        };
        for m in &mut self.motion {
            m.age(cycles);
        }

        let mut window = Window::default();
        let mut measurement = None;
        self.predicted.clear();
        self.associations.clear();
        let mut located = Vec::new();
        if !self.lost && predicted.is_valid() {
            window = Window::around(
                predicted,
                self.half_extent_px,
                &self.config,
                image.width(),
                image.height(),
            );
            // Stage 7 (for this image), then stages 1–4.
            predict_features(&self.features, predicted, &mut self.predicted);
            self.extractor.extract(
                image,
                window,
                &self.config,
                &mut self.edges,
                diagnostics.as_deref_mut(),
            );
            associate(
                &self.edges,
                &self.predicted,
                self.config.zeta_px,
                &mut self.associations,
                diagnostics,
            );
            locate_features(
                &self.predicted,
                &self.associations,
                &self.config,
                &mut located,
            );
            measurement = locate_object(&self.features, &located, &self.config, &mut self.rows);
        } else {
            self.lost = true;
        }

        // Stage 5: each parameter's model takes the measurement with its eq. 17 confidence.
        let status = match (&measurement, self.lost) {
            (Some(m), false) => {
                let l = m.location.to_array();
                for ((model, z), w) in self.motion.iter_mut().zip(l).zip(m.confidence) {
                    model.add(z, w);
                }
                self.coast_cycles = 0;
                Status::Tracking
            }
            _ => {
                self.coast_cycles += u64::from(cycles.max(1));
                let coasted_s = self.coast_cycles as f64 / self.config.rate_hz;
                if self.lost || coasted_s + 1e-9 >= self.config.lost_after_s {
                    self.lost = true;
                    Status::Lost
                } else {
                    Status::Coasting
                }
            }
        };

        // Stage 6: the prediction for the next frame (eq. 34).
        let next = if self.motion[0].has_information() {
            predict_location(&self.motion, 1.0)
        } else {
            predicted
        };
        let estimate = match &measurement {
            Some(m) if status == Status::Tracking => m.location,
            _ if status == Status::Lost => self.last_estimate,
            _ => predicted,
        };
        if status != Status::Lost {
            self.last_estimate = estimate;
        }
        TrackOutput {
            frame,
            t_s,
            status,
            measurement,
            predicted,
            estimate,
            next,
            position_3d: self.position_3d(estimate),
            window,
            features: located,
        }
    }
}

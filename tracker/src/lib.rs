//! The model-based vision tracker of Schneiderman, Nashman and Lumia, "Model-based vision
//! for car following" (NIST): a 2-D model of the back of the lead vehicle, made of
//! horizontal and vertical line segments, tracked in position and scale.
//!
//! The stages, in the paper's order (Figure 1), each a module:
//! 1. [`edges`]: edge extraction in the [`window`] of interest (2.3);
//! 2. [`association`]: data association (2.4);
//! 3. [`feature_location`]: feature location (2.5);
//! 4. [`object_location`]: object location (2.6);
//! 5. [`motion`]: the motion models' square root information filter (2.7);
//! 6. and 7. [`prediction`]: object and feature prediction (2.8);
//! 8. [`camera`]: the 3-D position (2.9).
//!
//! [`Tracker`] runs the loop. A pure library: 8-bit grey images in, estimates out; it knows
//! nothing of physics, rendering, scenario files or the file system.
//!
//! Image conventions: origin at the top-left corner, x right, y down, and pixel centres at
//! integer coordinates (pixel (i, j) is centred at x = i, y = j).
#![warn(missing_docs)]

pub mod association;
pub mod camera;
pub mod chamfer;
pub mod config;
pub mod edges;
pub mod feature_location;
pub mod gate;
pub mod gray;
pub mod householder;
pub mod location;
pub mod model;
pub mod motion;
pub mod object_location;
pub mod paint;
pub mod pixel_rect;
pub mod prediction;
pub mod resolvability;
pub mod robust;
mod step_io;
pub mod tracker;
pub mod window;

pub use camera::Camera;
pub use config::{ConfigError, TrackerConfig, TrackerMode};
pub use edges::{EdgeDiagnostic, EdgeFate, EdgePoint, Edges};
pub use feature_location::FeatureLocation;
pub use gate::{AcquireGate, GateRow};
pub use gray::{GrayView, ImageError};
pub use location::Location;
pub use model::{Feature, Orientation, TargetError, TargetModel};
pub use motion::MotionModel;
pub use object_location::Measurement;
pub use pixel_rect::PixelRect;
pub use prediction::PredictedFeature;
pub use tracker::{EgoMotion, Status, TrackEvent, TrackOutput, Tracker, TrackerError};
pub use window::Window;

#[cfg(feature = "synth")]
pub mod synth;

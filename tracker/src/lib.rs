//! The model-based vision tracker of Schneiderman, Nashman and Lumia, "Model-based vision
//! for car following" (NIST), stages 1–8.
//!
//! A pure library: 8-bit grey images in, estimates out. It knows nothing of physics,
//! rendering, scenario files or the file system.
#![warn(missing_docs)]

pub mod camera;
pub mod model;

pub use camera::Camera;
pub use model::{Feature, Orientation, TargetError, TargetModel};

//! The car-following simulator: the scene, the wgpu camera, the tracker on recorded frames,
//! and the `carfollow` command line.
#![warn(missing_docs)]
pub mod camera;
pub mod overlay;
pub mod scene;
pub mod target;
pub mod track;
pub mod record;
pub mod report;

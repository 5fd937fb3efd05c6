//! The car-following simulator: the scene, the wgpu camera, the tracker on recorded frames,
//! and the `carfollow` command line.
#![warn(missing_docs)]
pub mod camera;
pub mod closed_loop;
pub mod overlay;
pub mod record;
pub mod scenario;
pub mod scene;
pub mod target;
pub mod track;

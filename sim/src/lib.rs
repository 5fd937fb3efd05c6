//! The car-following simulator: the scene and its wgpu camera, the closed loop over the
//! `vehicle` physics and the `tracker`, scenario files, the record of a run and its reports,
//! the tracker on recorded frames, recordings that open in Foxglove with their replay, and
//! the `carfollow` command line.
#![warn(missing_docs)]
mod auto_gain;
pub mod camera;
pub mod child;
pub mod closed_loop;
pub mod driven_path;
mod frame_parts;
pub mod overlay;
pub mod record;
pub mod recording;
mod render_thread;
pub mod render_worker;
pub mod report;
pub mod scenario;
pub mod scene;
pub mod sweep;
pub mod target;
pub mod track;

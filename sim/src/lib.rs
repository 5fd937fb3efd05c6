//! sim
pub mod camera;
pub mod scene;

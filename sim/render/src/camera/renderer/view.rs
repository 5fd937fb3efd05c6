//! Where the camera stands for a field ([`CameraView`]): the one value the other modules
//! of the renderer take their view from. It imports none of them.

use crate::camera::frame::Field;
use crate::camera::rig::CameraRig;
use nalgebra::{Isometry3, Matrix4, Translation3, Vector3};

/// The camera for a field: its pose, and the frame positions reach the GPU in.
///
/// Positions reach the GPU relative to the camera (the origin), with every transform
/// composed in f64: in f32, world coordinates kilometres from the world's origin lose
/// millimetres, enough for the board to show through paint standing 3 mm proud of it.
pub(super) struct CameraView {
    pub world_from_camera: Isometry3<f64>,
    pub camera_from_world: Isometry3<f64>,
    /// The camera's position, the origin of what the GPU is given.
    pub eye: Vector3<f64>,
    /// Camera-relative positions to world ones, and back.
    pub world_from_relative: Matrix4<f64>,
    pub relative_from_world: Matrix4<f64>,
    /// Camera-relative positions to the camera's clip space.
    pub view_proj: Matrix4<f64>,
    /// The chase vehicle's pose (its headlamps ride on it).
    pub world_from_chase: Isometry3<f64>,
}

impl CameraView {
    /// The camera on the chase chassis, panned, as `field` has them.
    pub fn new(rig: &CameraRig, field: &Field) -> CameraView {
        let world_from_camera =
            rig.world_from_camera_panned(&field.world_from_chase, field.camera_pan_rad);
        let camera_from_world = world_from_camera.inverse();
        let eye = world_from_camera.translation.vector;
        let world_from_relative = Translation3::from(eye).to_homogeneous();
        let relative_from_world = Translation3::from(-eye).to_homogeneous();
        let view_proj =
            rig.clip_from_camera() * camera_from_world.to_homogeneous() * world_from_relative;
        CameraView {
            world_from_camera,
            camera_from_world,
            eye,
            world_from_relative,
            relative_from_world,
            view_proj,
            world_from_chase: field.world_from_chase,
        }
    }
}

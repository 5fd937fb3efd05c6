//! The rain's streaks on a frame read back (`rain_streaks`), before the sensor.

use super::Renderer;
use crate::camera::frame::FrameInput;
use crate::camera::rain_streaks::{draw_streaks, StreakView};
use crate::scene::Rain;
use image::GrayImage;
use nalgebra::Vector3;

impl Renderer {
    /// Draws frame `input`'s rain streaks on `image` when rain falls (nothing otherwise).
    /// The drops refract light from nearly a hemisphere around them (Garg & Nayar 2007,
    /// "Vision and rain", IJCV 75): half the sky above them and half the lit ground and
    /// spray below, here the mean of the sky's light and the airlight (a white, matte
    /// surface's light under the ambient and a quarter of the sun, [`Rain::airlight`]),
    /// times the sensor's brightness. The headlamps' light on the drops is left out.
    pub(super) fn draw_rain(&mut self, image: &mut GrayImage, input: &FrameInput) {
        let scene = std::sync::Arc::clone(&self.scene);
        let description = scene.description();
        let Some(rain) = description.raining() else {
            return;
        };
        let hood_row =
            self.main
                .hood
                .rows(&self.rig, &description.chase, input.camera_pan_rad) as usize;
        let world_from_camera = self
            .rig
            .world_from_camera_panned(&input.world_from_chase, input.camera_pan_rad);
        let sun_light = description.sun.lighting();
        let brightness = description.sensor.brightness() * input.auto_gain;
        let drop_light = 0.5 * (description.sky_light(&sun_light) + Rain::airlight(&sun_light));
        let view = StreakView {
            camera: &self.rig.intrinsics,
            camera_from_world: world_from_camera.rotation.inverse(),
            camera_velocity: input.world_from_chase.rotation
                * Vector3::new(input.chase_speed_mps, 0.0, 0.0),
            exposure_s: description.sensor.exposure_ms * 1e-3,
            drop_grey: (255.0 * drop_light * brightness).clamp(0.0, 255.0),
            hood_row,
        };
        draw_streaks(image, &rain, &view, description.seed, input.frame_index);
    }
}

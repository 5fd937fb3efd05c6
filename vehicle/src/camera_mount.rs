//! Where the camera sits on the chase vehicle, and the transform from the camera frame to
//! the vehicle frame.
//!
//! Camera frame (tracker stage 8): x right, y down, z forward. Vehicle frame: x forward,
//! y up, z right. Both are right-handed.

use crate::error::{check_range, VehicleError};
use rapier3d::math::{Mat3, Pose, Rotation, Vector};
use serde::{Deserialize, Serialize};

/// The camera's mounting on the chassis.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct CameraMount {
    /// Distance of the camera ahead of the rear axle, m (default 2.2 m: above the HMMWV's
    /// windscreen).
    #[schemars(extend("minimum" = -10.0, "maximum" = 10.0))]
    pub forward_m: f32,
    /// Height of the camera above the ground at nominal ride height, m (default 2.0 m: on
    /// the HMMWV's cab roof).
    #[schemars(extend("minimum" = 0.1, "maximum" = 10.0))]
    pub height_m: f32,
    /// Offset of the camera to the right of the centreline, m (default 0).
    #[schemars(extend("minimum" = -5.0, "maximum" = 5.0))]
    pub right_m: f32,
    /// Downward tilt of the optical axis, degrees (default 3°, so the lead's back sits a
    /// little below the image centre at 10 m).
    #[schemars(extend("minimum" = -45.0, "maximum" = 45.0))]
    pub pitch_down_deg: f32,
}

impl Default for CameraMount {
    fn default() -> Self {
        CameraMount {
            forward_m: 2.2,
            height_m: 2.0,
            right_m: 0.0,
            pitch_down_deg: 3.0,
        }
    }
}

impl CameraMount {
    /// Checks the mount for plausible values.
    pub fn validate(&self) -> Result<(), VehicleError> {
        check_range("forward_m", f64::from(self.forward_m), -10.0, 10.0)?;
        check_range("height_m", f64::from(self.height_m), 0.1, 10.0)?;
        check_range("right_m", f64::from(self.right_m), -5.0, 5.0)?;
        check_range(
            "pitch_down_deg",
            f64::from(self.pitch_down_deg),
            -45.0,
            45.0,
        )
    }

    /// The camera frame in the vehicle frame, straight ahead.
    pub fn vehicle_from_camera(&self) -> Pose {
        self.vehicle_from_camera_panned(0.0)
    }

    /// The camera frame in the vehicle frame with the camera panned by `pan_rad` about the
    /// vehicle's vertical axis through the mount (positive to the right; see
    /// [`crate::PanHead`]).
    pub fn vehicle_from_camera_panned(&self, pan_rad: f32) -> Pose {
        let (s, c) = self.pitch_down_deg.to_radians().sin_cos();
        // Camera axes expressed in the vehicle frame.
        let z_cam = Vector::new(c, -s, 0.0); // optical axis: forward, tilted down
        let x_cam = Vector::Z; // right
        let y_cam = z_cam.cross(x_cam); // down, tilted back
                                        // Turning right is a negative rotation about y (up).
        let rotation = Rotation::from_rotation_y(-pan_rad)
            * Rotation::from_mat3(&Mat3::from_cols(x_cam, y_cam, z_cam));
        Pose::from_parts(
            Vector::new(self.forward_m, self.height_m, self.right_m),
            rotation,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_camera_axes() {
        let m = CameraMount {
            pitch_down_deg: 0.0,
            ..CameraMount::default()
        };
        let v_from_c = m.vehicle_from_camera();
        // 10 m straight ahead of a level camera is 10 m ahead of it in the vehicle frame.
        let p = v_from_c.transform_point(Vector::new(0.0, 0.0, 10.0));
        assert!((p - Vector::new(12.2, 2.0, 0.0)).length() < 1e-5, "{p}");
        // Camera right is vehicle right; camera down is vehicle down.
        assert!((v_from_c.rotation * Vector::X - Vector::Z).length() < 1e-6);
        assert!((v_from_c.rotation * Vector::Y + Vector::Y).length() < 1e-6);
    }

    #[test]
    fn pitched_camera_looks_down() {
        let m = CameraMount::default();
        let p = m
            .vehicle_from_camera()
            .transform_point(Vector::new(0.0, 0.0, 10.0));
        assert!(p.y < 2.0 - 0.5, "{p}");
    }

    #[test]
    fn a_camera_panned_right_looks_right() {
        let m = CameraMount {
            pitch_down_deg: 0.0,
            ..CameraMount::default()
        };
        let p = m
            .vehicle_from_camera_panned(30f32.to_radians())
            .transform_point(Vector::new(0.0, 0.0, 10.0));
        // 10 m along the optical axis: 30° right of forward (z is right), at mount height.
        let want = Vector::new(2.2 + 10.0 * 0.866_025_4, 2.0, 5.0);
        assert!((p - want).length() < 1e-4, "{p}");
    }
}

//! The camera rig: intrinsics, image size and the mount on the chase vehicle, and the
//! matrices that take world points to the image.

use crate::scene::CameraMount;
use nalgebra::{Isometry3, Matrix3, Matrix4, Point3, Rotation3, Translation3, UnitQuaternion};

/// Near clipping plane, metres: closer than the hood's nearest point seen by the camera.
pub const NEAR_M: f64 = 0.5;
/// Far clipping plane, metres: the tracker cares about 5–30 m; a house at 250 m is a dozen
/// pixels, and llvmpipe's cost grows with every triangle drawn (the ground beyond shows as
/// sky a few pixels under the true horizon).
pub const FAR_M: f64 = 250.0;

/// Intrinsics, image size and mount.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CameraRig {
    /// Pinhole intrinsics: the very object the tracker's stage 8 uses.
    pub intrinsics: tracker::Camera,
    /// Image width, pixels (256 in paper section 3).
    pub width: u32,
    /// Image height, pixels (242 in paper section 3).
    pub height: u32,
    /// Where the camera sits on the chase vehicle.
    pub mount: CameraMount,
}

impl Default for CameraRig {
    /// The paper's 256×242 frame with [`tracker::Camera::default`] and the default mount.
    fn default() -> Self {
        CameraRig {
            intrinsics: tracker::Camera::default(),
            width: 256,
            height: 242,
            mount: CameraMount::default(),
        }
    }
}

impl CameraRig {
    /// The camera frame (x right, y down, z forward) in the chase vehicle's frame
    /// (x forward, y up, z right), pitched down by the mount's pitch.
    pub fn chase_from_camera(&self) -> Isometry3<f64> {
        let p = self.mount.pitch_deg.to_radians();
        let (s, c) = p.sin_cos();
        // Columns: camera x = vehicle z; camera y = down, tilted; camera z = forward, tilted.
        let rotation = Rotation3::from_matrix_unchecked(Matrix3::new(
            0.0, -s, c, //
            0.0, -c, -s, //
            1.0, 0.0, 0.0,
        ));
        Isometry3::from_parts(
            Translation3::new(self.mount.forward_offset_m, self.mount.height_m, 0.0),
            UnitQuaternion::from_rotation_matrix(&rotation),
        )
    }

    /// The camera's pose in the world, following the chase chassis (including its pitch
    /// and roll, which `world_from_chase` carries), looking straight ahead.
    pub fn world_from_camera(&self, world_from_chase: &Isometry3<f64>) -> Isometry3<f64> {
        world_from_chase * self.chase_from_camera()
    }

    /// The camera frame in the chase vehicle's frame with the camera panned by `pan_rad`
    /// about the vehicle's vertical axis through the mount (positive to the right).
    pub fn chase_from_camera_panned(&self, pan_rad: f64) -> Isometry3<f64> {
        let straight = self.chase_from_camera();
        // Turning right is a negative rotation about y (up).
        let pan = UnitQuaternion::from_axis_angle(&nalgebra::Vector3::y_axis(), -pan_rad);
        Isometry3::from_parts(straight.translation, pan * straight.rotation)
    }

    /// The camera's pose in the world with the camera panned by `pan_rad` (see
    /// [`CameraRig::chase_from_camera_panned`]).
    pub fn world_from_camera_panned(
        &self,
        world_from_chase: &Isometry3<f64>,
        pan_rad: f64,
    ) -> Isometry3<f64> {
        if pan_rad == 0.0 {
            // Bit for bit the fixed camera's pose.
            return self.world_from_camera(world_from_chase);
        }
        world_from_chase * self.chase_from_camera_panned(pan_rad)
    }

    /// Projects a camera-frame point to clip space for wgpu (x right, y up, depth 0..1),
    /// so that after the viewport transform the point lands where
    /// [`tracker::Camera::project`] says, in the integer-centre convention. wgpu's
    /// framebuffer puts pixel i's centre at i + 0.5, hence the half-pixel shift.
    pub fn clip_from_camera(&self) -> Matrix4<f64> {
        let [fx, fy] = self.intrinsics.focal_px();
        let [cx, cy] = self.intrinsics.image_center_px;
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let (n, f) = (NEAR_M, FAR_M);
        let a = f / (f - n);
        Matrix4::new(
            2.0 * fx / w,
            0.0,
            2.0 * (cx + 0.5) / w - 1.0,
            0.0, //
            0.0,
            -2.0 * fy / h,
            1.0 - 2.0 * (cy + 0.5) / h,
            0.0, //
            0.0,
            0.0,
            a,
            -a * n, //
            0.0,
            0.0,
            1.0,
            0.0,
        )
    }

    /// Where the renderer's matrix puts a world point, pixels (integer-centre convention):
    /// the same arithmetic the vertex shader and viewport do, in f64. `None` behind the
    /// camera.
    pub fn project_world(
        &self,
        world_from_chase: &Isometry3<f64>,
        point_world: [f64; 3],
    ) -> Option<[f64; 2]> {
        let cam = self.world_from_camera(world_from_chase).inverse()
            * Point3::new(point_world[0], point_world[1], point_world[2]);
        let clip = self.clip_from_camera() * cam.to_homogeneous();
        if clip.w <= 0.0 {
            return None;
        }
        let (nx, ny) = (clip.x / clip.w, clip.y / clip.w);
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        Some([(nx + 1.0) * 0.5 * w - 0.5, (1.0 - ny) * 0.5 * h - 0.5])
    }
}

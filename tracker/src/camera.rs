//! The pinhole camera, and stage 8: the target's 3-D position (paper 2.9, eq. 36).
//!
//! Conventions shared with the renderer: the camera frame is x right, y down, z forward
//! (metres). Image coordinates have their origin at the top-left corner and **pixel centres
//! at integer coordinates**: pixel (i, j) is centred at x = i, y = j.

/// Pinhole intrinsics: the "intrinsic camera parameters" eq. 36 needs.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Camera {
    /// Focal length, millimetres.
    pub focal_length_mm: f64,
    /// Pixel size on the CCD, millimetres: `[width, height]` (the "mm/pixel" of eq. 36).
    pub pixel_size_mm: [f64; 2],
    /// Image centre (principal point), pixels, in the integer-centre convention.
    pub image_center_px: [f64; 2],
}

impl Default for Camera {
    /// An 8 mm lens on a CCD with 25 µm pixels (320 px focal length), centred on the 256×242
    /// frame of paper section 3. At the shipped target's 10 m nominal range a 1.6 m wide
    /// target then spans 51 px: large enough for stable features, small enough to track at
    /// 5 m (102 px) and at 15 m (34 px).
    fn default() -> Self {
        Camera {
            focal_length_mm: 8.0,
            pixel_size_mm: [0.025, 0.025],
            image_center_px: [127.5, 120.5],
        }
    }
}

impl Camera {
    /// The focal length in pixels along image x and y: `f_mm / (mm/pixel)`.
    pub fn focal_px(&self) -> [f64; 2] {
        [
            self.focal_length_mm / self.pixel_size_mm[0],
            self.focal_length_mm / self.pixel_size_mm[1],
        ]
    }

    /// Projects a point in the camera frame (metres, z forward) to image pixels.
    /// Returns `None` for points at or behind the camera.
    pub fn project(&self, point_cam: [f64; 3]) -> Option<[f64; 2]> {
        let [x, y, z] = point_cam;
        if z <= 0.0 {
            return None;
        }
        let [fx, fy] = self.focal_px();
        Some([
            self.image_center_px[0] + fx * x / z,
            self.image_center_px[1] + fy * y / z,
        ])
    }

    /// Stage 8 (eq. 36): the target's position in the camera frame (metres: x right, y down,
    /// z forward) from its image location `(c_x, c_y)`, its size in the image
    /// `target_size_image_px` (pixels, along image x) and its physical size `target_size_m`
    /// (metres, the same dimension).
    ///
    /// z = TargetSize / (TargetSizeImage · mm/pixel) · FocalLength, then
    /// x = (C_x − ImageCenterX) · mm/pixel · z / FocalLength, and likewise y.
    ///
    /// The paper prints z's pixel-size factor as a multiplier; the pinhole relation (and
    /// the units: metres from metres) need it as a divisor, as in x and y, so it divides
    /// here. A test checks the round trip through [`Camera::project`].
    pub fn position_3d(
        &self,
        c_x: f64,
        c_y: f64,
        target_size_image_px: f64,
        target_size_m: f64,
    ) -> [f64; 3] {
        let z =
            target_size_m / (target_size_image_px * self.pixel_size_mm[0]) * self.focal_length_mm;
        let x = (c_x - self.image_center_px[0]) * self.pixel_size_mm[0] * z / self.focal_length_mm;
        let y = (c_y - self.image_center_px[1]) * self.pixel_size_mm[1] * z / self.focal_length_mm;
        [x, y, z]
    }
}

//! What passes between Python and the loop: `Estimate`, `Command`, `ControlInput` and
//! `Camera`, each a Python class over its Rust twin in `sim_core`.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use sim_core::{CameraModel, EstimateStatus};

/// A tracker's estimate of the target in the camera's frame (x right, y down, z forward,
/// metres), with its image location where the tracker has one.
#[pyclass(module = "carfollow", name = "Estimate", eq, from_py_object)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    pub(crate) inner: sim_core::Estimate,
}

#[pymethods]
impl Estimate {
    #[new]
    #[pyo3(signature = (range_m, lateral_m, cx=None, cy=None, scale=None, status="tracking", vertical_m=None, vehicle=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        range_m: f64,
        lateral_m: f64,
        cx: Option<f64>,
        cy: Option<f64>,
        scale: Option<f64>,
        status: &str,
        vertical_m: Option<f64>,
        vehicle: Option<usize>,
    ) -> PyResult<Estimate> {
        let status = EstimateStatus::parse(status).ok_or_else(|| {
            PyValueError::new_err(format!(
                "status = {status:?}: must be \"tracking\", \"coasting\" or \"lost\""
            ))
        })?;
        let inner = sim_core::Estimate {
            range_m,
            lateral_m,
            vertical_m,
            cx,
            cy,
            scale,
            status,
            vehicle,
        };
        inner
            .validate()
            .map_err(|e| PyValueError::new_err(format!("Estimate: {e}")))?;
        Ok(Estimate { inner })
    }

    /// Distance ahead along the optical axis, metres.
    #[getter]
    fn range_m(&self) -> f64 {
        self.inner.range_m
    }

    /// Offset to the right, metres.
    #[getter]
    fn lateral_m(&self) -> f64 {
        self.inner.lateral_m
    }

    /// Offset downwards, metres (None: from cy, else 0).
    #[getter]
    fn vertical_m(&self) -> Option<f64> {
        self.inner.vertical_m
    }

    /// The target's centre in the image, pixels (x).
    #[getter]
    fn cx(&self) -> Option<f64> {
        self.inner.cx
    }

    /// The target's centre in the image, pixels (y).
    #[getter]
    fn cy(&self) -> Option<f64> {
        self.inner.cy
    }

    /// The target's size relative to its size at the nominal range.
    #[getter]
    fn scale(&self) -> Option<f64> {
        self.inner.scale
    }

    /// "tracking", "coasting" or "lost".
    #[getter]
    fn status(&self) -> &'static str {
        self.inner.status.as_str()
    }

    /// The vehicle the tracker says it holds: its index in the truth's "vehicles" list
    /// (1 the lead, 2 on the actors; without a lead, 1 on), or None when it does not say.
    #[getter]
    fn vehicle(&self) -> Option<usize> {
        self.inner.vehicle
    }

    fn __repr__(&self) -> String {
        let e = &self.inner;
        let opt = |v: Option<f64>| v.map_or("None".to_string(), |v| format!("{v}"));
        format!(
            "Estimate(range_m={}, lateral_m={}, cx={}, cy={}, scale={}, status={:?}{})",
            e.range_m,
            e.lateral_m,
            opt(e.cx),
            opt(e.cy),
            opt(e.scale),
            e.status.as_str(),
            e.vehicle
                .map_or(String::new(), |v| format!(", vehicle={v}"))
        )
    }
}

/// A controller's commands for one physics step.
#[pyclass(module = "carfollow", name = "Command", eq, from_py_object)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Command {
    pub(crate) inner: sim_core::Command,
}

#[pymethods]
impl Command {
    #[new]
    #[pyo3(signature = (steering_rad, throttle, brake, pan_rate_rad_s=0.0))]
    fn new(steering_rad: f64, throttle: f64, brake: f64, pan_rate_rad_s: f64) -> PyResult<Command> {
        let inner = sim_core::Command {
            steering_rad,
            throttle,
            brake,
            pan_rate_rad_s,
        };
        inner
            .validate()
            .map_err(|e| PyValueError::new_err(format!("Command: {e}")))?;
        Ok(Command { inner })
    }

    /// Road-wheel steering angle asked for, radians, positive to the right.
    #[getter]
    fn steering_rad(&self) -> f64 {
        self.inner.steering_rad
    }

    /// Throttle, 0–1.
    #[getter]
    fn throttle(&self) -> f64 {
        self.inner.throttle
    }

    /// Brake, 0–1.
    #[getter]
    fn brake(&self) -> f64 {
        self.inner.brake
    }

    /// The pan head's rate asked for, rad/s.
    #[getter]
    fn pan_rate_rad_s(&self) -> f64 {
        self.inner.pan_rate_rad_s
    }

    fn __repr__(&self) -> String {
        let c = &self.inner;
        format!(
            "Command(steering_rad={}, throttle={}, brake={}, pan_rate_rad_s={})",
            c.steering_rad, c.throttle, c.brake, c.pan_rate_rad_s
        )
    }
}

/// What a controller is given at one physics step: the delayed estimate and the chase's own
/// state. Read-only.
#[pyclass(module = "carfollow", name = "ControlInput", frozen)]
#[derive(Clone, Copy, Debug)]
pub struct ControlInput {
    pub(crate) inner: sim_core::ControlInput,
}

#[pymethods]
impl ControlInput {
    /// The latest estimate the delay line has delivered (None before the first).
    #[getter]
    fn estimate(&self) -> Option<Estimate> {
        self.inner.estimate.map(|inner| Estimate { inner })
    }

    /// Whether `estimate` arrived at this step.
    #[getter]
    fn fresh(&self) -> bool {
        self.inner.fresh
    }

    /// The capture time of the estimate's frame, seconds.
    #[getter]
    fn captured_t(&self) -> Option<f64> {
        self.inner.captured_t_s
    }

    /// The pan head's reading at the estimate's capture, radians.
    #[getter]
    fn captured_pan_rad(&self) -> Option<f64> {
        self.inner.captured_pan_rad
    }

    /// The time now, seconds.
    #[getter]
    fn t(&self) -> f64 {
        self.inner.t_s
    }

    /// The chase's forward speed, m/s.
    #[getter]
    fn speed_mps(&self) -> f64 {
        self.inner.speed_mps
    }

    /// The chase's yaw rate, rad/s (positive turning right).
    #[getter]
    fn yaw_rate_rad_s(&self) -> f64 {
        self.inner.yaw_rate_rad_s
    }

    /// The chase's steering angle now, radians (positive to the right).
    #[getter]
    fn steering_rad(&self) -> f64 {
        self.inner.steering_rad
    }

    /// The pan head's encoder reading, radians (0 for a fixed camera).
    #[getter]
    fn pan_rad(&self) -> f64 {
        self.inner.pan_rad
    }

    /// The chase's rear axle in the world by its odometry, metres (x, y up, z).
    #[getter]
    fn position_m(&self) -> (f64, f64, f64) {
        let t = self.inner.world_from_chase.translation;
        (f64::from(t.x), f64::from(t.y), f64::from(t.z))
    }

    /// The chase's heading by its odometry, radians: the angle of its forward axis from the
    /// world's +x towards +z (turning right).
    #[getter]
    fn heading_rad(&self) -> f64 {
        let forward = self.inner.world_from_chase.rotation * vehicle::Vector::new(1.0, 0.0, 0.0);
        f64::from(forward.z).atan2(f64::from(forward.x))
    }

    fn __repr__(&self) -> String {
        format!(
            "ControlInput(t={:.4}, speed_mps={:.3}, fresh={}, estimate={})",
            self.inner.t_s,
            self.inner.speed_mps,
            self.inner.fresh,
            self.estimate().map_or("None".into(), |e| e.__repr__())
        )
    }
}

/// The camera a tracker is given: intrinsics, image size, mount, the pan head's reading at
/// the frame's capture, and the target model. Read-only.
#[pyclass(module = "carfollow", name = "Camera", frozen)]
#[derive(Clone, Debug)]
pub struct Camera {
    pub(crate) inner: CameraModel,
    /// The gyro's reading since the last frame, with a frame.
    pub(crate) gyro_rad: Option<[f64; 3]>,
}

#[pymethods]
impl Camera {
    /// Focal length, millimetres.
    #[getter]
    fn focal_length_mm(&self) -> f64 {
        self.inner.intrinsics.focal_length_mm
    }

    /// Pixel size on the sensor, millimetres (width, height).
    #[getter]
    fn pixel_size_mm(&self) -> (f64, f64) {
        let [w, h] = self.inner.intrinsics.pixel_size_mm;
        (w, h)
    }

    /// The focal length in pixels (x, y).
    #[getter]
    fn focal_px(&self) -> (f64, f64) {
        let [x, y] = self.inner.intrinsics.focal_px();
        (x, y)
    }

    /// The principal point, pixels (pixel centres at integer coordinates).
    #[getter]
    fn image_center_px(&self) -> (f64, f64) {
        let [x, y] = self.inner.intrinsics.image_center_px;
        (x, y)
    }

    /// Image width, pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.inner.width
    }

    /// Image height, pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.inner.height
    }

    /// The camera's height above the ground, metres.
    #[getter]
    fn mount_height_m(&self) -> f64 {
        self.inner.mount_height_m
    }

    /// How far ahead of the chase's rear axle the camera sits, metres.
    #[getter]
    fn mount_forward_m(&self) -> f64 {
        self.inner.mount_forward_m
    }

    /// How far the camera is pitched down, degrees.
    #[getter]
    fn mount_pitch_down_deg(&self) -> f64 {
        self.inner.mount_pitch_down_deg
    }

    /// The pan head's encoder reading at the frame's capture, radians (0: fixed camera).
    #[getter]
    fn pan_rad(&self) -> f64 {
        self.inner.pan_rad
    }

    /// The chase's rate gyro: the camera's rotation since the previous frame, radians, as a
    /// rotation vector in the previous camera frame (+y turns the camera right, +x tilts it
    /// up), with the gyro's bias and noise; None on the first frame and in reset().
    #[getter]
    fn gyro_rad(&self) -> Option<(f64, f64, f64)> {
        self.gyro_rad.map(|[x, y, z]| (x, y, z))
    }

    /// The target's size, metres (width, height).
    #[getter]
    fn target_size_m(&self) -> (f64, f64) {
        let [w, h] = self.inner.target.size_m();
        (w, h)
    }

    /// The range at which the target's scale is 1, metres.
    #[getter]
    fn target_nominal_range_m(&self) -> f64 {
        self.inner.target.nominal_range_m()
    }

    /// The target's size in the image at scale 1, pixels (width, height).
    #[getter]
    fn target_size_px(&self) -> (f64, f64) {
        let ([fx, fy], [w, h]) = (self.inner.intrinsics.focal_px(), self.inner.target.size_m());
        let r = self.inner.target.nominal_range_m();
        (w * fx / r, h * fy / r)
    }

    /// The target model's line segments, metres about its centre at the nominal range
    /// (x right, y up): ((x0, y0), (x1, y1)) each.
    #[getter]
    fn target_segments(&self) -> Vec<((f64, f64), (f64, f64))> {
        let corners = self.inner.target.corners_m();
        self.inner
            .target
            .segments()
            .iter()
            .map(|&[a, b]| {
                let (a, b) = (corners[a], corners[b]);
                ((a[0], a[1]), (b[0], b[1]))
            })
            .collect()
    }

    /// Projects a point in the camera frame (metres, x right, y down, z forward) to image
    /// pixels; None behind the camera.
    fn project(&self, x: f64, y: f64, z: f64) -> Option<(f64, f64)> {
        self.inner
            .intrinsics
            .project([x, y, z])
            .map(|[u, v]| (u, v))
    }

    fn __repr__(&self) -> String {
        format!(
            "Camera(focal_length_mm={}, {}x{}, pan_rad={:.4}, target={:?})",
            self.inner.intrinsics.focal_length_mm,
            self.inner.width,
            self.inner.height,
            self.inner.pan_rad,
            self.inner.target.name()
        )
    }
}

//! The recording's own message types, beside Foxglove's well-known ones: the tracker's
//! state, the chase controller's commands, the ground truth (each a flat protobuf message,
//! so that Foxglove plots every field), and the tracker's input on each frame, which replay
//! reads back.

use foxglove::Encode;

/// The tracker's output on one frame (`/tracker/state`).
#[derive(Clone, Debug, Default, Encode)]
pub struct TrackerState {
    /// Frame index from 0.
    pub frame: u64,
    /// Capture time, seconds.
    pub t_s: f64,
    /// `tracking`, `coasting` or `lost`.
    pub status: String,
    /// The status as a number to plot: 0 tracking, 1 coasting, 2 lost.
    pub status_code: u32,
    /// Whether stage 4 made a measurement.
    pub measured: bool,
    /// The estimate: the measurement, else the prediction (pixels, pixels, scale).
    pub est_cx_px: f64,
    /// See `est_cx_px`.
    pub est_cy_px: f64,
    /// See `est_cx_px`.
    pub est_scale: f64,
    /// The location predicted for this frame.
    pub pred_cx_px: f64,
    /// See `pred_cx_px`.
    pub pred_cy_px: f64,
    /// See `pred_cx_px`.
    pub pred_scale: f64,
    /// Stage 8: the target in the camera frame, metres (x right, y down, z forward).
    pub x_m: f64,
    /// See `x_m`.
    pub y_m: f64,
    /// See `x_m`: the range.
    pub z_m: f64,
    /// Eq. 17 confidences (0 without a measurement).
    pub confidence_x: f64,
    /// See `confidence_x`.
    pub confidence_y: f64,
    /// See `confidence_x`.
    pub confidence_scale: f64,
    /// The share of the measured outline covered by edges, horizontal features.
    pub coverage_h: f64,
    /// The same for vertical features.
    pub coverage_v: f64,
    /// How much more a small move would cover (NaN where not computed, or where the fit
    /// jumped too far to be trusted: the tracker's −∞ and +∞, which would upset a plot's
    /// axis).
    pub coverage_gain: f64,
    /// The edge threshold used, on eq. 4's |∇f| in grey levels per pixel.
    pub edge_threshold: f64,
    /// Whether a chamfer search ran (robust mode).
    pub searched: bool,
    /// `acquired` or `reacquired`, else empty.
    pub event: String,
    /// The window of interest's size index.
    pub window_size: u32,
}

/// The chase controller's commands and state after one frame (`/controller`).
#[derive(Clone, Debug, Default, Encode)]
pub struct ControllerState {
    /// Frame index.
    pub frame: u64,
    /// The controller's mode (`following`, `stopping`, ...).
    pub mode: String,
    /// Front-wheel steering, radians, positive left.
    pub steering_rad: f64,
    /// Throttle, 0–1.
    pub throttle: f64,
    /// Brake, 0–1.
    pub brake: f64,
    /// The chase's forward speed, m/s (odometry).
    pub chase_speed_mps: f64,
    /// The gap the gap keeper steers by, metres (NaN before any estimate).
    pub gap_estimate_m: f64,
    /// The gap it aims for, metres.
    pub desired_gap_m: f64,
    /// Its speed reference, m/s.
    pub speed_ref_mps: f64,
    /// The path curvature pure pursuit commands, 1/m.
    pub curvature: f64,
    /// Whether the emergency brake is on.
    pub emergency: bool,
    /// Breadcrumbs on the trail.
    pub breadcrumbs: u32,
    /// The largest curvature of the lead's path ahead, 1/m (the curve-aware gap keeping's).
    pub curvature_ahead: f64,
    /// Where the pan head is aimed, degrees, positive to the right (0 without one).
    pub pan_aim_deg: f64,
    /// The rate commanded of the pan head, degrees per second.
    pub pan_rate_cmd_deg_s: f64,
}

/// What only the recorder sees (`/truth`).
#[derive(Clone, Debug, Default, Encode)]
pub struct GroundTruth {
    /// Frame index.
    pub frame: u64,
    /// The target's true centre in the image, pixels.
    pub true_cx_px: f64,
    /// See `true_cx_px`.
    pub true_cy_px: f64,
    /// True scale.
    pub true_scale: f64,
    /// True range along the optical axis, metres.
    pub true_range_m: f64,
    /// True lateral offset in the camera frame, metres.
    pub true_lateral_m: f64,
    /// The estimate's range error, metres (estimate − truth).
    pub range_error_m: f64,
    /// The estimate's image error, pixels.
    pub image_error_px: f64,
    /// Whether the whole target is in view.
    pub in_view: bool,
    /// Whether the target is partly out of view (some of it in the image, not all).
    pub partly_out_of_view: bool,
    /// The ground truth's judgement that tracking is lost.
    pub lost_truth: bool,
    /// The following distance, metres.
    pub gap_m: f64,
    /// The lead's speed, m/s.
    pub lead_speed_mps: f64,
    /// The chase's distance from the lead's path, metres.
    pub lateral_deviation_m: f64,
    /// Distance the chase has driven, metres.
    pub chase_distance_m: f64,
    /// The vehicles touched during this frame.
    pub collision: bool,
    /// Why the frame is lost (`out_of_view`, `occluded`, `tracker`; empty when it is not).
    pub loss_cause: String,
    /// The pan head's true angle, degrees, positive to the right (0 without one).
    pub camera_pan_deg: f64,
}

/// What the tracker was given with one frame besides the image (`/tracker/input`): the
/// time, and in robust mode the gyro's reading of the camera's rotation. Replay reads it
/// back with [`TrackerInputDecoded`].
#[derive(Clone, Debug, Default, Encode)]
pub struct TrackerInput {
    /// Frame index.
    pub frame: u64,
    /// The time handed to the tracker, seconds.
    pub t_s: f64,
    /// Whether the tracker was given the gyro's reading.
    pub aided: bool,
    /// The rotation vector, radians (previous camera frame), when `aided`.
    pub ego_x_rad: f64,
    /// See `ego_x_rad`.
    pub ego_y_rad: f64,
    /// See `ego_x_rad`.
    pub ego_z_rad: f64,
}

/// [`TrackerInput`] as replay decodes it: the same fields, numbered as the SDK's derive
/// numbers them (declaration order from 1; a test checks the two agree).
#[derive(Clone, PartialEq, prost::Message)]
pub struct TrackerInputDecoded {
    /// Frame index.
    #[prost(uint64, tag = "1")]
    pub frame: u64,
    /// Time, seconds.
    #[prost(double, tag = "2")]
    pub t_s: f64,
    /// Whether the gyro's reading was given.
    #[prost(bool, tag = "3")]
    pub aided: bool,
    /// Rotation vector x, radians.
    #[prost(double, tag = "4")]
    pub ego_x_rad: f64,
    /// Rotation vector y, radians.
    #[prost(double, tag = "5")]
    pub ego_y_rad: f64,
    /// Rotation vector z, radians.
    #[prost(double, tag = "6")]
    pub ego_z_rad: f64,
}

/// The tracker's state as replay decodes it (the fields replay compares).
#[derive(Clone, PartialEq, prost::Message)]
pub struct TrackerStateDecoded {
    /// Frame index.
    #[prost(uint64, tag = "1")]
    pub frame: u64,
    /// Time, seconds.
    #[prost(double, tag = "2")]
    pub t_s: f64,
    /// Status.
    #[prost(string, tag = "3")]
    pub status: String,
    /// Estimate, pixels.
    #[prost(double, tag = "6")]
    pub est_cx_px: f64,
    /// Estimate, pixels.
    #[prost(double, tag = "7")]
    pub est_cy_px: f64,
    /// Estimate, scale.
    #[prost(double, tag = "8")]
    pub est_scale: f64,
    /// Stage 8, metres.
    #[prost(double, tag = "12")]
    pub x_m: f64,
    /// Stage 8, metres.
    #[prost(double, tag = "14")]
    pub z_m: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use prost::Message;

    #[test]
    fn replay_decodes_what_the_sdk_encodes() {
        let input = TrackerInput {
            frame: 7,
            t_s: 7.0 / 15.0,
            aided: true,
            ego_x_rad: -1.25e-3,
            ego_y_rad: f64::MIN_POSITIVE,
            ego_z_rad: 0.1 + 0.2,
        };
        let mut buf = Vec::new();
        foxglove::Encode::encode(&input, &mut buf).unwrap();
        let back = TrackerInputDecoded::decode(buf.as_slice()).unwrap();
        assert_eq!(back.frame, 7);
        assert_eq!(back.t_s.to_bits(), input.t_s.to_bits());
        assert!(back.aided);
        assert_eq!(back.ego_x_rad.to_bits(), input.ego_x_rad.to_bits());
        assert_eq!(back.ego_y_rad.to_bits(), input.ego_y_rad.to_bits());
        assert_eq!(back.ego_z_rad.to_bits(), input.ego_z_rad.to_bits());

        let state = TrackerState {
            frame: 3,
            t_s: 0.2,
            status: "coasting".into(),
            est_cx_px: 127.25,
            est_cy_px: -3.5,
            est_scale: 1.0625,
            x_m: 0.125,
            y_m: 9.0,
            z_m: 10.5,
            ..TrackerState::default()
        };
        let mut buf = Vec::new();
        foxglove::Encode::encode(&state, &mut buf).unwrap();
        let back = TrackerStateDecoded::decode(buf.as_slice()).unwrap();
        assert_eq!(
            (back.frame, back.t_s, back.status.as_str()),
            (3, 0.2, "coasting")
        );
        assert_eq!(
            [
                back.est_cx_px,
                back.est_cy_px,
                back.est_scale,
                back.x_m,
                back.z_m
            ],
            [127.25, -3.5, 1.0625, 0.125, 10.5]
        );
    }
}

//! Recordings of closed-loop runs that open in Foxglove (`carfollow run --mcap`), the same
//! messages served live (`run --live`), and replay of a recording's camera frames through
//! the tracker (`carfollow track run.mcap`).
//!
//! A recording is an MCAP file written with Foxglove's SDK, zstd-compressed by chunk. Every
//! message is logged on the simulation clock: frame k at k/15 s after the Unix epoch (so
//! Foxglove shows 1970-01-01 and the run's own seconds). Per frame:
//!
//! | topic | schema |
//! |---|---|
//! | `/camera/image` | `foxglove.RawImage`, mono8 (compressed with the chunk) |
//! | `/camera/calibration` | `foxglove.CameraCalibration` |
//! | `/camera/annotations` | `foxglove.ImageAnnotations`: the overlay |
//! | `/tf` | `foxglove.FrameTransforms`: map → world, world → chase, world → lead, chase → camera |
//! | `/scene` | `foxglove.SceneUpdate`: both vehicles, the breadcrumb trail, the lead's path |
//! | `/tracker/state` | [`TrackerState`] |
//! | `/tracker/input` | [`TrackerInput`]: what the tracker was given besides the image |
//! | `/controller` | [`ControllerState`] |
//! | `/truth` | [`GroundTruth`] |
//! | `/events` | `foxglove.Log`: status changes, (re)acquisitions, losses, controller events, failed criteria |
//!
//! and one metadata record, `carfollow` ([`ReplaySetup::metadata`]): the scenario as run
//! (resolved, as TOML), its target model, seed and overrides, the program's version, and the
//! tracker's start. That is everything replay needs besides the frames.

mod convert;
mod messages;
mod replay;
mod writer;

pub use messages::{
    ControllerState, GroundTruth, TrackerInput, TrackerInputDecoded, TrackerState,
    TrackerStateDecoded,
};
pub use replay::{
    replay, ReplayError, ReplayJob, ReplaySummary, SettingChange, Tape, REPLAY_CSV_COLUMNS,
};
pub use writer::{LiveOptions, RecordError, Recorder, RecorderOptions};

use sim_core::ClosedLoop;
use sim_core::Scenario;
use std::collections::BTreeMap;
use tracker::{Camera, Location, TargetModel};

/// The name of the recording's metadata record.
pub const METADATA_NAME: &str = "carfollow";

/// The recording's file name in a run's output folder.
pub const MCAP_FILE: &str = "run.mcap";

/// The topics of a recording.
pub mod topics {
    /// `foxglove.RawImage`, mono8.
    pub const IMAGE: &str = "/camera/image";
    /// `foxglove.CameraCalibration`.
    pub const CALIBRATION: &str = "/camera/calibration";
    /// `foxglove.ImageAnnotations`.
    pub const ANNOTATIONS: &str = "/camera/annotations";
    /// `foxglove.FrameTransforms`.
    pub const TRANSFORMS: &str = "/tf";
    /// `foxglove.SceneUpdate`.
    pub const SCENE: &str = "/scene";
    /// [`super::TrackerState`].
    pub const TRACKER: &str = "/tracker/state";
    /// [`super::TrackerInput`].
    pub const INPUT: &str = "/tracker/input";
    /// [`super::ControllerState`].
    pub const CONTROLLER: &str = "/controller";
    /// [`super::GroundTruth`].
    pub const TRUTH: &str = "/truth";
    /// `foxglove.Log`.
    pub const EVENTS: &str = "/events";
    /// Every topic, in the order they are created.
    pub const ALL: [&str; 10] = [
        IMAGE,
        CALIBRATION,
        ANNOTATIONS,
        TRANSFORMS,
        SCENE,
        TRACKER,
        INPUT,
        CONTROLLER,
        TRUTH,
        EVENTS,
    ];
}

/// A frame's log time, nanoseconds: frame k at k/15 s, rounded to the nanosecond.
pub fn log_time_ns(frame: u64) -> u64 {
    let rate = u128::from(vehicle::CAMERA_HZ);
    ((u128::from(frame) * 2_000_000_000 + rate) / (2 * rate)) as u64
}

/// What a recording carries besides its frames, so that replay needs nothing else: the
/// scenario as run, its target, and where the tracker started.
#[derive(Clone, Debug)]
pub struct ReplaySetup {
    /// The scenario's name.
    pub scenario: String,
    /// Its seed.
    pub seed: u64,
    /// The scenario as run: overrides applied, defaults filled in (TOML).
    pub resolved_toml: String,
    /// The overrides given to the run, in order.
    pub overrides: Vec<String>,
    /// The target model (TOML, the format of `scenarios/targets/`).
    pub target_toml: String,
    /// The teleoperator's placement the tracker started from.
    pub start: Location,
    /// The camera's intrinsics.
    pub camera: Camera,
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// Frames in the run.
    pub frames: u64,
    /// The lead's body, metres: length, height, width (for the scene).
    pub lead_box_m: [f64; 3],
    /// The sensor noise σ (grey levels) the recorded images are without: each frame's
    /// noise, which is a function of the seed and the frame's index
    /// (`camera::shift_noise`), is subtracted when recording and added back on replay,
    /// exactly. 0: the images are as the tracker saw them. The other camera effects
    /// (vignetting, shot noise, the automatic gain) come before that noise and stay in the
    /// recorded images.
    pub noise_removed_sigma: f64,
}

/// A target model as the TOML of `scenarios/targets/` (read back by [`crate::target::parse`]).
pub fn target_toml(model: &TargetModel) -> String {
    #[derive(serde::Serialize)]
    struct File<'a> {
        name: &'a str,
        nominal_range_m: f64,
        corners_m: &'a [[f64; 2]],
        segments: &'a [[usize; 2]],
        paint: &'a str,
    }
    toml::to_string(&File {
        name: model.name(),
        nominal_range_m: model.nominal_range_m(),
        corners_m: model.corners_m(),
        segments: model.segments(),
        paint: model.paint().as_str(),
    })
    .expect("a target model is plain TOML")
}

/// Three numbers as `a,b,c`, each in Rust's shortest form that reads back to the same bits.
fn triple(v: [f64; 3]) -> String {
    format!("{},{},{}", v[0], v[1], v[2])
}

impl ReplaySetup {
    /// The setup of the run of `scenario` by `looped`, before its first step; `Err` when the
    /// resolved scenario cannot be written as TOML.
    pub fn of(scenario: &Scenario, looped: &ClosedLoop) -> Result<ReplaySetup, String> {
        let rig = looped.rig();
        let resolved_toml = toml::to_string(&scenario.resolved)
            .map_err(|e| format!("cannot write the resolved scenario as TOML: {e}"))?;
        Ok(ReplaySetup {
            scenario: scenario.name.clone(),
            seed: scenario.seed,
            resolved_toml,
            overrides: scenario.overrides.clone(),
            target_toml: target_toml(&scenario.target),
            start: looped.tracker_start(),
            camera: scenario.camera,
            width: rig.width,
            height: rig.height,
            frames: looped.frames(),
            lead_box_m: sim_core::lead_body_size_m(),
            noise_removed_sigma: scenario.sensor.noise_sigma_grey,
        })
    }

    /// The metadata record: `scenario`, `seed`, `carfollow_version`, `git_commit` (when
    /// known), `overrides` (JSON list), `resolved_scenario` and `target` (TOML),
    /// `tracker_start` (`cx,cy,scale`), `camera` (`focal_length_mm,pixel_size_mm,
    /// pixel_size_mm,centre_x,centre_y`), `image_size` (`W,H`), `frames` and
    /// `image_noise_removed_sigma` (see [`ReplaySetup::noise_removed_sigma`]). Numbers are in
    /// Rust's shortest round-trip form, so they read back exactly.
    pub fn metadata(&self) -> BTreeMap<String, String> {
        let c = self.camera;
        let mut m = BTreeMap::new();
        m.insert("scenario".into(), self.scenario.clone());
        m.insert("seed".into(), self.seed.to_string());
        m.insert(
            "carfollow_version".into(),
            env!("CARGO_PKG_VERSION").to_string(),
        );
        if let Some(commit) = option_env!("CARFOLLOW_GIT_COMMIT") {
            m.insert("git_commit".into(), commit.to_string());
        }
        m.insert(
            "overrides".into(),
            serde_json::to_string(&self.overrides).expect("strings are JSON"),
        );
        m.insert("resolved_scenario".into(), self.resolved_toml.clone());
        m.insert("target".into(), self.target_toml.clone());
        m.insert(
            "tracker_start".into(),
            triple([self.start.c_x, self.start.c_y, self.start.scale]),
        );
        m.insert(
            "camera".into(),
            format!(
                "{},{},{},{},{}",
                c.focal_length_mm,
                c.pixel_size_mm[0],
                c.pixel_size_mm[1],
                c.image_center_px[0],
                c.image_center_px[1]
            ),
        );
        m.insert(
            "image_size".into(),
            format!("{},{}", self.width, self.height),
        );
        m.insert("frames".into(), self.frames.to_string());
        m.insert("lead_box_m".into(), triple(self.lead_box_m));
        m.insert(
            "image_noise_removed_sigma".into(),
            self.noise_removed_sigma.to_string(),
        );
        m
    }

    /// Reads the metadata record back; `Err` names the key that is missing or unreadable.
    pub fn from_metadata(m: &BTreeMap<String, String>) -> Result<ReplaySetup, String> {
        let get = |key: &str| {
            m.get(key)
                .map(String::as_str)
                .ok_or_else(|| format!("its `{METADATA_NAME}` metadata has no `{key}`"))
        };
        let numbers = |key: &str, n: usize| -> Result<Vec<f64>, String> {
            let text = get(key)?;
            let v: Option<Vec<f64>> = text
                .split(',')
                .map(|p| p.parse::<f64>().ok().filter(|x| x.is_finite()))
                .collect();
            v.filter(|v| v.len() == n).ok_or_else(|| {
                format!("its `{METADATA_NAME}` metadata's `{key}` is not {n} numbers: {text:?}")
            })
        };
        let integer = |key: &str| -> Result<u64, String> {
            let text = get(key)?;
            text.parse::<u64>().map_err(|_| {
                format!("its `{METADATA_NAME}` metadata's `{key}` is not a whole number: {text:?}")
            })
        };
        let overrides: Vec<String> = serde_json::from_str(get("overrides")?)
            .map_err(|e| format!("its `{METADATA_NAME}` metadata's `overrides`: {e}"))?;
        let start = numbers("tracker_start", 3)?;
        let camera = numbers("camera", 5)?;
        let size = numbers("image_size", 2)?;
        let lead = numbers("lead_box_m", 3)?;
        let whole = |v: f64| ((1.0..=4096.0).contains(&v) && v.fract() == 0.0).then_some(v as u32);
        let (Some(width), Some(height)) = (whole(size[0]), whole(size[1])) else {
            return Err(format!(
                "its `{METADATA_NAME}` metadata's `image_size` is not a size in pixels"
            ));
        };
        Ok(ReplaySetup {
            scenario: get("scenario")?.to_string(),
            seed: integer("seed")?,
            resolved_toml: get("resolved_scenario")?.to_string(),
            overrides,
            target_toml: get("target")?.to_string(),
            start: Location::new(start[0], start[1], start[2]),
            camera: Camera {
                focal_length_mm: camera[0],
                pixel_size_mm: [camera[1], camera[2]],
                image_center_px: [camera[3], camera[4]],
            },
            width,
            height,
            frames: integer("frames")?,
            lead_box_m: [lead[0], lead[1], lead[2]],
            noise_removed_sigma: numbers("image_noise_removed_sigma", 1)?[0],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_times_are_the_frames_on_the_simulation_clock() {
        assert_eq!(log_time_ns(0), 0);
        assert_eq!(log_time_ns(1), 66_666_667);
        assert_eq!(log_time_ns(2), 133_333_333);
        assert_eq!(log_time_ns(15), 1_000_000_000);
        assert_eq!(log_time_ns(15 * 1020), 1020 * 1_000_000_000);
    }

    #[test]
    fn the_target_reads_back_as_written() {
        let s = Scenario::builtin(&[]).unwrap();
        let text = target_toml(&s.target);
        let back = sim_core::parse_target(&text, std::path::Path::new("run.mcap")).unwrap();
        assert_eq!(back, s.target);
        // Its paint rule too.
        let stripes = s.target.clone().with_paint(tracker::paint::Paint::Stripes);
        let back = sim_core::parse_target(&target_toml(&stripes), std::path::Path::new("run.mcap"))
            .unwrap();
        assert_eq!(back.paint(), tracker::paint::Paint::Stripes);
    }

    #[test]
    fn the_resolved_scenario_reads_back_as_run() {
        let s = Scenario::builtin(&["tracker.lambda=0.7".into()]).unwrap();
        let text = toml::to_string(&s.resolved).unwrap();
        let target = target_toml(&s.target);
        let back = Scenario::parse(&text, std::path::Path::new("run.mcap"), &[], |_| {
            sim_core::parse_target(&target, std::path::Path::new("run.mcap"))
        })
        .unwrap();
        assert_eq!(back.tracker.lambda, 0.7);
        assert_eq!(format!("{:?}", back.tracker), format!("{:?}", s.tracker));
        assert_eq!(format!("{:?}", back.camera), format!("{:?}", s.camera));
        assert_eq!(back.init_offset, s.init_offset);
    }
}

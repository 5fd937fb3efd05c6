//! What the renderer takes and gives per frame.

use crate::scene::Braking;
use image::GrayImage;
use nalgebra::Isometry3;
use tracker::PixelRect;

/// The inputs of one frame: the clock, the two vehicles' poses (from physics) and the
/// actors'.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameInput {
    /// Frame number; selects this frame's sensor noise, so frame k's noise does not depend
    /// on which frames were rendered before.
    pub frame_index: u64,
    /// Simulation time, seconds (moves oncoming traffic).
    pub time_s: f64,
    /// The chase vehicle's pose: vehicle frame (x forward, y up, z right; origin on the
    /// ground below its centre when level) in the world.
    pub world_from_chase: Isometry3<f64>,
    /// The lead vehicle's pose, same convention.
    pub world_from_lead: Isometry3<f64>,
    /// Each actor's pose (`SceneDescription::actors`, one each, in order): its body's
    /// centre on the ground, x forward, y up, z right (the frame its shape is drawn in, as
    /// the cars' are; the caller converts from the physics' frame). A count that is not
    /// the description's is a [`RenderError::Actors`](crate::RenderError::Actors).
    pub world_from_actors: Vec<Isometry3<f64>>,
    /// The camera's pan about the chase's vertical axis through the mount, radians
    /// (positive to the right; 0 for the paper's fixed camera): the pan head's true angle.
    pub camera_pan_rad: f64,
    /// The automatic gain control's gain for this frame, a factor on the sensor's
    /// brightness (1 without it; see [`crate::scene::AutoGain`]).
    pub auto_gain: f64,
    /// Which vehicles brake, so that their brake lamps are lit (read only for vehicles
    /// whose tail lamps are: [`crate::scene::TailLamps`]).
    pub braking: Braking,
    /// With an interlaced camera (`environment.sensor.interlaced`), the world when the
    /// frame's other field was exposed, one field period earlier: the frame's odd rows show
    /// it, its even rows the world above. `None` for a progressive camera.
    pub earlier_field: Option<Field>,
    /// The chase's forward speed, m/s: the rain's streaks are the drops' motion relative to
    /// the camera (read only when rain falls; 0 in [`FrameInput::fixed_camera`]).
    pub chase_speed_mps: f64,
    /// The lead's forward speed, m/s: its tyres' spray (read only with rain's spray,
    /// [`crate::scene::Rain::spray`]; 0 in [`FrameInput::fixed_camera`]).
    pub lead_speed_mps: f64,
    /// Each actor's forward speed, m/s, in the order of [`FrameInput::world_from_actors`]:
    /// their spray (read only with rain's spray; an actor without one is taken at rest).
    pub actor_speeds_mps: Vec<f64>,
}

/// The poses of one field of an interlaced frame (see [`FrameInput::earlier_field`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// Simulation time, seconds.
    pub time_s: f64,
    /// The chase vehicle's pose.
    pub world_from_chase: Isometry3<f64>,
    /// The lead vehicle's pose.
    pub world_from_lead: Isometry3<f64>,
    /// The actors' poses (see [`FrameInput::world_from_actors`]).
    pub world_from_actors: Vec<Isometry3<f64>>,
    /// The camera's pan, radians.
    pub camera_pan_rad: f64,
}

impl FrameInput {
    /// This frame's own (even rows') field.
    pub fn field(&self) -> Field {
        Field {
            time_s: self.time_s,
            world_from_chase: self.world_from_chase,
            world_from_lead: self.world_from_lead,
            world_from_actors: self.world_from_actors.clone(),
            camera_pan_rad: self.camera_pan_rad,
        }
    }

    /// The frame with the actors at `world_from_actors` (see
    /// [`FrameInput::world_from_actors`]).
    pub fn with_actors(mut self, world_from_actors: Vec<Isometry3<f64>>) -> FrameInput {
        self.world_from_actors = world_from_actors;
        self
    }

    /// Frame `frame_index` at `time_s` of a fixed camera (no pan) without automatic gain:
    /// the paper's camera, with no actors ([`FrameInput::with_actors`] adds them).
    pub fn fixed_camera(
        frame_index: u64,
        time_s: f64,
        world_from_chase: Isometry3<f64>,
        world_from_lead: Isometry3<f64>,
    ) -> FrameInput {
        FrameInput {
            frame_index,
            time_s,
            world_from_chase,
            world_from_lead,
            world_from_actors: Vec::new(),
            camera_pan_rad: 0.0,
            auto_gain: 1.0,
            braking: Braking::default(),
            earlier_field: None,
            chase_speed_mps: 0.0,
            lead_speed_mps: 0.0,
            actor_speeds_mps: Vec::new(),
        }
    }
}

/// What the tracker is scored against. Image coordinates have their origin at the top-left
/// corner and pixel centres at integer coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundTruth {
    /// True image x of the target's centre, pixels.
    pub c_x: f64,
    /// True image y of the target's centre, pixels.
    pub c_y: f64,
    /// True scale: `nominal_range_m / z` (paper 2.1.1: 1 at nominal range).
    pub scale: f64,
    /// The target centre in the camera frame (x right, y down, z forward), metres.
    pub target_cam_m: [f64; 3],
    /// Whether every corner of the target projects inside the image (occlusion is not
    /// considered).
    pub in_view: bool,
    /// Whether some of the target, not all, projects inside the image: partly out of view.
    /// False when [`GroundTruth::in_view`] is, and when none of it is in the image.
    pub partly_in_view: bool,
}

impl GroundTruth {
    /// The truth of a target that is not there (a scene without a lead): nowhere, and none
    /// of it in view.
    pub const ABSENT: GroundTruth = GroundTruth {
        c_x: f64::NAN,
        c_y: f64::NAN,
        scale: f64::NAN,
        target_cam_m: [f64::NAN; 3],
        in_view: false,
        partly_in_view: false,
    };
}

/// One rendered frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// The 8-bit grey image, `width × height` of the rig.
    pub image: GrayImage,
    /// The pixels of `image` that are the camera's (the whole image unless only part of the
    /// frame was rendered: see [`crate::camera::Renderer::render_part`]); the rest is
    /// unspecified (the sky's grey, or with MSAA what the multisampled target last held).
    pub exact: PixelRect,
    /// The target's true position.
    pub truth: GroundTruth,
}

//! The traffic of a scenario file as written: the other vehicles (`[[actors]]`), where they
//! start and how they are driven, and the lanes the lead drives in. [`super::Scenario::load`]
//! validates them (`validate/actors.rs`).

use serde::{Deserialize, Serialize};
use vehicle::EventScript;

/// `[[actors]]`: another vehicle on the road, driven by its own scripted driver along its
/// lane (pure pursuit on the lane's centre, as the lead is driven), with events that
/// change its speed or its lane. It is a physics vehicle like the lead: it collides with
/// the chase and the lead, and the camera sees it, shadow and all.
///
/// ```toml
/// [[actors]]
/// name = "cutter"
/// kind = "sedan"
/// lane = 2
/// start = { gap_m = 4.0, ahead_of = "chase" }
/// speed_profile = [[0.0, 11.0]]
///
/// [[actors.events]]
/// name = "cut-in"
/// trigger = { time_s = 6.0 }
/// action = { lane = 1, duration_s = 2.5, shape = "sinusoidal" }
/// ```
#[derive(Clone, Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ActorFile {
    /// Its name, as triggers and reports name it: letters, digits, `-` or `_`, unique, and
    /// neither `chase` nor `lead`.
    pub name: String,
    /// What it is: `"sedan"`, `"hatchback"`, `"van"` or `"truck"` (the shapes the renderer
    /// draws, each with its physics and the target model of its back,
    /// `scenarios/targets/<kind>-back.toml`).
    #[schemars(extend("enum" = ["sedan", "hatchback", "van", "truck"]))]
    pub kind: String,
    /// Its lane at the start (default 1): 1 is the lane next to the centre line, as
    /// OpenDRIVE's lane −1, up to `route.lanes` by the verge.
    #[serde(default = "first_lane")]
    #[schemars(extend("minimum" = 1, "maximum" = 4))]
    pub lane: u32,
    /// Its offset from its lane's centre, metres, positive to the left (default 0), as
    /// `[lead] offset_m`; or, farther left, onto a lane of the oncoming side, within half
    /// that lane's width of its centre: an actor there drives with the road, as a car
    /// overtaking on a two-lane road does (OpenSCENARIO's ALKS tests place the car that
    /// cuts in so).
    #[serde(default, skip_serializing_if = "super::file::is_zero")]
    #[schemars(extend("minimum" = -3.0, "maximum" = 40.0))]
    pub offset_m: f64,
    /// Where it starts: `{ station_m = S }` (its rear axle, metres along the route), or
    /// `{ gap_m = G, ahead_of = "chase" }` / `{ gap_m = G, behind = "lead" }` (bumper to
    /// bumper, along the road, whatever the lanes), or the same with `time_gap_s = T` (the
    /// gap the vehicle behind covers in T seconds at its initial speed). The vehicle named
    /// is `chase`, `lead` or an actor listed before this one.
    pub start: StartFile,
    /// Speed at t = 0, m/s (default: the profile's first speed): 0–40.
    #[schemars(extend("minimum" = 0.0, "maximum" = 40.0))]
    pub initial_speed_mps: Option<f64>,
    /// What the profile's keys are: `"time"` (seconds) or `"distance"` (metres driven).
    #[serde(default = "time_basis")]
    #[schemars(extend("enum" = ["time", "distance"]))]
    pub speed_basis: String,
    /// `[[key, speed_mps], ...]`, as `[lead] speed_profile` is written; a standing vehicle
    /// is `[[0.0, 0.0]]`.
    #[serde(deserialize_with = "super::file::exact::rows")]
    pub speed_profile: Vec<[f64; 2]>,
    /// Its paint's albedo (default: the kind's): 0.02–0.95.
    #[schemars(extend("minimum" = 0.02, "maximum" = 0.95))]
    pub albedo: Option<f64>,
    /// What happens to it, and when (`[[actors.events]]`: see `[[lead.events]]`).
    #[serde(default, skip_serializing_if = "EventScript::is_empty")]
    pub events: EventScript,
    /// Its lamps, as `[lead.lamps]`: `lamps = { tail = true }` (default: lit at night).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lamps: Option<super::file::LampsFile>,
}

/// An actor's start: by station, or by a gap or a time gap to another vehicle.
#[derive(Clone, Debug, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StartFile {
    /// Its rear axle's station, metres along the route: on the route.
    #[schemars(extend("minimum" = 0.0))]
    pub station_m: Option<f64>,
    /// The gap, bumper to bumper along the road, to the vehicle named by `ahead_of` or
    /// `behind`, metres: 0–1000.
    #[schemars(extend("minimum" = 0.0, "maximum" = 1000.0))]
    pub gap_m: Option<f64>,
    /// The time gap to it, seconds: the gap that the vehicle behind covers in this time at
    /// its initial speed, 0–60.
    #[schemars(extend("minimum" = 0.0, "maximum" = 60.0))]
    pub time_gap_s: Option<f64>,
    /// Start this far ahead of the vehicle named.
    pub ahead_of: Option<String>,
    /// Start this far behind the vehicle named.
    pub behind: Option<String>,
}

pub(crate) fn first_lane() -> u32 {
    1
}

fn time_basis() -> String {
    "time".into()
}

/// Whether a lane is the first (serialised only when it is not, so that a scenario
/// without lanes resolves as before).
pub(crate) fn is_first_lane(lane: &u32) -> bool {
    *lane == 1
}

/// A validated actor: what the plan places and the loop drives.
#[derive(Clone, Debug)]
pub struct ActorSpec {
    /// Its name.
    pub name: String,
    /// What it is.
    pub kind: sim_render::VehicleKind,
    /// Its lane at the start.
    pub lane: u32,
    /// Its offset from its lane's centre at the start, metres, positive to the left.
    pub offset_m: f64,
    /// Its rear axle's station at t = 0, metres along the route.
    pub start_m: f64,
    /// Its speed at t = 0, m/s.
    pub initial_speed_mps: f64,
    /// Its scripted speed.
    pub profile: vehicle::SpeedProfile,
    /// Its paint's albedo.
    pub albedo: f64,
    /// Its events.
    pub events: EventScript,
    /// Whether its tail lamps are lit.
    pub tail_lamps: bool,
}

/// The physics of a vehicle of `kind`.
pub fn kind_params(kind: sim_render::VehicleKind) -> vehicle::VehicleParams {
    use sim_render::VehicleKind;
    match kind {
        VehicleKind::Sedan => vehicle::VehicleParams::sedan(),
        VehicleKind::Hatchback => vehicle::VehicleParams::hatchback(),
        VehicleKind::Van => vehicle::VehicleParams::van(),
        VehicleKind::Truck => vehicle::VehicleParams::truck(),
    }
}

/// The default paint of a vehicle of `kind`: mid greys, distinct from one another and
/// from the road.
pub fn kind_albedo(kind: sim_render::VehicleKind) -> f64 {
    use sim_render::VehicleKind;
    match kind {
        VehicleKind::Sedan => 0.55,
        VehicleKind::Hatchback => 0.35,
        VehicleKind::Van => 0.7,
        VehicleKind::Truck => 0.8,
    }
}

//! The scenario file as written: serde structs with `deny_unknown_fields`, every field
//! optional where a default exists. [`super::Scenario::load`] validates it. Each field's doc
//! gives its unit and its allowed range (every number must also be finite); validation
//! refuses anything outside, naming the field. The vehicle crate's configurations
//! (`chase.controller`, `lead.driver`, `environment.bumps`) carry their own ranges, checked
//! by their constructors during validation.

use serde::{Deserialize, Serialize};
use vehicle::{BumpsConfig, ChaseControllerConfig, LeadDriverConfig};

use super::traffic::{first_lane, is_first_lane};
use super::{ActorFile, Expect};

/// The whole file.
#[derive(Clone, Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ScenarioFile {
    /// Short name: names the output folder.
    pub name: String,
    /// What the scenario is for.
    #[serde(default)]
    pub description: String,
    /// Simulated time, seconds: one camera frame (1/15 s) to 86400.
    #[schemars(extend("minimum" = 0.06666666666666667, "maximum" = 86400.0))]
    pub duration_s: f64,
    /// The one seed; every random stream derives from it.
    #[serde(default)]
    pub seed: u64,
    /// The road.
    pub route: RouteFile,
    /// The lead vehicle: the one the chase starts behind, on whose back the tracker's target
    /// is. Without one, the chase starts at `chase.start_m` in `chase.lane` and cruises
    /// at `chase.controller.cruise_speed_mps` in its lane until its tracker finds a
    /// vehicle in its path (`tracker.start = "search"`), as esmini's and ScenarioRunner's
    /// files often start, the car under test with nothing ahead.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lead: Option<LeadFile>,
    /// The chase vehicle.
    #[serde(default)]
    pub chase: ChaseFile,
    /// The camera.
    #[serde(default)]
    pub camera: CameraFile,
    /// The tracker.
    pub tracker: TrackerFile,
    /// The loop's timing.
    #[serde(default, rename = "loop")]
    pub loop_: LoopFile,
    /// Light, clutter and sensor.
    #[serde(default)]
    pub environment: EnvironmentFile,
    /// Pass/fail criteria.
    #[serde(default)]
    pub expect: Expect,
    /// The other vehicles on the road (`[[actors]]`; none by default).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub actors: Vec<ActorFile>,
}

/// `[route]`.
#[derive(Clone, Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RouteFile {
    /// Lanes each way (default 1): 1–4. Lane 1 is next to the centre line (OpenDRIVE's lane
    /// −1), lane `lanes` by the verge; dashed paint divides lanes that run the same way.
    #[serde(default = "first_lane", skip_serializing_if = "is_first_lane")]
    #[schemars(extend("minimum" = 1, "maximum" = 4))]
    pub lanes: u32,
    /// Width of one lane, metres (default 3.5): 2–6. Every lane's, unless `lane_widths_m`
    /// gives each its own.
    #[serde(default = "default_lane_width")]
    #[schemars(extend("minimum" = 2.0, "maximum" = 6.0))]
    pub lane_width_m: f64,
    /// Each lane's own width, metres, lane 1 (next to the centre line or the median) first:
    /// one per lane of `lanes`, each 2–6 (default: none, every lane `lane_width_m` wide).
    /// Give this or `lane_width_m`, not both. Lane k's centre is `median_m`, the widths of
    /// lanes 1 to k − 1 and half its own to the right of the centre line.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lane_widths_m: Vec<f64>,
    /// The median, metres (default 0): 0–10. The width of the strip between the centre
    /// line and lane 1 on each side (OpenDRIVE's inner border, median or shoulder lanes),
    /// paved, with a solid line along each of its edges instead of the dashed centre line.
    #[serde(default, skip_serializing_if = "is_zero")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 10.0))]
    pub median_m: f64,
    /// Stations (metres along the centreline) where a road crosses: on the route.
    #[serde(default)]
    pub intersections_m: Vec<f64>,
    /// The centreline, in driving order: at least one segment, at most
    /// 50 000 m in all. Give either `segments` or `opendrive`.
    #[serde(default)]
    pub segments: Vec<SegmentFile>,
    /// The road of an OpenDRIVE file instead of `segments`:
    /// `opendrive = { file = "roads/x.xodr", road = "1" }`. Its reference line becomes the
    /// centreline, its station 0 the route's start at the origin heading +x, and its
    /// driving lanes `lanes` and `lane_width_m` (so the scenario gives neither). What the
    /// file holds beyond the subset carfollow drives is refused, naming its line.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub opendrive: Option<OpenDriveFile>,
    /// The road's height along its centreline, OpenDRIVE's elevation profile (default: none,
    /// level at y = 0): records `[s_m, a, b, c, d]`, the first at station 0, stations
    /// increasing and on the route; from `s_m` to the next record's station the height is
    /// `a + b·ds + c·ds² + d·ds³` metres, `ds` metres past `s_m`, and the last record holds
    /// to the route's end. Each record must meet the one before without a step (1 cm), and
    /// the grade stay within ±20 % everywhere. The ground beside the road is as high as the
    /// road abreast. An OpenDRIVE road's `<elevationProfile>` gives it (so the scenario
    /// does not).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub elevation: Vec<[f64; 5]>,
    /// The lane offset, OpenDRIVE's `<laneOffset>` (default: none, the centre line is the
    /// reference line `segments` lay): how far the centre line (where the lanes of the two
    /// directions meet) lies to the left of the reference line, metres, as records
    /// `[s_m, a, b, c, d]` read as `elevation`'s (the first at station 0, stations increasing,
    /// no step of more than 1 cm where they meet). Stations stay the reference line's. At
    /// most 25 m either way, changing by at most 0.2 m a metre, and bending the centre line
    /// no tighter than a radius of 8 m. An OpenDRIVE road's `<laneOffset>` records give it
    /// (so the scenario does not).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lane_offset: Vec<[f64; 5]>,
}

/// `route.opendrive`: a road of an OpenDRIVE file.
#[derive(Clone, Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OpenDriveFile {
    /// The `.xodr` file, relative to the scenario file's folder (as `tracker.target` is).
    pub file: String,
    /// The `id` of the road to follow (default: the file's one road, or the first of its
    /// chain of roads, each linked to the next end to start). The file must hold that road
    /// and the roads it leads into alone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub road: Option<String>,
}

fn default_lane_width() -> f64 {
    3.5
}

pub(crate) fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// One piece of the route: `{ straight_m = L }`, `{ arc_radius_m = R, arc_angle_deg = A }`
/// (A positive turns left), a clothoid `{ spiral_m = L, curvature_start = K0,
/// curvature_end = K1 }`, OpenDRIVE's cubic `{ poly3_m = L, poly3 = [a, b, c, d] }` or its
/// parametric cubic `{ param_poly3_m = L, u = [aU, bU, cU, dU], v = [aV, bV, cV, dV],
/// p_range = "arc_length" }`. Each piece starts where the one before ends, along its end's
/// heading; the cubics' u runs along that heading and v to its left. Every curve must be
/// one the vehicles can drive: curvature at most 1/8 per metre everywhere.
#[derive(Clone, Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SegmentFile {
    /// Length of a straight, metres: (0, 50 000].
    #[schemars(extend("exclusiveMinimum" = 0.0, "maximum" = 50000.0))]
    pub straight_m: Option<f64>,
    /// Radius of an arc, metres: 8–10 000.
    #[schemars(extend("minimum" = 8.0, "maximum" = 10000.0))]
    pub arc_radius_m: Option<f64>,
    /// Turn of an arc, degrees (positive left): non-zero, at most 360 either way.
    #[schemars(extend("minimum" = -360.0, "maximum" = 360.0))]
    pub arc_angle_deg: Option<f64>,
    /// Length of a clothoid (Euler spiral), metres: (0, 50 000].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0.0, "maximum" = 50000.0))]
    pub spiral_m: Option<f64>,
    /// A clothoid's curvature at its start, 1/metres (positive turns left): −0.125–0.125.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = -0.125, "maximum" = 0.125))]
    pub curvature_start: Option<f64>,
    /// A clothoid's curvature at its end, 1/metres (positive turns left): −0.125–0.125.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = -0.125, "maximum" = 0.125))]
    pub curvature_end: Option<f64>,
    /// Arc length of a cubic `v(u)` (OpenDRIVE's `poly3`), metres: (0, 50 000].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0.0, "maximum" = 50000.0))]
    pub poly3_m: Option<f64>,
    /// The cubic's `[a, b, c, d]`: `v = a + b·u + c·u² + d·u³`, metres to the left.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poly3: Option<[f64; 4]>,
    /// Station length of a parametric cubic (OpenDRIVE's `paramPoly3`), metres:
    /// (0, 50 000].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0.0, "maximum" = 50000.0))]
    pub param_poly3_m: Option<f64>,
    /// The parametric cubic's `[aU, bU, cU, dU]` (forward).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub u: Option<[f64; 4]>,
    /// The parametric cubic's `[aV, bV, cV, dV]` (to the left).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v: Option<[f64; 4]>,
    /// What the parametric cubic's `p` runs over: `arc_length` (0 to its length, the
    /// default) or `normalized` (0 to 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub p_range: Option<sim_render::PRange>,
}

/// `[lead]`.
#[derive(Clone, Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LeadFile {
    /// Where the lead's rear axle starts, metres along the route (default 30): on the
    /// route, and far enough along that the chase vehicle, `initial_gap_m` behind, starts
    /// on it too.
    #[serde(default = "default_lead_start")]
    #[schemars(extend("minimum" = 0.0))]
    pub start_m: f64,
    /// Speed at t = 0, m/s (default: the profile's first speed): 0–40.
    #[schemars(extend("minimum" = 0.0, "maximum" = 40.0))]
    pub initial_speed_mps: Option<f64>,
    /// What the profile's keys are: `"time"` (seconds) or `"distance"` (metres).
    #[serde(default = "default_basis")]
    #[schemars(extend("enum" = ["time", "distance"]))]
    pub speed_basis: String,
    /// `[[key, speed_mps], ...]`, keys increasing; linear between, held beyond. Keys within
    /// ±1e7 (s or m), speeds 0–40 m/s.
    #[serde(deserialize_with = "exact::rows")]
    pub speed_profile: Vec<[f64; 2]>,
    /// The driver's tuning (weaving, lateral acceleration in turns, ...).
    #[serde(default)]
    pub driver: LeadDriverConfig,
    /// The lead's lane at the start (default 1; see `route.lanes`): the chase starts
    /// behind it in the same lane.
    #[serde(default = "first_lane", skip_serializing_if = "is_first_lane")]
    #[schemars(extend("minimum" = 1, "maximum" = 4))]
    pub lane: u32,
    /// Its offset from its lane's centre, metres, positive to the left (default 0): where
    /// it starts and what it keeps until a lateral event moves it, within half its lane's
    /// width. Euro NCAP's car-to-car rear tests offset the target for their overlaps.
    #[serde(default, skip_serializing_if = "is_zero")]
    #[schemars(extend("minimum" = -3.0, "maximum" = 3.0))]
    pub offset_m: f64,
    /// What happens to the lead, and when (`[[lead.events]]`, as `[[actors.events]]`): a
    /// lead that changes lane, brakes or stops.
    #[serde(default, skip_serializing_if = "vehicle::EventScript::is_empty")]
    pub events: vehicle::EventScript,
    /// The lead's own lamps: its tail and brake lamps (default: lit at night).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lamps: Option<LampsFile>,
}

/// A vehicle's own lamps, which glow whatever lights the scene: the lead's
/// (`[lead.lamps]`) or an actor's (`lamps` in `[[actors]]`).
#[derive(Clone, Debug, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LampsFile {
    /// Its tail lamps lit: two red lamps at its back's corners (5 cd each, SAE J585), the
    /// brake lamps in them (80 cd more, SAE J586) while its brake is applied (default: lit
    /// with the sun at or below the horizon, `environment.sun.elevation_deg` ≤ 0, and off
    /// by day). The lead's are drawn below its target board.
    pub tail: Option<bool>,
}

/// Whether a vehicle's tail lamps are lit, from its `lamps` (default: at night, with the
/// sun at `sun_elevation_deg` at or below the horizon).
pub(crate) fn tail_lamps_lit(lamps: Option<&LampsFile>, sun_elevation_deg: f64) -> bool {
    lamps
        .and_then(|l| l.tail)
        .unwrap_or(sun_elevation_deg <= 0.0)
}

fn default_lead_start() -> f64 {
    30.0
}
fn default_basis() -> String {
    "time".into()
}

/// `[chase]`.
#[derive(Clone, Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ChaseFile {
    /// Where the chase's rear axle starts, metres along the route: only in a scenario
    /// without `[lead]` (with one, the chase starts `initial_gap_m` behind it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0))]
    pub start_m: Option<f64>,
    /// The chase's lane (default 1; see `route.lanes`): only in a scenario without `[lead]`
    /// (with one, the chase starts in the lead's lane).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 1, "maximum" = 4))]
    pub lane: Option<u32>,
    /// Camera-to-target distance at t = 0, metres (default 10): 3–60 with the tracker
    /// placed on the target (`tracker.start = "operator"`), which must then be in the
    /// camera's view; up to 250 (the renderer's far plane: nothing further is drawn) with
    /// `tracker.start = "search"` and a `controller.cruise_speed_mps`, which a start over
    /// 60 m needs: the chase cruises until its tracker finds the lead, then follows it.
    #[schemars(extend("minimum" = 3.0, "maximum" = 250.0))]
    pub initial_gap_m: Option<f64>,
    /// Whether the chase starts at its cruise speed, `controller.cruise_speed_mps` (which
    /// this needs), instead of the lead's initial speed (default false, as every
    /// car-following run starts). A chase that starts at its cruise speed behind a slower
    /// or standing lead closes on it from the first step, at the speed it holds until it
    /// finds a target, as Euro NCAP's car-to-car rear tests start the car under test at its
    /// test speed; a sweep over the cruise speed then moves both. (Written only when on.)
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub start_at_cruise_speed: bool,
    /// The paper's manual throttle ("throttle was controlled manually"): with a profile, the
    /// chase's speed follows this scripted driver, as `[lead] speed_profile` is written
    /// (`[[key, speed_mps], ...]`), and only steering is closed-loop; the emergency brake
    /// still guards the gap. Without one, the gap keeper sets the speed.
    #[serde(default, deserialize_with = "exact::optional_rows")]
    pub speed_profile: Option<Vec<[f64; 2]>>,
    /// What `speed_profile`'s keys are: `"time"` (seconds, the default) or `"distance"`
    /// (metres driven).
    #[serde(default = "default_basis")]
    #[schemars(extend("enum" = ["time", "distance"]))]
    pub speed_basis: String,
    /// The controller (gap keeper or manual speed, look-ahead, loss handling). Its camera
    /// mount comes from `[camera.mount]`.
    #[serde(default)]
    pub controller: ChaseControllerConfig,
    /// The chase's headlamps (`[chase.headlamps]`; off by default, and then not written, so
    /// a scenario without them reads and writes as before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub headlamps: Option<HeadlampsFile>,
}

/// `[chase.headlamps]`: two spot lights at the chase's front corners, lighting the scene
/// with an inverse-square fall-off (see the book's "Night").
#[derive(Clone, Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HeadlampsFile {
    /// The beam: `"off"` (the default), `"low"` (dipped: aimed 1° down, cut off above the
    /// lamps' horizontal) or `"high"` (main beam: level, brighter, wider, no cut-off).
    #[schemars(extend("enum" = ["off", "low", "high"]))]
    pub beam: String,
}

/// A file without `[chase]` has the defaults of an empty `[chase]`: the same as serde's
/// field defaults.
impl Default for ChaseFile {
    fn default() -> Self {
        ChaseFile {
            start_m: None,
            lane: None,
            initial_gap_m: None,
            start_at_cruise_speed: false,
            speed_profile: None,
            speed_basis: default_basis(),
            controller: ChaseControllerConfig::default(),
            headlamps: None,
        }
    }
}

/// `[camera]`.
#[derive(Clone, Debug, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CameraFile {
    /// Focal length, millimetres (default 8): 1–200.
    #[schemars(extend("minimum" = 1.0, "maximum" = 200.0))]
    pub focal_length_mm: Option<f64>,
    /// Pixel size, millimetres `[w, h]` (default 0.025 × 0.025): each in (0, 1).
    #[serde(default, deserialize_with = "exact::optional")]
    pub pixel_size_mm: Option<[f64; 2]>,
    /// Principal point, pixels (default the frame's centre): in the 256 × 242 frame.
    #[serde(default, deserialize_with = "exact::optional")]
    pub image_center_px: Option<[f64; 2]>,
    /// Where the camera sits on the chase vehicle (`right_m` must be 0: the renderer
    /// mounts it on the centreline).
    #[serde(default)]
    pub mount: vehicle::CameraMount,
    /// The pan head (default: none, the paper's fixed camera): `enabled = true` turns the
    /// camera to keep the lead centred, within `max_rate_deg_s`, `max_accel_deg_s2` and
    /// `limit_deg`; its encoder reads the angle `encoder_latency_ms` late with
    /// `encoder_noise_deg` of noise (see `vehicle::PanHeadConfig` for the defaults and
    /// ranges).
    #[serde(default)]
    pub pan: vehicle::PanHeadConfig,
}

/// `[tracker]`.
#[derive(Clone, Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TrackerFile {
    /// Target model file, relative to the scenario file (its format: `scenarios/targets/`
    /// and `carfollow target`).
    pub target: String,
    /// λ of eq. 18, the features' exponential decay: in (0, 1), as eq. 18 requires.
    #[schemars(extend("exclusiveMinimum" = 0.0, "exclusiveMaximum" = 1.0))]
    pub lambda: Option<f64>,
    /// δ of eq. 7, degrees.
    #[schemars(extend("exclusiveMinimum" = 0.0, "exclusiveMaximum" = 45.0))]
    pub delta_deg: Option<f64>,
    /// ζ of 2.4, pixels.
    #[schemars(extend("exclusiveMinimum" = 0.0))]
    pub zeta_px: Option<f64>,
    /// Edge threshold on eq. 4's |∇f|, grey levels per pixel.
    #[schemars(extend("minimum" = 0.0))]
    pub edge_threshold: Option<f64>,
    /// Coasting time before `lost`, seconds.
    pub lost_after_s: Option<f64>,
    /// Sub-pixel edges (an improvement over the paper).
    pub subpixel_edges: Option<bool>,
    /// `"paper"` (the default) or `"robust"`, the mode that goes beyond the paper.
    #[schemars(extend("enum" = ["paper", "robust", null]))]
    pub mode: Option<String>,
    /// The teleoperator's placement error at start: `[dx_px, dy_px, dscale]` added to the
    /// true location (default none): |dx|, |dy| at most 128,
    /// dscale in (-0.5, 1].
    #[serde(default, deserialize_with = "exact::optional")]
    pub init_offset: Option<[f64; 3]>,
    /// Where the tracker starts: `"operator"` (the default), placed on the target at t = 0
    /// as the paper's teleoperator did (2.2), with `init_offset`'s error; or `"search"`,
    /// nothing placed: it searches the whole image (robust mode's search, which the
    /// paper's mode takes its start from), in traffic for a vehicle in the chase's lane;
    /// a chase starting over 60 m behind (`chase.initial_gap_m`) needs it. Until the first
    /// acquisition, frames without the target are `not_acquired`, not a lost track.
    /// (Written only when given.)
    #[schemars(extend("enum" = ["operator", "search", null]))]
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<String>,
}

/// `[loop]`.
#[derive(Clone, Debug, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LoopFile {
    /// Camera and tracker rate, Hz: 15 only, the paper's (the physics clock is built on it).
    #[schemars(extend("enum" = [15.0, null]))]
    pub rate_hz: Option<f64>,
    /// Tracker-to-controller latency, ms (default 128): 0–2000.
    #[schemars(extend("minimum" = 0.0, "maximum" = 2000.0))]
    pub latency_ms: Option<f64>,
    /// Latency jitter, ± ms (default 0): 0 to `latency_ms`.
    #[schemars(extend("minimum" = 0.0))]
    pub jitter_ms: Option<f64>,
    /// Probability that an estimate is dropped (default 0): [0, 1).
    #[schemars(extend("minimum" = 0.0, "exclusiveMaximum" = 1.0))]
    pub drop_probability: Option<f64>,
}

/// `[environment]`.
#[derive(Clone, Debug, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentFile {
    /// The sun.
    #[serde(default)]
    pub sun: SunFile,
    /// Clutter along the route, per km.
    #[serde(default)]
    pub clutter: ClutterFile,
    /// The camera's sensor.
    #[serde(default)]
    pub sensor: SensorFile,
    /// Gentle bumps under the road, so the chassis pitches and rolls.
    pub bumps: Option<BumpsConfig>,
    /// Controlled distractors moving with the lead (`[[environment.distractors]]`).
    #[serde(default)]
    pub distractors: Vec<DistractorFile>,
    /// Overpasses across the route (`[[environment.overpasses]]`).
    #[serde(default)]
    pub overpasses: Vec<OverpassFile>,
    /// The road's surface.
    #[serde(default)]
    pub road: RoadFile,
    /// Procedural textures on the ground (`[environment.textures]`).
    #[serde(default)]
    pub textures: TexturesFile,
    /// Fog (`[environment.fog]`; none by default, and then not written, so a scenario
    /// without it reads and writes as before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fog: Option<FogFile>,
    /// Rain (`[environment.rain]`; none by default, and then not written, so a scenario
    /// without it reads and writes as before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rain: Option<RainFile>,
}

/// `[environment.rain]`: rain falling on the scene, and what it does to the camera's view.
/// The drops' sizes follow Marshall–Palmer (`N(D) = N0 e^(−ΛD)`, N0 = 8000 m⁻³ mm⁻¹,
/// `Λ = 4.1 R^−0.21` per mm) and fall at Gunn–Kinzer's speeds (Atlas's fit,
/// `9.65 − 10.3 e^(−0.6 D)` m/s). The air: their extinction, `β = π N0 / (2Λ³)`
/// (`0.18 R^0.63` per km), is added to any fog's, by Koschmieder's law, and the sky is the
/// airlight (an overcast). Streaks: each drop imaged at least a quarter of a pixel wide is
/// a line, its motion relative to the camera over the exposure, lit by the sky and the
/// scene, a new draw each frame. The wet road: the asphalt's and the paint's albedo times
/// `1 − 0.4 w` (Lekner & Dorf; w = min(1, R / 2.5)), and a water film over
/// `w R / (R + 7.6)` of it mirroring the sky by water's Fresnel reflectance. Applied to the
/// scene's light before the sensor, whose gain, noise and automatic gain act on it.
#[derive(Clone, Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RainFile {
    /// The rain rate R, mm of water an hour: 0–200 (0 is dry, as without the table). The
    /// usual bands: light under 2.5 mm/h, moderate 2.5–7.6, heavy over 7.6.
    #[schemars(extend("minimum" = 0.0, "maximum" = 200.0))]
    pub rate_mm_h: f64,
    /// Spray from the tyres (default false: none, the frames as before spray existed).
    /// Behind the lead and every actor, a plume of fine droplets that dims and veils what
    /// lies behind it (the board on the lead's back), lit by the scene's light (the
    /// airlight, the headlamps', the street lights'), hidden behind nearer things, and puffy,
    /// a new draw each frame from its own random stream. Negligible below 55 km/h, it grows
    /// with the square of the excess speed and with the film's depth
    /// (`0.5 mm · (R / 10 mm/h)^0.59`): the trail's extinction cross-section per metre is
    /// `σ0 = 3 ε h w n / (2 r)`, ε = 0.1 ((v − 55 km/h) / 45 km/h)² the share of the water
    /// swept that is atomised, h the film, w = 0.25 m the tyres' width, n = 4 tyres, r =
    /// 0.15 mm the droplets' radius; it spreads behind the vehicle and settles out over
    /// `v · 0.95 s` metres (the guide's camera-world page has the model). Needs rain
    /// (`rate_mm_h` over 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spray: Option<bool>,
    /// Lamps mirrored on the wet road (default false: the road mirrors the sky alone). The
    /// water film mirrors the lit lamps (the lead's and the actors' tail and brake lamps,
    /// the street lights, the chase's headlamps, whose mirror images lie ahead, away from
    /// the camera) as it mirrors the sky, on the same share of the road and by the same
    /// Fresnel law, a rough mirror (rms slope 0.15, after Cox & Munk's wind-roughened
    /// water) that draws each lamp out into a streak along the line from its foot towards
    /// the camera. Needs rain (`rate_mm_h` over 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lamp_reflections: Option<bool>,
}

/// `[environment.fog]`: fog between the camera and everything it sees, by Koschmieder's
/// law. A surface `d` metres from the camera keeps `exp(−β d)` of its light, `β = 3.912 / V`
/// per metre, and takes the rest from the fog's own luminance, `ambient + strength / 4` of
/// `[environment.sun]` (a white medium scattering the sunlight equally in every direction,
/// bathed in the ambient light); the sky is the fog's luminance alone. Applied before the
/// sensor, whose gain, noise and automatic gain act on it as on any light.
#[derive(Clone, Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FogFile {
    /// The meteorological optical range V, metres: 1–100000, the distance at which a black
    /// object's contrast against the fog falls to 2 % (dense fog under 50 m, fog under
    /// 1000 m, haze beyond).
    #[schemars(extend("minimum" = 1.0, "maximum" = 100000.0))]
    pub visual_range_m: f64,
}

/// `[environment.road]`.
#[derive(Clone, Debug, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RoadFile {
    /// What the road is paved with: `"asphalt"` (the default) or `"gravel"`. It chooses the
    /// road's texture; the road's grey is the same.
    #[schemars(extend("enum" = ["asphalt", "gravel", null]))]
    pub surface: Option<String>,
}

/// `[environment.textures]`: seeded, mipmapped detail on the road and the grass (asphalt
/// grain, patches and sealed cracks; grass blades; gravel stones), multiplying each
/// surface's albedo by a factor of mean 1.
#[derive(Clone, Debug, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TexturesFile {
    /// On or off (default on, [`sim_render::Textures::default`]).
    pub enabled: Option<bool>,
    /// Scale of the texture's departures from its mean: 0–2 (default 1).
    #[schemars(extend("minimum" = 0.0, "maximum" = 2.0))]
    pub contrast: Option<f64>,
}

/// `[[environment.distractors]]`: a pole or a wire that moves with the lead beside one of
/// the target's features (section 4's "close and parallel" clutter).
#[derive(Clone, Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DistractorFile {
    /// `"pole"` (vertical, beside a vertical feature), `"wire"` (horizontal, beside a
    /// horizontal feature) or `"shadow"` (a shadow's edge, cast by a thin fin standing out
    /// of the board, placed for the sun at the start).
    #[schemars(extend("enum" = ["pole", "wire", "shadow"]))]
    pub kind: String,
    /// The target segment it runs beside (its index in the target file).
    pub feature: usize,
    /// Gap from the feature's line to its near side, pixels at the nominal range (scale 1),
    /// positive away from the target's centre: ±60. Give this or `offset_m`.
    #[schemars(extend("minimum" = -60.0, "maximum" = 60.0))]
    pub offset_px: Option<f64>,
    /// The same gap in metres on the board: ±2. Give this or `offset_px`.
    #[schemars(extend("minimum" = -2.0, "maximum" = 2.0))]
    pub offset_m: Option<f64>,
    /// Its width, metres: 0.005–0.5 (default 0.05 for a pole, 0.02 for a wire).
    #[schemars(extend("minimum" = 0.005, "maximum" = 0.5))]
    pub width_m: Option<f64>,
    /// Its albedo: 0–1 (default 0.1, dark; the board's light paint is 0.85).
    #[schemars(extend("minimum" = 0.0, "maximum" = 1.0))]
    pub albedo: Option<f64>,
}

/// `[[environment.overpasses]]`: a bridge over the route, whose shadow lies across the
/// road as a band.
#[derive(Clone, Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OverpassFile {
    /// Where it crosses the route, metres along it: on the route.
    #[schemars(extend("minimum" = 0.0))]
    pub station_m: f64,
    /// The deck's width along the route, metres: 2–60 (default 10).
    #[schemars(extend("minimum" = 2.0, "maximum" = 60.0))]
    pub deck_m: Option<f64>,
    /// The deck's underside above the road, metres: 4.5–20 (default 5.5).
    #[schemars(extend("minimum" = 4.5, "maximum" = 20.0))]
    pub height_m: Option<f64>,
}

/// `[environment.sun]`.
#[derive(Clone, Debug, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SunFile {
    /// Compass direction the sunlight comes from, degrees: -360–360.
    #[schemars(extend("minimum" = -360.0, "maximum" = 360.0))]
    pub azimuth_deg: Option<f64>,
    /// Height above the horizon, degrees: -18–90. At or below 0 the sun has set: no direct
    /// light and no sun shadow, and the ambient light and the sky's brightness fall through
    /// civil (0 to -6), nautical (-6 to -12) and astronomical (-12 to -18) twilight to
    /// night's (see the book's "Night").
    #[schemars(extend("minimum" = -18.0, "maximum" = 90.0))]
    pub elevation_deg: Option<f64>,
    /// Direct light, 0–2 (1 is full sun).
    #[schemars(extend("minimum" = 0.0, "maximum" = 2.0))]
    pub strength: Option<f64>,
    /// Ambient light, 0–2.
    #[schemars(extend("minimum" = 0.0, "maximum" = 2.0))]
    pub ambient: Option<f64>,
    /// Soft shadows on the target (default false): a fine shadow map around the board and
    /// penumbrae sized by the sun's 0.53° disc; about half the renderer's speed.
    pub soft_shadows: Option<bool>,
}

/// `[environment.clutter]`: every density 0–1000 per km.
#[derive(Clone, Debug, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ClutterFile {
    /// Trees per km.
    #[schemars(extend("minimum" = 0.0, "maximum" = 1000.0))]
    pub trees_per_km: Option<f64>,
    /// Telephone poles per km.
    #[schemars(extend("minimum" = 0.0, "maximum" = 1000.0))]
    pub poles_per_km: Option<f64>,
    /// Houses per km.
    #[schemars(extend("minimum" = 0.0, "maximum" = 1000.0))]
    pub houses_per_km: Option<f64>,
    /// Buildings per km.
    #[schemars(extend("minimum" = 0.0, "maximum" = 1000.0))]
    pub buildings_per_km: Option<f64>,
    /// Parked vehicles per km.
    #[schemars(extend("minimum" = 0.0, "maximum" = 1000.0))]
    pub parked_vehicles_per_km: Option<f64>,
    /// Oncoming vehicles per km.
    #[schemars(extend("minimum" = 0.0, "maximum" = 1000.0))]
    pub oncoming_vehicles_per_km: Option<f64>,
    /// Cracks per km.
    #[schemars(extend("minimum" = 0.0, "maximum" = 1000.0))]
    pub cracks_per_km: Option<f64>,
    /// Patches per km.
    #[schemars(extend("minimum" = 0.0, "maximum" = 1000.0))]
    pub patches_per_km: Option<f64>,
    /// Pot holes per km.
    #[schemars(extend("minimum" = 0.0, "maximum" = 1000.0))]
    pub potholes_per_km: Option<f64>,
    /// Street lights per km (0–100), evenly spaced on the right of the road, none within
    /// 4 m of an intersection: each a steel pole 1 m beyond the road's edge with an arm
    /// reaching 2 m over the road and a lamp head 8 m up. By day they stand and cast
    /// shadows; at night (the sun at or below the horizon) each lights the scene as a
    /// full cut-off road luminaire of about 10 000 lm (2 500 cd inside a cone of 70° about
    /// the downward vertical, none past 75°, falling as the inverse square of the
    /// distance), the 8 nearest the camera in each frame, and its lens glows to a camera
    /// inside the cone. 30 a km (every 33 m) light a road to 5–15 lux (EN 13201's classes
    /// M3–M5). None by default, and then not written, so a scenario without them reads and
    /// writes as before.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 100.0))]
    pub street_lights_per_km: Option<f64>,
}

/// `[environment.sensor]`.
#[derive(Clone, Debug, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SensorFile {
    /// Gain: 0.05–20.
    #[schemars(extend("minimum" = 0.05, "maximum" = 20.0))]
    pub gain: Option<f64>,
    /// Gaussian noise, grey levels: 0–64.
    #[schemars(extend("minimum" = 0.0, "maximum" = 64.0))]
    pub noise_sigma_grey: Option<f64>,
    /// Optional Gaussian blur, pixels: 0–10.
    #[schemars(extend("minimum" = 0.0, "maximum" = 10.0))]
    pub blur_sigma_px: Option<f64>,
    /// Strength of the lens's cos⁴ vignetting: 0 (off, the default)–1.
    #[schemars(extend("minimum" = 0.0, "maximum" = 1.0))]
    pub vignetting: Option<f64>,
    /// Shot noise: the full-well capacity, electrons, at grey 255: 100–10⁷ (absent: off).
    #[schemars(extend("minimum" = 100.0, "maximum" = 10000000.0))]
    pub shot_noise_full_well_e: Option<f64>,
    /// Read noise of the sensor before the gain, electrons rms: 0–1000 (absent: off). It
    /// needs `shot_noise_full_well_e`, and counts the sensor's noise at the frame's gain
    /// (`gain` times the automatic gain): a pixel of grey v has noise variance
    /// 255·G·v/full_well + (255·G·read_noise_e/full_well)² grey levels², so a dark frame
    /// brought up by the gain is noisier, not just darker.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 1000.0))]
    pub read_noise_e: Option<f64>,
    /// Automatic gain control (absent: off).
    pub auto_gain: Option<AutoGainFile>,
    /// An interlaced video camera: each frame's odd rows exposed one field (1/60 s)
    /// before its even rows (default false: progressive).
    pub interlaced: Option<bool>,
}

/// `[environment.sensor.auto_gain]`: every field optional, with
/// [`sim_render::AutoGain::default`]'s values.
#[derive(Clone, Debug, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AutoGainFile {
    /// The mean grey the control aims at: 10–245.
    #[schemars(extend("minimum" = 10.0, "maximum" = 245.0))]
    pub target_grey: Option<f64>,
    /// Its time constant, seconds: 0.1–60.
    #[schemars(extend("minimum" = 0.1, "maximum" = 60.0))]
    pub time_constant_s: Option<f64>,
    /// Its largest gain (the smallest is the reciprocal): 1–64.
    #[schemars(extend("minimum" = 1.0, "maximum" = 64.0))]
    pub max_gain: Option<f64>,
    /// Highlight protection: the largest share of the metering window (the frame's central
    /// half each way) it lets clip to white, 0–0.5; it never raises the gain beyond the one
    /// that brings the brightest pixels past that share to grey 250, and lowers it while
    /// more than that share is white, whatever the mean (absent: off, the mean alone
    /// decides). A dark frame with a bright target in it, such as a car's back in the
    /// chase's high beams, then keeps the target's pattern instead of clipping it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 0.5))]
    pub max_clipped_share: Option<f64>,
}

/// Fixed-length arrays of numbers read strictly: the toml parser lets `[f64; 2]` take the
/// first two of four numbers from a file (and refuses the same array in a `--set`), so
/// these read a list and insist on its length, with the list's position in the error.
pub(crate) mod exact {
    use serde::de::{Deserializer, Error};
    use serde::Deserialize;

    fn sized<E: Error, const N: usize>(v: Vec<f64>) -> Result<[f64; N], E> {
        let len = v.len();
        <[f64; N]>::try_from(v).map_err(|_| {
            E::invalid_length(len, &format!("an array of exactly {N} numbers").as_str())
        })
    }

    /// `Option<[f64; N]>`: absent, or exactly `N` numbers (use with `#[serde(default)]`).
    pub fn optional<'de, D: Deserializer<'de>, const N: usize>(
        d: D,
    ) -> Result<Option<[f64; N]>, D::Error> {
        Option::<Vec<f64>>::deserialize(d)?.map(sized).transpose()
    }

    /// `Vec<[f64; N]>`: rows of exactly `N` numbers each.
    pub fn rows<'de, D: Deserializer<'de>, const N: usize>(
        d: D,
    ) -> Result<Vec<[f64; N]>, D::Error> {
        Vec::<Vec<f64>>::deserialize(d)?
            .into_iter()
            .map(sized)
            .collect()
    }

    /// `Option<Vec<[f64; N]>>`: absent, or rows of exactly `N` numbers each.
    pub fn optional_rows<'de, D: Deserializer<'de>, const N: usize>(
        d: D,
    ) -> Result<Option<Vec<[f64; N]>>, D::Error> {
        Option::<Vec<Vec<f64>>>::deserialize(d)?
            .map(|rows| rows.into_iter().map(sized).collect())
            .transpose()
    }
}

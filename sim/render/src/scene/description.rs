//! The scene description: everything the scenario code fills in, in SI units. Building a
//! [`crate::scene::Scene`] from it is deterministic for a given `seed`.

use super::error::SceneError;
use super::night::{Beam, MIN_SUN_ELEVATION_DEG};
use super::object_slot::ObjectSlot;
use super::rain::Rain;
use super::route::{RouteSegment, RouteSpec};
use super::vehicle_kind::VehicleKind;
use tracker::TargetModel;

/// How much clutter to place along the route, per kilometre of route (both sides together
/// unless stated).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Densities {
    /// Trees per km.
    pub trees_per_km: f64,
    /// Telephone poles per km (one side, the right, joined by wires).
    pub poles_per_km: f64,
    /// Houses per km (low, gabled, with windows).
    pub houses_per_km: f64,
    /// Buildings per km (tall boxes with a grid of windows).
    pub buildings_per_km: f64,
    /// Vehicles parked on the right shoulder, per km.
    pub parked_vehicles_per_km: f64,
    /// Oncoming vehicles in the opposite lane, per km (moving at `oncoming_speed_m_s`).
    pub oncoming_vehicles_per_km: f64,
    /// Speed of oncoming traffic, m/s.
    pub oncoming_speed_m_s: f64,
    /// Cracks per km of road.
    pub cracks_per_km: f64,
    /// Repair patches per km of road.
    pub patches_per_km: f64,
    /// Pot holes per km of road.
    pub potholes_per_km: f64,
    /// Street lights per km (one side, the right, evenly spaced; each a pole with an arm
    /// over the road and a lamp head that lights the road at night: `StreetLights`). None
    /// by default, and then not written, so a description without them reads and writes
    /// as before.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub street_lights_per_km: f64,
}

/// Whether a density is zero (then not written).
fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl Default for Densities {
    /// A rural road with the paper's clutter in moderate amounts (section 4 drove on such
    /// roads): enough that several items are in view in most frames.
    fn default() -> Self {
        Densities {
            trees_per_km: 60.0,
            poles_per_km: 22.0,
            houses_per_km: 8.0,
            buildings_per_km: 3.0,
            parked_vehicles_per_km: 6.0,
            oncoming_vehicles_per_km: 6.0,
            oncoming_speed_m_s: 12.0,
            cracks_per_km: 60.0,
            patches_per_km: 12.0,
            potholes_per_km: 10.0,
            street_lights_per_km: 0.0,
        }
    }
}

/// A piece of clutter the scenario places by hand (world x, z on the ground), in addition to
/// what the densities place. Tests use these to put a shadow exactly where they want it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Placement {
    /// A telephone pole (no wires) at world `(x_m, z_m)`.
    Pole {
        /// World x, metres.
        x_m: f64,
        /// World z, metres.
        z_m: f64,
    },
    /// A tree at world `(x_m, z_m)`.
    Tree {
        /// World x, metres.
        x_m: f64,
        /// World z, metres.
        z_m: f64,
    },
    /// A bridge carrying another road over the route: a deck across the road on two
    /// abutments, whose shadow lies across the road as a band with straight edges.
    Overpass {
        /// Where its centre line crosses the route, metres along it.
        station_m: f64,
        /// The deck's width along the route, metres (the shadow band's width, for a sun
        /// overhead).
        deck_m: f64,
        /// Height of the deck's underside above the road, metres.
        height_m: f64,
    },
}

/// What a controlled distractor is.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum DistractorKind {
    /// A vertical bar from the ground up (a pole), beside a vertical feature.
    Pole,
    /// A horizontal bar across the image (a wire), beside a horizontal feature.
    Wire,
    /// The edge of a shadow, parallel to the feature: a thin fin standing out of the board
    /// (vertical beside a vertical feature, a visor beside a horizontal one) casts it, placed
    /// so that with the sun where it is at the start the shadow's far edge falls at the
    /// offset. As the lead turns, the edge moves as a real shadow would.
    Shadow {
        /// Where the fin stands on the board, metres across the feature (x for a vertical
        /// feature, y for a horizontal one, in the target's frame).
        root_m: f64,
        /// How far it stands out of the board towards the chase, metres.
        depth_m: f64,
    },
}

/// A line that moves with the lead, beside one of the target's features, at a set offset:
/// section 4's clutter "of similar orientation ... near a predicted feature location", held
/// where a study wants it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Distractor {
    /// Pole or wire.
    pub kind: DistractorKind,
    /// The target segment it runs beside (vertical for a pole, horizontal for a wire).
    pub feature: usize,
    /// Gap between the feature's line and the distractor's near side, metres on the board,
    /// positive away from the target's centre.
    pub offset_m: f64,
    /// Its width across its length, metres.
    pub width_m: f64,
    /// Its albedo, 0–1 (the board's light paint is `BOARD_ALBEDO`).
    pub albedo: f64,
}

/// Where a distractor beside feature `feature` of `target` with gap `offset_m` has its near
/// side, metres across the feature in the board's frame (x right or y up), and which way is
/// outwards (away from the target's centre): `(near, ±1)`.
pub fn distractor_near_side(
    target: &tracker::TargetModel,
    feature: usize,
    offset_m: f64,
) -> (f64, f64) {
    let line = target.line_m(feature).unwrap_or(0.0);
    let outward = if line < 0.0 { -1.0 } else { 1.0 };
    (line + outward * offset_m, outward)
}

/// The sun: a directional light, and the sky's ambient light.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sun {
    /// Azimuth, degrees, measured in the ground plane from world +x towards world +z.
    /// The direction towards the sun is `(cos el · cos az, sin el, cos el · sin az)`.
    pub azimuth_deg: f64,
    /// Elevation above the horizon, degrees, −18 to 90: at or below 0 the sun has set, and
    /// the scene is lit by the twilight sky alone ([`Sun::lighting`]).
    pub elevation_deg: f64,
    /// Irradiance of direct sunlight on a surface facing the sun, relative units (the
    /// brightness of a white, sunlit, sun-facing surface at gain 1 and nominal exposure).
    pub strength: f64,
    /// Irradiance from the sky on any surface, same units: what shadows are left with.
    pub ambient: f64,
    /// Soft shadows on the target: a fine shadow map around the board (1.6 cm texels) and
    /// penumbrae as wide as the sun's 0.53° disc seen across each occluder's distance.
    /// Off by default: it halves the renderer's speed on llvmpipe. Off, shadow edges
    /// everywhere are as soft as the main map's 11 cm texels.
    pub soft_shadows: bool,
    /// Brightness of the sky itself, same units.
    pub sky: f64,
}

impl Default for Sun {
    /// Afternoon sun behind the chase vehicle and to its left at the route's start, so the
    /// board is lit and shadows fall across the road; ambient a third of the sun, as on a
    /// clear day.
    fn default() -> Self {
        Sun {
            azimuth_deg: 150.0,
            elevation_deg: 40.0,
            strength: 0.75,
            ambient: 0.25,
            sky: 0.9,
            soft_shadows: false,
        }
    }
}

/// Fog: a uniform, white, scattering medium between the camera and what it sees, by
/// Koschmieder's law. A surface at distance `d` from the camera keeps `exp(−β d)` of its
/// radiance ([`Fog::transmittance`]) and takes the rest from the fog's own luminance
/// ([`Fog::luminance`], the airlight), so its contrast against its background falls by
/// `exp(−β d)`; the sky, at infinite distance, is the fog's luminance alone. Applied to the
/// scene's radiance before the sensor, so that its gain, noise and automatic gain act on
/// it as on any light.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Fog {
    /// The meteorological optical range V, metres: the distance at which a black object's
    /// contrast against the fog falls to 2 % (the extinction is `β = 3.912 / V`).
    pub visual_range_m: f64,
}

impl Fog {
    /// Koschmieder's constant, `−ln 0.02`: the extinction times the visual range.
    pub const KOSCHMIEDER: f64 = 3.912;
    /// The least visual range a scene takes, metres.
    pub const MIN_VISUAL_RANGE_M: f64 = 1.0;
    /// The share of the sun's irradiance a white medium scattering equally in every
    /// direction sends towards the camera, relative to what a white, matte surface facing
    /// the sun sends: the isotropic phase function `1 / 4π` against a Lambertian surface's
    /// `1 / π`.
    pub const SUN_SHARE: f64 = 0.25;

    /// The extinction coefficient β, per metre: `3.912 / V`.
    pub fn extinction_per_m(&self) -> f64 {
        Self::KOSCHMIEDER / self.visual_range_m
    }

    /// The share of a surface's radiance that reaches the camera from `distance_m` away,
    /// `exp(−β d)`.
    pub fn transmittance(&self, distance_m: f64) -> f64 {
        (-self.extinction_per_m() * distance_m).exp()
    }

    /// The fog's own luminance (the airlight of an infinite path) under `sun`, in the
    /// sun's units: `ambient + strength / 4`. The droplets scatter without absorbing, the
    /// sunlight equally in every direction (a quarter of what a white, matte surface facing
    /// the sun returns, [`Fog::SUN_SHARE`]), and the ambient light bathes the fog from every
    /// side, as it does any surface. Under the default sun (0.75, 0.25) it is 0.44, a
    /// mid-grey between the road and the board's white paint.
    pub fn luminance(&self, sun: &Sun) -> f64 {
        sun.ambient + Self::SUN_SHARE * sun.strength
    }
}

/// The CCD sensor's response and noise (all applied per frame, seeded).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sensor {
    /// Electronic gain, a factor (1 = nominal).
    pub gain: f64,
    /// Exposure time, milliseconds; brightness scales with `exposure_ms / NOMINAL_EXPOSURE_MS`.
    pub exposure_ms: f64,
    /// Standard deviation of additive Gaussian noise, grey levels.
    pub noise_sigma_grey: f64,
    /// Optional optical blur: Gaussian standard deviation, pixels.
    pub blur_sigma_px: Option<f64>,
    /// Strength of the lens's cos⁴ fall-off of light towards the corners, 0–1: a pixel
    /// seeing at angle θ off the optical axis is scaled by `1 − s·(1 − cos⁴θ)` (0 = off).
    pub vignetting: f64,
    /// Optional signal-dependent shot noise: the full-well capacity, electrons, that a
    /// grey level of 255 collects. A pixel of grey `v` then has Poisson noise of standard
    /// deviation `sqrt(255 · v / full_well_e)` grey levels (Gaussian approximation).
    pub shot_noise_full_well_e: Option<f64>,
    /// Optional read noise of the sensor's output amplifier, electrons (rms), before the
    /// gain; it needs [`Sensor::shot_noise_full_well_e`]. Set, the shot noise too is
    /// counted at the frame's electronic gain `G` (`gain` times the automatic gain), so a
    /// dark frame brought up by the gain is noisier, not just darker: a pixel of grey `v`
    /// collected `N = v · full_well_e / (255 G)` electrons, and has Gaussian noise of
    /// variance `(255 G / full_well_e)² · (N + read_noise_e²)`, that is
    /// `255 G v / full_well_e + (255 G read_noise_e / full_well_e)²` grey levels² (the
    /// EMVA 1288 standard's linear camera model: photon shot noise, Poisson, plus a
    /// signal-independent dark noise, both amplified by the gain). `None`: the shot noise
    /// at gain 1, as [`Sensor::shot_noise_full_well_e`] says, and no read noise but
    /// `noise_sigma_grey` (the frame grabber's, after the gain).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub read_noise_e: Option<f64>,
    /// Optional automatic gain control (off: the fixed `gain`).
    pub auto_gain: Option<AutoGain>,
    /// An interlaced video camera, as the 1990s CCDs were: each frame is two fields, its
    /// even rows exposed at the frame's time and its odd rows one field period
    /// ([`FIELD_PERIOD_STEPS`] physics steps, 1/60 s) earlier, so what moves across the
    /// image shows combed edges. False: a progressive camera, every row at once.
    pub interlaced: bool,
}

/// The field period of an interlaced camera, in physics steps: 2 at 120 Hz, 1/60 s, the
/// field rate of 60 Hz video.
pub const FIELD_PERIOD_STEPS: u64 = 2;

/// The camera's automatic gain control: a gain, on top of `Sensor::gain`, that brings the
/// mean grey of the metering window ([`AutoGain::metering_window`]) towards a target with
/// a first-order time constant.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AutoGain {
    /// The mean grey level the control aims at, 1–254.
    pub target_grey: f64,
    /// Time constant of the control, seconds.
    pub time_constant_s: f64,
    /// The largest gain it sets; the smallest is its reciprocal.
    pub max_gain: f64,
    /// Highlight protection: the largest share of the metering window it lets clip to
    /// white (grey 255), 0–0.5; it never sets a gain that would clip more, whatever the
    /// mean. `None`: off, the mean alone decides, as a camera that meters the whole frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_clipped_share: Option<f64>,
}

impl Default for AutoGain {
    /// Aims at mid-grey over about half a second, within a factor 8 either way.
    fn default() -> Self {
        AutoGain {
            target_grey: 110.0,
            time_constant_s: 0.5,
            max_gain: 8.0,
            max_clipped_share: None,
        }
    }
}

impl AutoGain {
    /// The window the control meters, for frames `width × height`: the central half of
    /// the frame in each direction. The renderer always renders it exactly when the
    /// control is on, so that the gain never depends on pixels a partial frame leaves
    /// unspecified.
    pub fn metering_window(width: usize, height: usize) -> tracker::PixelRect {
        tracker::PixelRect {
            x0: width / 4,
            y0: height / 4,
            x1: width - width / 4,
            y1: height - height / 4,
        }
    }
}

impl Sensor {
    /// Exposure (ms) at which brightness equals the light's relative irradiance times albedo.
    pub const NOMINAL_EXPOSURE_MS: f64 = 4.0;

    /// The combined brightness factor of gain and exposure.
    pub fn brightness(&self) -> f64 {
        self.gain * self.exposure_ms / Self::NOMINAL_EXPOSURE_MS
    }
}

impl Default for Sensor {
    /// Nominal gain and exposure; 2 grey levels of noise, about what a 1990s CCD with an
    /// 8-bit frame grabber showed on a bright day; no blur.
    fn default() -> Self {
        Sensor {
            gain: 1.0,
            exposure_ms: Sensor::NOMINAL_EXPOSURE_MS,
            noise_sigma_grey: 2.0,
            blur_sigma_px: None,
            vignetting: 0.0,
            shot_noise_full_well_e: None,
            read_noise_e: None,
            auto_gain: None,
            interlaced: false,
        }
    }
}

/// The lead vehicle (a box truck) and where its target board hangs.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LeadVehicle {
    /// Body length, width, height (metres).
    pub length_m: f64,
    /// Body width, metres.
    pub width_m: f64,
    /// Top of the body above the ground, metres.
    pub height_m: f64,
    /// Height of the target's centre above the ground, metres.
    pub board_centre_height_m: f64,
    /// Controlled distractors that move with it.
    pub distractors: Vec<Distractor>,
    /// Whether its tail lamps are lit ([`crate::scene::TailLamps`]; false: no lamps drawn,
    /// and not written, so a description without them reads and writes as before).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub tail_lamps: bool,
}

impl Default for LeadVehicle {
    /// A small box truck: 5 m long, 2.5 m wide, 2.7 m tall; the board's centre at 1.6 m so
    /// the shipped target's 2.3 × 1.7 m board (its 1.6 × 1.0 m frame and the board's margin,
    /// `tracker::paint::BOARD_MARGIN_M`) fits on the back door.
    fn default() -> Self {
        LeadVehicle {
            length_m: 5.0,
            width_m: 2.5,
            height_m: 2.7,
            board_centre_height_m: 1.6,
            distractors: Vec::new(),
            tail_lamps: false,
        }
    }
}

/// The chase vehicle as far as the camera sees it: its hood.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ChaseVehicle {
    /// Where the hood's front edge is, metres forward of the vehicle origin.
    pub hood_front_m: f64,
    /// Where the hood's back edge (windscreen) is, metres forward of the vehicle origin.
    pub hood_back_m: f64,
    /// Height of the hood's top above the ground, metres.
    pub hood_height_m: f64,
    /// Width of the hood, metres.
    pub hood_width_m: f64,
}

impl Default for ChaseVehicle {
    /// A HMMWV-like hood: flat, 2 m wide, 1.5 m above the ground, ending 2.3 m ahead of the
    /// vehicle origin; with the default mount it fills the bottom ~20 rows of the frame.
    fn default() -> Self {
        ChaseVehicle {
            hood_front_m: 2.3,
            hood_back_m: 0.3,
            hood_height_m: 1.5,
            hood_width_m: 2.0,
        }
    }
}

/// Where the camera sits on the chase vehicle (vehicle frame: x forward, y up, z right;
/// origin on the ground below the vehicle's centre when level).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CameraMount {
    /// Height of the optical centre above the vehicle origin, metres.
    pub height_m: f64,
    /// Forward offset of the optical centre from the vehicle origin, metres.
    pub forward_offset_m: f64,
    /// Downward pitch of the optical axis, degrees (positive looks down).
    pub pitch_deg: f64,
}

impl Default for CameraMount {
    /// Above the cab of a HMMWV (paper section 3): 2.2 m up, 0.3 m ahead of the centre,
    /// tilted 3° down so the road and the lead's back share the frame.
    fn default() -> Self {
        CameraMount {
            height_m: 2.2,
            forward_offset_m: 0.3,
            pitch_deg: 3.0,
        }
    }
}

/// What the road is paved with: it chooses the road's texture (see [`Textures`]); its
/// albedo is the same either way.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum RoadSurface {
    /// Asphalt: fine aggregate, patches and sealed cracks.
    #[default]
    Asphalt,
    /// Gravel: stones of a few centimetres.
    Gravel,
}

impl RoadSurface {
    /// The name a scenario file gives it: `"asphalt"` or `"gravel"`.
    pub fn as_str(self) -> &'static str {
        match self {
            RoadSurface::Asphalt => "asphalt",
            RoadSurface::Gravel => "gravel",
        }
    }

    /// The surface of that name.
    pub fn parse(name: &str) -> Option<RoadSurface> {
        [RoadSurface::Asphalt, RoadSurface::Gravel]
            .into_iter()
            .find(|s| s.as_str() == name)
    }
}

/// Procedural textures on the ground's surfaces (asphalt, grass, gravel): detail that
/// multiplies each surface's albedo by a factor of mean 1, sampled trilinearly from
/// seeded, mipmapped textures at the surface's world position.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Textures {
    /// Whether the ground is textured (off: the flat albedos and the grass's mottle alone,
    /// the frames the renderer drew before it had textures, bit for bit).
    pub enabled: bool,
    /// Scale of the texture's departures from its mean: 1 as generated, 0 none.
    pub contrast: f64,
}

impl Textures {
    /// The texture contrast when textures are on and none is given.
    pub const DEFAULT_CONTRAST: f64 = 1.0;
}

impl Default for Textures {
    /// On, at the generated contrast (the regression suite passes with them, every
    /// shipped scenario in both tracker modes).
    fn default() -> Self {
        Textures {
            enabled: true,
            contrast: Self::DEFAULT_CONTRAST,
        }
    }
}

/// A vehicle in traffic that the description places and the caller poses each frame
/// (`FrameInput::world_from_actors`): what it looks like.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct ActorBody {
    /// Its kind, and so its shape.
    pub kind: VehicleKind,
    /// Its paint's albedo, 0–1 (a truck's box and cab; its door is a shade darker).
    #[schemars(extend("minimum" = 0.0, "maximum" = 1.0))]
    pub albedo: f64,
    /// Whether its tail lamps are lit ([`crate::scene::TailLamps`]; false: no lamps drawn,
    /// and not written, so a description without them reads and writes as before).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub tail_lamps: bool,
}

/// Everything needed to build the world. Filled by the scenario code.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SceneDescription {
    /// The scenario seed; clutter and noise each use a named stream of it.
    pub seed: u64,
    /// The route.
    pub route: RouteSpec,
    /// Clutter densities.
    pub densities: Densities,
    /// Extra, hand-placed clutter.
    pub placements: Vec<Placement>,
    /// The light.
    pub sun: Sun,
    /// The sensor.
    pub sensor: Sensor,
    /// The target painted on the lead's back.
    pub target: TargetModel,
    /// The lead vehicle.
    pub lead: LeadVehicle,
    /// The chase vehicle's hood.
    pub chase: ChaseVehicle,
    /// The ground, as the physics has it (the flat plane and its bumps): the road and the
    /// verges beside it are drawn on the same height field (see `Terrain`).
    pub ground: vehicle::GroundConfig,
    /// What the road is paved with.
    pub road_surface: RoadSurface,
    /// Textures on the ground's surfaces.
    pub textures: Textures,
    /// Vehicles in traffic, each drawn in its own object slot and posed each frame by the
    /// caller, in this order (at most [`ObjectSlot::MAX_ACTORS`]; none when not given, and
    /// then not written, so a description without them reads and writes as before).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub actors: Vec<ActorBody>,
    /// Fog between the camera and everything it sees (`None`: clear air, the frames drawn
    /// before fog existed, bit for bit; then not written, so a description without it reads
    /// and writes as before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fog: Option<Fog>,
    /// The chase's headlamps' beam (`None`: off, the frames drawn before headlamps existed,
    /// bit for bit; then not written, so a description without them reads and writes as
    /// before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub headlamps: Option<Beam>,
    /// Rain on the scene (`None`, or a rate of 0: dry, the frames drawn before rain existed,
    /// bit for bit; `None` is not written, so a description without it reads and writes as
    /// before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rain: Option<Rain>,
    /// No lead on the road (a scenario without one, whose chase cruises until its tracker
    /// finds a vehicle in its path): `lead` is neither drawn nor lit, its pose in a frame
    /// is not read, and its target has no ground truth (false, the default, is not
    /// written, so a description with a lead reads and writes as before).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub without_lead: bool,
}

impl SceneDescription {
    /// The rain that falls, if any (a rate of 0 is none).
    pub fn raining(&self) -> Option<Rain> {
        self.rain.filter(Rain::falls)
    }

    /// The extinction of the air, per metre, and whether any (fog's and falling rain's,
    /// added: the two are independent scatterers). `None` in clear air: the frames are then
    /// drawn without it, as before either existed.
    pub fn extinction_per_m(&self) -> Option<f64> {
        match (&self.fog, self.raining()) {
            (None, None) => None,
            (Some(fog), None) => Some(fog.extinction_per_m()),
            (None, Some(rain)) => Some(rain.extinction_per_m()),
            (Some(fog), Some(rain)) => Some(fog.extinction_per_m() + rain.extinction_per_m()),
        }
    }

    /// The sky's light under `sun_light` (the sun as it lights the scene): in fog or rain, a
    /// ray that meets nothing crosses an endless path of them, and the sky is their airlight
    /// ([`Fog::luminance`]); in clear air, the sun's sky.
    pub fn sky_light(&self, sun_light: &Sun) -> f64 {
        if self.extinction_per_m().is_some() {
            Rain::airlight(sun_light)
        } else {
            sun_light.sky
        }
    }

    /// Whether any vehicle's tail lamps are lit (the lead's or an actor's).
    pub fn has_tail_lamps(&self) -> bool {
        self.lead.tail_lamps || self.actors.iter().any(|a| a.tail_lamps)
    }

    /// Checks the numbers a scene cannot be built from; each error names the field.
    pub fn validate(&self) -> Result<(), SceneError> {
        let positive = |field: &str, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(SceneError::Invalid {
                    field: field.to_string(),
                    reason: format!("must be positive and finite, got {value}"),
                })
            }
        };
        let non_negative = |field: &str, value: f64| {
            if value.is_finite() && value >= 0.0 {
                Ok(())
            } else {
                Err(SceneError::Invalid {
                    field: field.to_string(),
                    reason: format!("must be zero or positive and finite, got {value}"),
                })
            }
        };
        let finite = |field: &str, values: &[f64]| match values.iter().find(|v| !v.is_finite()) {
            None => Ok(()),
            Some(value) => Err(SceneError::Invalid {
                field: field.to_string(),
                reason: format!("must be finite, got {value}"),
            }),
        };
        if self.route.segments.is_empty() {
            return Err(SceneError::Invalid {
                field: "route.segments".into(),
                reason: "the route needs at least one segment".into(),
            });
        }
        for (i, segment) in self.route.segments.iter().enumerate() {
            match *segment {
                RouteSegment::Straight { length_m } => {
                    positive(&format!("route.segments[{i}].length_m"), length_m)?
                }
                RouteSegment::Arc {
                    radius_m,
                    angle_deg,
                } => {
                    positive(&format!("route.segments[{i}].radius_m"), radius_m)?;
                    positive(&format!("route.segments[{i}].|angle_deg|"), angle_deg.abs())?;
                }
                RouteSegment::Spiral {
                    length_m,
                    curvature_start,
                    curvature_end,
                } => {
                    positive(&format!("route.segments[{i}].length_m"), length_m)?;
                    finite(
                        &format!("route.segments[{i}].curvature"),
                        &[curvature_start, curvature_end],
                    )?;
                }
                RouteSegment::Poly3 { length_m, v } => {
                    positive(&format!("route.segments[{i}].length_m"), length_m)?;
                    finite(&format!("route.segments[{i}].v"), &v)?;
                }
                RouteSegment::ParamPoly3 { length_m, u, v, .. } => {
                    positive(&format!("route.segments[{i}].length_m"), length_m)?;
                    finite(&format!("route.segments[{i}].u"), &u)?;
                    finite(&format!("route.segments[{i}].v"), &v)?;
                }
            }
        }
        positive("route.lane_width_m", self.route.lane_width_m)?;
        if !(1..=RouteSpec::MAX_LANES).contains(&self.route.lanes) {
            return Err(SceneError::Invalid {
                field: "route.lanes".into(),
                reason: format!(
                    "lanes in each direction must be 1–{}, got {}",
                    RouteSpec::MAX_LANES,
                    self.route.lanes
                ),
            });
        }
        let median = self.route.median_m;
        if !(median.is_finite() && median >= 0.0) {
            return Err(SceneError::Invalid {
                field: "route.median_m".into(),
                reason: format!("must be finite and at least 0, got {median}"),
            });
        }
        let widths = &self.route.lane_widths_m;
        if !widths.is_empty() && widths.len() != self.route.lanes as usize {
            return Err(SceneError::Invalid {
                field: "route.lane_widths_m".into(),
                reason: format!(
                    "one width per lane: {} for {} lanes",
                    widths.len(),
                    self.route.lanes
                ),
            });
        }
        for (i, &w) in widths.iter().enumerate() {
            positive(&format!("route.lane_widths_m[{i}]"), w)?;
        }
        self.validate_actors()?;
        let d = &self.densities;
        for (field, value) in [
            ("densities.trees_per_km", d.trees_per_km),
            ("densities.poles_per_km", d.poles_per_km),
            ("densities.houses_per_km", d.houses_per_km),
            ("densities.buildings_per_km", d.buildings_per_km),
            ("densities.parked_vehicles_per_km", d.parked_vehicles_per_km),
            (
                "densities.oncoming_vehicles_per_km",
                d.oncoming_vehicles_per_km,
            ),
            ("densities.oncoming_speed_m_s", d.oncoming_speed_m_s),
            ("densities.cracks_per_km", d.cracks_per_km),
            ("densities.patches_per_km", d.patches_per_km),
            ("densities.potholes_per_km", d.potholes_per_km),
            ("densities.street_lights_per_km", d.street_lights_per_km),
            ("sun.strength", self.sun.strength),
            ("sun.ambient", self.sun.ambient),
            ("sun.sky", self.sun.sky),
            ("sensor.noise_sigma_grey", self.sensor.noise_sigma_grey),
        ] {
            non_negative(field, value)?;
        }
        if let Some(fog) = &self.fog {
            if !(fog.visual_range_m.is_finite() && fog.visual_range_m >= Fog::MIN_VISUAL_RANGE_M) {
                return Err(SceneError::Invalid {
                    field: "fog.visual_range_m".into(),
                    reason: format!(
                        "must be at least {} m and finite, got {}",
                        Fog::MIN_VISUAL_RANGE_M,
                        fog.visual_range_m
                    ),
                });
            }
        }
        if let Some(rain) = &self.rain {
            let r = rain.rate_mm_h;
            if !(r.is_finite() && (0.0..=Rain::MAX_RATE_MM_H).contains(&r)) {
                return Err(SceneError::Invalid {
                    field: "rain.rate_mm_h".into(),
                    reason: format!("must be 0–{} mm/h, got {r}", Rain::MAX_RATE_MM_H),
                });
            }
        }
        if !(self.sun.elevation_deg >= MIN_SUN_ELEVATION_DEG && self.sun.elevation_deg <= 90.0) {
            return Err(SceneError::Invalid {
                field: "sun.elevation_deg".into(),
                reason: format!(
                    "must be in [{MIN_SUN_ELEVATION_DEG}, 90], got {}",
                    self.sun.elevation_deg
                ),
            });
        }
        positive("sun.azimuth_deg (finite)", self.sun.azimuth_deg.abs() + 1.0)?;
        positive("sensor.gain", self.sensor.gain)?;
        positive("sensor.exposure_ms", self.sensor.exposure_ms)?;
        if let Some(sigma) = self.sensor.blur_sigma_px {
            positive("sensor.blur_sigma_px", sigma)?;
        }
        if !(0.0..=1.0).contains(&self.sensor.vignetting) {
            return Err(SceneError::Invalid {
                field: "sensor.vignetting".into(),
                reason: format!("must be 0–1, got {}", self.sensor.vignetting),
            });
        }
        if let Some(e) = self.sensor.shot_noise_full_well_e {
            positive("sensor.shot_noise_full_well_e", e)?;
        }
        if let Some(e) = self.sensor.read_noise_e {
            non_negative("sensor.read_noise_e", e)?;
            if self.sensor.shot_noise_full_well_e.is_none() {
                return Err(SceneError::Invalid {
                    field: "sensor.read_noise_e".into(),
                    reason: "needs sensor.shot_noise_full_well_e".into(),
                });
            }
        }
        if let Some(a) = self.sensor.auto_gain {
            positive("sensor.auto_gain.target_grey", a.target_grey)?;
            positive("sensor.auto_gain.time_constant_s", a.time_constant_s)?;
            positive("sensor.auto_gain.max_gain", a.max_gain)?;
        }
        positive("lead.length_m", self.lead.length_m)?;
        positive("lead.width_m", self.lead.width_m)?;
        positive("lead.height_m", self.lead.height_m)?;
        positive(
            "lead.board_centre_height_m",
            self.lead.board_centre_height_m,
        )?;
        if !(0.0..=2.0).contains(&self.textures.contrast) {
            return Err(SceneError::Invalid {
                field: "textures.contrast".into(),
                reason: format!("must be 0–2, got {}", self.textures.contrast),
            });
        }
        positive("chase.hood_width_m", self.chase.hood_width_m)?;
        positive("chase.hood_height_m", self.chase.hood_height_m)?;
        Ok(())
    }
}

impl SceneDescription {
    /// Checks the actors: no more than the renderer has slots for, each albedo 0–1.
    fn validate_actors(&self) -> Result<(), SceneError> {
        let most = ObjectSlot::MAX_ACTORS as usize;
        if self.actors.len() > most {
            return Err(SceneError::Invalid {
                field: "actors".into(),
                reason: format!(
                    "at most {most} actors (the renderer's slots for them), got {}",
                    self.actors.len()
                ),
            });
        }
        for (i, actor) in self.actors.iter().enumerate() {
            if !(0.0..=1.0).contains(&actor.albedo) {
                return Err(SceneError::Invalid {
                    field: format!("actors[{i}].albedo"),
                    reason: format!("must be 0–1, got {}", actor.albedo),
                });
            }
        }
        Ok(())
    }
}

impl Sun {
    /// Unit vector from the ground towards the sun, world frame.
    pub fn direction(&self) -> [f64; 3] {
        let (az, el) = (
            self.azimuth_deg.to_radians(),
            self.elevation_deg.to_radians(),
        );
        [el.cos() * az.cos(), el.sin(), el.cos() * az.sin()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{builtin_description, builtin_target};

    /// Lanes outside 1–4, too many actors and an actor's albedo outside 0–1 are refused,
    /// each naming its field.
    #[test]
    fn lanes_and_actors_out_of_range_are_refused_by_name() {
        let refused = |edit: &dyn Fn(&mut SceneDescription)| {
            let mut d = builtin_description(builtin_target(), 1);
            edit(&mut d);
            match d.validate() {
                Err(SceneError::Invalid { field, .. }) => field,
                other => panic!("{other:?}"),
            }
        };
        let actor = |albedo| ActorBody {
            kind: VehicleKind::Truck,
            albedo,
            tail_lamps: false,
        };
        assert_eq!(refused(&|d| d.route.lanes = 0), "route.lanes");
        assert_eq!(refused(&|d| d.route.lanes = 5), "route.lanes");
        assert_eq!(
            refused(&|d| d.actors = vec![actor(0.5); ObjectSlot::MAX_ACTORS as usize + 1]),
            "actors"
        );
        assert_eq!(
            refused(&|d| d.actors = vec![actor(0.5), actor(f64::NAN)]),
            "actors[1].albedo"
        );
        let mut d = builtin_description(builtin_target(), 1);
        d.route.lanes = RouteSpec::MAX_LANES;
        d.actors = vec![actor(1.0); ObjectSlot::MAX_ACTORS as usize];
        let scene = crate::scene::Scene::build(d).expect("the most lanes and actors");
        let slots: Vec<u32> = scene.objects().iter().map(|o| o.slot).collect();
        assert_eq!(slots.last(), Some(&(ObjectSlot::COUNT - 1)));
    }
}

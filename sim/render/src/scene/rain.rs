//! Rain ([`Rain`]): what a rain rate does to a camera's view, from the drops' published
//! physics. The drops in the air (Marshall–Palmer's sizes, Gunn–Kinzer's fall speeds) dim
//! the scene with distance and draw streaks across the image; the road under them turns
//! wet, darker and a mirror for the sky.

use super::description::{Fog, Sun};

/// The rate's band, after the American Meteorological Society's glossary (and the UK Met
/// Office's): light below 2.5 mm/h, moderate from 2.5 to 7.6 mm/h, heavy above.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RainBand {
    /// Under [`Rain::MODERATE_FROM_MM_H`].
    Light,
    /// From [`Rain::MODERATE_FROM_MM_H`] to [`Rain::HEAVY_ABOVE_MM_H`].
    Moderate,
    /// Over [`Rain::HEAVY_ABOVE_MM_H`].
    Heavy,
}

/// Rain falling on the scene at `rate_mm_h`. Each of its effects acts on the scene's
/// radiance before the sensor, whose gain, noise and automatic gain act on it as on any
/// light:
///
/// - **The air** ([`Rain::extinction_per_m`]): the drops scatter light out of every ray, by
///   Koschmieder's law as fog does (the two extinctions add), with the same airlight; the
///   sky is the airlight, an overcast's grey.
/// - **Streaks** ([`Rain::visible_drops`], drawn by the renderer): each drop near enough to
///   image at least [`Rain::MIN_DROP_PX`] wide is a line, its length its motion relative to
///   the camera over the exposure, its brightness the light it refracts from the scene.
/// - **The wet road** ([`Rain::wet_albedo_factor`], [`Rain::film_share`]): the asphalt's
///   and its paint's albedo falls, and a water film mirrors the sky by Fresnel's law.
///
/// Two more effects are options, off by default (the frames then drawn as before they
/// existed, bit for bit):
///
/// - **Spray** ([`Rain::spray`], [`super::Spray`]): the plume of fine droplets the tyres of
///   every vehicle moving faster than about 55 km/h throw up from the water film, which
///   dims and veils what lies behind it, lit by the scene.
/// - **Lamps mirrored** ([`Rain::lamp_reflections`]): the water film mirrors the lit lamps
///   (the chase's headlamps, the tail and brake lamps, the street lights) as it mirrors the
///   sky, a rough mirror ([`Rain::FILM_SLOPE_RMS`]) that draws each lamp out into a streak
///   towards the camera.
///
/// A rate of 0 is dry: the scene as without rain, bit for bit.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Rain {
    /// The rain rate R, millimetres of water an hour.
    pub rate_mm_h: f64,
    /// Whether the vehicles' tyres throw spray ([`super::Spray`]); not written when off,
    /// so a description without it reads and writes as before.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub spray: bool,
    /// Whether the wet road mirrors the lit lamps; not written when off.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub lamp_reflections: bool,
}

impl Rain {
    /// Rain at `rate_mm_h`, without spray or mirrored lamps.
    pub const fn new(rate_mm_h: f64) -> Rain {
        Rain {
            rate_mm_h,
            spray: false,
            lamp_reflections: false,
        }
    }

    /// The root-mean-square slope of the water film's surface, as a Beckmann distribution's
    /// roughness `m` (the mean square slope over both directions is `m²`): 0.15. Cox & Munk
    /// (1954, "Measurement of the roughness of the sea surface from photographs of the sun's
    /// glitter", JOSA 44(11)) measured a mean square slope `0.003 + 0.00512 U` on water under
    /// a wind of U m/s, 0.02 (m = 0.15) at 3.5 m/s; a road's film, stirred by the drops'
    /// impacts and the traffic's wakes, is taken as rough as that. It sets how far a
    /// mirrored lamp is drawn out: at the grazing angles a camera sees the road at, the
    /// lobe of directions `m` wide spans metres of road, a streak along the line from the
    /// lamp's foot towards the camera.
    pub const FILM_SLOPE_RMS: f64 = 0.15;

    /// The least rate of moderate rain, mm/h (light rain below it).
    pub const MODERATE_FROM_MM_H: f64 = 2.5;
    /// The rate above which rain is heavy, mm/h.
    pub const HEAVY_ABOVE_MM_H: f64 = 7.6;
    /// The largest rate a scene takes, mm/h: about the heaviest hour of rain ever measured
    /// in Europe, beyond any rate a vehicle keeps driving in.
    pub const MAX_RATE_MM_H: f64 = 200.0;
    /// Marshall–Palmer's intercept N0, drops per cubic metre per millimetre of diameter
    /// (Marshall & Palmer 1948, "The distribution of raindrops with size":
    /// `N(D) = N0 exp(−Λ D)`).
    pub const MP_N0_PER_M3_MM: f64 = 8000.0;
    /// The largest drop drawn, mm: drops over about 6 mm break up as they fall (Pruppacher &
    /// Klett, "Microphysics of clouds and precipitation").
    pub const MAX_DROP_MM: f64 = 6.0;
    /// The narrowest image of a drop drawn as a streak, pixels: a drop imaged narrower
    /// crosses each pixel of its streak in under a sixtieth of a 4 ms exposure at the
    /// shortest streaks, and changes it by under a grey level.
    pub const MIN_DROP_PX: f64 = 0.25;
    /// The nearest drop drawn, metres: nearer, a fixed-focus lens's blur disc is many
    /// times the drop's own image, which it spreads below a grey level.
    pub const NEAREST_DROP_M: f64 = 0.3;
    /// The share of its albedo a road loses when wet: wet, a rough surface's pores fill
    /// with water (refractive index 1.33), light is trapped by total internal reflection in
    /// the film and more of it absorbed (Lekner & Dorf 1988, "Why some things are darker
    /// when wet", Applied Optics 27(7)); their model and measurements on dark rough
    /// surfaces such as asphalt give a wet albedo about 0.5–0.7 of the dry; 0.6 here.
    pub const WET_DARKENING: f64 = 0.4;
    /// Water's reflectance at normal incidence, `((n − 1)/(n + 1))²` with n = 1.33: the
    /// Fresnel term's floor in Schlick's approximation.
    pub const WATER_F0: f64 = 0.02;

    /// The rate's band.
    pub fn band(&self) -> RainBand {
        if self.rate_mm_h < Self::MODERATE_FROM_MM_H {
            RainBand::Light
        } else if self.rate_mm_h <= Self::HEAVY_ABOVE_MM_H {
            RainBand::Moderate
        } else {
            RainBand::Heavy
        }
    }

    /// Whether any rain falls (a rate of 0 is dry, the scene as without rain).
    pub fn falls(&self) -> bool {
        self.rate_mm_h > 0.0
    }

    /// Marshall–Palmer's slope Λ, per millimetre: `4.1 R^−0.21`.
    pub fn slope_per_mm(&self) -> f64 {
        4.1 * self.rate_mm_h.powf(-0.21)
    }

    /// The drops per cubic metre, all sizes: `N0 / Λ`.
    pub fn drops_per_m3(&self) -> f64 {
        Self::MP_N0_PER_M3_MM / self.slope_per_mm()
    }

    /// A drop's terminal fall speed in still air at sea level, m/s, for a diameter
    /// `diameter_mm`: Atlas, Srivastava & Sekhon's (1973) fit to Gunn & Kinzer's (1949)
    /// measurements, `9.65 − 10.3 exp(−0.6 D)`, 0 for the smallest drops where the fit
    /// goes negative (about 0.1 mm).
    pub fn fall_speed_mps(diameter_mm: f64) -> f64 {
        (9.65 - 10.3 * (-0.6 * diameter_mm).exp()).max(0.0)
    }

    /// The extinction coefficient of the air in this rain, per metre. Drops are large
    /// beside light's wavelength, so each removes from a ray the light falling on its
    /// cross-section `π D² / 4` (geometric optics; the equal share it diffracts stays
    /// within a fraction of a milliradian of the ray, inside its pixel). Over
    /// Marshall–Palmer's drops, `β = ∫ N0 exp(−ΛD) π D²/4 dD = π N0 / (2 Λ³)`, which is
    /// `0.18 R^0.63` per kilometre: the power law of the published fits of visibility in
    /// rain (an exponent of 0.63), about 1 per km (a visual range of 4 km) in heavy rain of
    /// 16 mm/h.
    pub fn extinction_per_m(&self) -> f64 {
        if !self.falls() {
            return 0.0;
        }
        let l = self.slope_per_mm();
        // N0 per m³ per mm, D² in mm² (1e-6 m²).
        std::f64::consts::PI * Self::MP_N0_PER_M3_MM * 1e-6 / (2.0 * l * l * l)
    }

    /// The visual range in this rain alone, metres (Koschmieder: `3.912 / β`); infinite
    /// when dry.
    pub fn visual_range_m(&self) -> f64 {
        Fog::KOSCHMIEDER / self.extinction_per_m()
    }

    /// The airlight of the rain's (and any fog's) path to the sky under `sun`: the same
    /// white, scattering medium as fog's, [`Fog::luminance`].
    pub fn airlight(sun: &Sun) -> f64 {
        sun.ambient + Fog::SUN_SHARE * sun.strength
    }

    /// How wet the road is, 0–1: a rate's share of the moderate band's threshold, 1 from
    /// there on (from moderate rain on, water stands in the road's texture; light rain
    /// darkens it in patches).
    pub fn wetness(&self) -> f64 {
        (self.rate_mm_h / Self::MODERATE_FROM_MM_H).clamp(0.0, 1.0)
    }

    /// The factor on the road's (asphalt's and its paint's) albedo: `1 − 0.4 w`, w the
    /// [`Rain::wetness`] ([`Rain::WET_DARKENING`]): 0.6 from moderate rain on.
    pub fn wet_albedo_factor(&self) -> f64 {
        1.0 - Self::WET_DARKENING * self.wetness()
    }

    /// The share of the road that a smooth film of water covers, mirroring the sky:
    /// `w · R / (R + 7.6)`: half of what stands in the texture at the heavy band's
    /// threshold, 0.68 at 16 mm/h, rising towards a road wholly drowned. The model's own
    /// choice: the share grows with the rate, is half at heavy rain's threshold, and
    /// leaves most of a lightly wet road rough.
    pub fn film_share(&self) -> f64 {
        let r = self.rate_mm_h.max(0.0);
        self.wetness() * r / (r + Self::HEAVY_ABOVE_MM_H)
    }

    /// Water's Fresnel reflectance seen at `cos_incidence` from the normal (Schlick's
    /// approximation, `F0 + (1 − F0)(1 − cos θ)⁵`): 0.02 looking straight down, 0.5 at 7.6°
    /// from grazing, where a camera 2 m up sees the road 15 m ahead.
    pub fn water_reflectance(cos_incidence: f64) -> f64 {
        let c = 1.0 - cos_incidence.clamp(0.0, 1.0);
        Self::WATER_F0 + (1.0 - Self::WATER_F0) * c.powi(5)
    }

    /// The expected number of drops a frame draws as streaks, for a camera with focal
    /// lengths `focal_px` (pixels) and an image `width` × `height` pixels: the drops in the
    /// camera's view whose image is at least [`Rain::MIN_DROP_PX`] wide, that is nearer than
    /// `z_max(D) = f D / MIN_DROP_PX`. A drop of diameter D in the frustum up to `z_max`
    /// (`W H z_max³ / (3 fx fy)` cubic metres) over Marshall–Palmer's sizes:
    /// `∫ N0 e^(−ΛD) W H z_max³/(3 fx fy) dD = 2 N0 W H fx² / (fy p³ Λ⁴)` (D in metres in
    /// z_max): for the paper's camera (320 px focal length, 256 × 242 pixels) about 130 in
    /// light rain of 2 mm/h, 410 at 8 mm/h and 740 in heavy rain of 16 mm/h, growing as
    /// `Λ⁻⁴`, `R^0.84`.
    pub fn visible_drops(&self, focal_px: [f64; 2], width: f64, height: f64) -> f64 {
        if !self.falls() {
            return 0.0;
        }
        let [fx, fy] = focal_px;
        let p = Self::MIN_DROP_PX;
        let l = self.slope_per_mm();
        // D in mm: z_max = fx D 1e-3 / p metres, so D³ carries 1e-9.
        2.0 * Self::MP_N0_PER_M3_MM * width * height * fx * fx * 1e-9 / (fy * p * p * p * l.powi(4))
    }
}

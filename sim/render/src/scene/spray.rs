//! Spray ([`Spray`]): the plume of fine droplets a vehicle's tyres throw up from the water
//! film on a wet road, as a density of extinction behind the vehicle, from the film's
//! depth, the vehicle's speed and the droplets' size.

use super::rain::Rain;

/// The spray behind a vehicle in rain ([`Rain::spray`]). The model, each step with its
/// source or stated as the model's own choice:
///
/// 1. **The film.** The water standing above the road's texture is
///    `h = FILM_AT_REFERENCE_M · (R / FILM_REFERENCE_MM_H)^0.59` metres for a rain rate R,
///    the exponent that of Gallaway et al.'s regression of film depth on rainfall intensity
///    (1979, "Pavement and geometric design criteria for minimizing hydroplaning",
///    FHWA-RD-79-30), the scale (0.5 mm at 10 mm/h) the model's own choice for a two-lane
///    road's drainage path.
/// 2. **The water thrown.** A tyre of width `w` sweeps `h w v` cubic metres a second at
///    speed v; a share `ε(v)` of it leaves as droplets fine enough to hang in the air. Below
///    `ONSET_MPS` (55 km/h) the water leaves as sheets and large drops that fall at once,
///    and spray is negligible; above it the share grows with the square of the excess
///    speed, `ε = ATOMISED_AT_REFERENCE · ((v − v0) / (v_ref − v0))²`, 0.1 at 100 km/h (the
///    model's own choice of form and scale, after the observation that spray is negligible
///    below 50–60 km/h and grows fast with speed and film depth).
/// 3. **The trail.** The droplets are left behind in the air the vehicle has passed, so
///    each metre of trail holds `ε h w n` cubic metres of water for `n` tyres. Drops of
///    radius r much larger than light's wavelength remove their cross-section twice
///    (extinction efficiency 2), so a volume V of water in drops of radius r removes light
///    over `3 V / (2 r)` square metres: the trail's extinction cross-section per metre is
///    `σ = 3 ε h w n / (2 r)` metres (the integral of the extinction β over the plume's
///    cross-section).
/// 4. **The plume.** Behind the vehicle's back (s metres behind it) σ spreads over a
///    Gaussian across the trail of half-width `W(s) = W0 + SPREAD_PER_M s` (W0 half the
///    vehicle's width) and an exponential over height of scale
///    `H(s) = min(SOURCE_HEIGHT_M + RISE_PER_M s, MAX_HEIGHT_M)`:
///    `β(s, y, z) = σ(s) / (√π W H) · exp(−(y/W)²) · exp(−z/H)`. The droplets settle out:
///    `σ(s) = σ0 exp(−s / (v t))`, t the time a droplet of [`Spray::DROPLET_DIAMETER_MM`]
///    takes to fall through a metre at its terminal speed ([`Rain::fall_speed_mps`]).
/// 5. **Puffs.** The turbulence of the wake makes the trail puffy: β is times
///    `1 + PUFF_DEPTH sin(2π s / PUFF_M + φ)`, and σ0 times a gust `1 + GUST (2u − 1)`, φ
///    and u drawn each frame and for each vehicle from the `"spray"` stream.
/// 6. **Light.** The plume veils what lies behind it by Koschmieder's law over the path
///    through it, `exp(−∫β)`, and adds the light its droplets scatter towards the camera:
///    the airlight of rain's and fog's white medium ([`Rain::airlight`]), and a quarter
///    ([`Spray::SCATTER_SHARE`]) of the headlamps' and street lights' light falling on it.
pub struct Spray;

impl Spray {
    /// The speed below which spray is negligible, m/s (55 km/h: spray is observed to be
    /// negligible below about 50–60 km/h).
    pub const ONSET_MPS: f64 = 55.0 / 3.6;
    /// The reference speed of [`Spray::ATOMISED_AT_REFERENCE`], m/s (100 km/h).
    pub const REFERENCE_MPS: f64 = 100.0 / 3.6;
    /// The share of the water swept that leaves as fine droplets at the reference speed:
    /// 0.1, the model's own choice.
    pub const ATOMISED_AT_REFERENCE: f64 = 0.1;
    /// The film's depth above the texture at [`Spray::FILM_REFERENCE_MM_H`], metres.
    pub const FILM_AT_REFERENCE_M: f64 = 0.5e-3;
    /// The rain rate of [`Spray::FILM_AT_REFERENCE_M`], mm/h.
    pub const FILM_REFERENCE_MM_H: f64 = 10.0;
    /// Gallaway et al.'s exponent of film depth on rainfall intensity.
    pub const FILM_EXPONENT: f64 = 0.59;
    /// A tyre's width, metres (a pickup's 265 mm, a car's 205 mm: 0.25 m for all).
    pub const TYRE_WIDTH_M: f64 = 0.25;
    /// The tyres that throw spray: all four of a car's or pickup's.
    pub const TYRES: f64 = 4.0;
    /// The diameter of the droplets that hang in the air, mm: the fine end of tyre spray's
    /// droplets (a tenth of a millimetre to a millimetre), the larger falling at once.
    pub const DROPLET_DIAMETER_MM: f64 = 0.3;
    /// The height scale of the plume at the vehicle's back, metres (the wheel arches').
    pub const SOURCE_HEIGHT_M: f64 = 0.4;
    /// How fast the plume's height scale grows behind the vehicle, metres per metre.
    pub const RISE_PER_M: f64 = 0.1;
    /// The greatest height scale, metres: the wake mixes the spray up to about a car's
    /// roof.
    pub const MAX_HEIGHT_M: f64 = 1.5;
    /// How fast the plume's half-width grows behind the vehicle, metres per metre.
    pub const SPREAD_PER_M: f64 = 0.1;
    /// How far the plume is drawn behind its source, in settling lengths (`v t`): 4, where
    /// 1.8 % of it is left.
    pub const LENGTH_IN_DECAYS: f64 = 4.0;
    /// The puffs' wavelength along the trail, metres.
    pub const PUFF_M: f64 = 3.0;
    /// The puffs' depth of modulation, 0–1.
    pub const PUFF_DEPTH: f64 = 0.5;
    /// A frame's gust: the source's strength varies by up to this share either way.
    pub const GUST: f64 = 0.2;
    /// The share of the lamps' light on a droplet it scatters towards the camera, in the
    /// units of a white matte surface's: a quarter, as fog's share of the sun
    /// ([`super::Fog::SUN_SHARE`]).
    pub const SCATTER_SHARE: f64 = 0.25;

    /// The film's depth above the road's texture in `rain`, metres (0 when dry).
    pub fn film_depth_m(rain: &Rain) -> f64 {
        if !rain.falls() {
            return 0.0;
        }
        Self::FILM_AT_REFERENCE_M
            * (rain.rate_mm_h / Self::FILM_REFERENCE_MM_H).powf(Self::FILM_EXPONENT)
    }

    /// The share of the water swept that leaves as fine droplets at `speed_mps`: 0 up to
    /// [`Spray::ONSET_MPS`], then growing with the square of the excess speed.
    pub fn atomised_share(speed_mps: f64) -> f64 {
        let excess = (speed_mps.abs() - Self::ONSET_MPS).max(0.0);
        let x = excess / (Self::REFERENCE_MPS - Self::ONSET_MPS);
        Self::ATOMISED_AT_REFERENCE * x * x
    }

    /// The trail's extinction cross-section per metre at its source, `σ0 = 3 ε h w n / (2 r)`,
    /// metres, for a vehicle at `speed_mps` in `rain` (0 below the onset or when dry).
    pub fn source_cross_section_m(rain: &Rain, speed_mps: f64) -> f64 {
        let r = 0.5 * Self::DROPLET_DIAMETER_MM * 1e-3;
        3.0 * Self::atomised_share(speed_mps)
            * Self::film_depth_m(rain)
            * Self::TYRE_WIDTH_M
            * Self::TYRES
            / (2.0 * r)
    }

    /// The settling length `v t`, metres: how far behind a vehicle at `speed_mps` its
    /// trail falls to 1/e (t: a metre at the droplets' terminal speed).
    pub fn settling_length_m(speed_mps: f64) -> f64 {
        speed_mps.abs() / Rain::fall_speed_mps(Self::DROPLET_DIAMETER_MM)
    }

    /// The plume's extinction, per metre, `s` metres behind the back of a vehicle of
    /// half-width `half_width_m` at `speed_mps`, `y` metres from its centre line and `z`
    /// metres up, without the puffs and gusts (their mean).
    pub fn extinction_per_m(
        rain: &Rain,
        speed_mps: f64,
        half_width_m: f64,
        [s, y, z]: [f64; 3],
    ) -> f64 {
        if s < 0.0 || z < 0.0 {
            return 0.0;
        }
        let sigma = Self::source_cross_section_m(rain, speed_mps);
        if sigma == 0.0 {
            return 0.0;
        }
        let w = half_width_m + Self::SPREAD_PER_M * s;
        let h = (Self::SOURCE_HEIGHT_M + Self::RISE_PER_M * s).min(Self::MAX_HEIGHT_M);
        let decayed = sigma * (-s / Self::settling_length_m(speed_mps)).exp();
        decayed / (std::f64::consts::PI.sqrt() * w * h) * (-(y / w).powi(2)).exp() * (-z / h).exp()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spray_starts_at_its_onset_and_grows_with_speed_and_rain() {
        let heavy = Rain::new(16.0);
        let light = Rain::new(2.0);
        assert_eq!(Spray::source_cross_section_m(&heavy, 40.0 / 3.6), 0.0);
        let at = |rain: &Rain, kmh: f64| Spray::source_cross_section_m(rain, kmh / 3.6);
        assert!(at(&heavy, 80.0) > 0.0);
        assert!(at(&heavy, 100.0) > at(&heavy, 80.0));
        assert!(at(&heavy, 100.0) > at(&light, 100.0));
        assert_eq!(Spray::source_cross_section_m(&Rain::new(0.0), 30.0), 0.0);
        // 0.1 × 0.66 mm × 0.25 m × 4 tyres × 3 / (2 × 0.15 mm) ≈ 0.66 m at 100 km/h, 16 mm/h.
        assert!(
            (at(&heavy, 100.0) - 0.66).abs() < 0.01,
            "{}",
            at(&heavy, 100.0)
        );
    }

    #[test]
    fn the_plume_holds_its_cross_section() {
        // ∫∫ β dy dz over the cross-section is σ(s).
        let rain = Rain::new(16.0);
        let v = 27.0;
        let s = 5.0;
        let (dy, dz) = (0.01, 0.01);
        let mut sum = 0.0;
        for i in -1000..1000 {
            for j in 0..2000 {
                let p = [s, (f64::from(i) + 0.5) * dy, (f64::from(j) + 0.5) * dz];
                sum += Spray::extinction_per_m(&rain, v, 0.9, p) * dy * dz;
            }
        }
        let sigma =
            Spray::source_cross_section_m(&rain, v) * (-s / Spray::settling_length_m(v)).exp();
        assert!((sum / sigma - 1.0).abs() < 0.01, "{sum} vs {sigma}");
    }
}

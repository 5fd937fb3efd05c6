//! Dusk and night: the sky's light with the sun below the horizon ([`twilight_factor`]) and
//! the chase's headlamps ([`Beam`], [`Headlamps`]).

use super::description::{ChaseVehicle, Sun};

/// The lowest sun a scene takes, degrees: the end of astronomical twilight, below which the
/// sky is as dark as it gets.
pub const MIN_SUN_ELEVATION_DEG: f64 = -18.0;

/// The sky's illuminance on the ground (lux) at the sun's elevation (degrees) through
/// twilight, from the standard tables (the U.S. Naval Observatory's and the IES Lighting
/// Handbook's figures for a clear sky without moon: about 400 lux at sunset, 3 lux at the end
/// of civil twilight, 0.008 lux at the end of nautical twilight, 0.001 lux of starlight at
/// the end of astronomical twilight). [`twilight_factor`] interpolates their logarithm
/// linearly in the elevation.
pub const TWILIGHT_LUX: [(f64, f64); 4] =
    [(0.0, 400.0), (-6.0, 3.0), (-12.0, 0.008), (-18.0, 0.001)];

/// The share of the sunset's sky light left with the sun `elevation_deg` degrees below the
/// horizon (0 to −18): 1 at 0°, then the log-linear fall of [`TWILIGHT_LUX`], 7.5e-3 at −6°
/// (civil dusk), 2e-5 at −12° (nautical) and 2.5e-6 at −18° (astronomical, night). Below
/// −18° it stays at night's level; above 0° it is 1.
pub fn twilight_factor(elevation_deg: f64) -> f64 {
    if elevation_deg >= 0.0 {
        return 1.0;
    }
    let e = elevation_deg.clamp(MIN_SUN_ELEVATION_DEG, 0.0);
    let l0 = TWILIGHT_LUX[0].1;
    for pair in TWILIGHT_LUX.windows(2) {
        let ((a, la), (b, lb)) = (pair[0], pair[1]);
        if e <= a && e >= b {
            let t = (a - e) / (a - b);
            let log = la.log10() + t * (lb.log10() - la.log10());
            return 10f64.powf(log) / l0;
        }
    }
    TWILIGHT_LUX[3].1 / l0
}

impl Sun {
    /// The light the scene is shaded with. With the sun above the horizon, the sun as given,
    /// untouched. At or below it (down to −18°), no direct sunlight (`strength` 0, so no
    /// sun shadow either: the shadow maps are still drawn, from straight overhead, but
    /// nothing reads them), and the ambient and the sky's brightness are scaled by
    /// [`twilight_factor`]: the given ambient and sky stand for the sky's light at sunset.
    pub fn lighting(&self) -> Sun {
        if self.elevation_deg > 0.0 {
            return self.clone();
        }
        let k = twilight_factor(self.elevation_deg);
        Sun {
            azimuth_deg: self.azimuth_deg,
            elevation_deg: 90.0,
            strength: 0.0,
            ambient: self.ambient * k,
            sky: self.sky * k,
            soft_shadows: self.soft_shadows,
        }
    }
}

/// The chase's headlamps' beam.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Beam {
    /// Dipped beam: aimed 1° down, with a sharp upper cut-off at the lamps' horizontal
    /// above which only stray light (5 %) passes.
    Low,
    /// Main beam: level, brighter, without a cut-off.
    High,
}

/// The photometry of one headlamp's beam: a Gaussian hot spot about its axis (aimed
/// `aim_deg` up), and, for a dipped beam, an upper cut-off.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Headlamps {
    /// The peak luminous intensity, candela.
    pub peak_cd: f64,
    /// The axis's elevation from the chase's forward direction, degrees (negative: down).
    pub aim_deg: f64,
    /// The hot spot's horizontal standard deviation, degrees.
    pub sigma_h_deg: f64,
    /// The hot spot's vertical standard deviation, degrees.
    pub sigma_v_deg: f64,
    /// The upper cut-off's elevation from the forward direction, degrees (`None`: no
    /// cut-off). Above it, over [`Headlamps::CUT_OFF_RAMP_DEG`], the intensity falls to
    /// `stray` of the hot spot's.
    pub cut_off_deg: Option<f64>,
    /// The share of the intensity left above the cut-off.
    pub stray: f64,
}

impl Headlamps {
    /// The illuminance (lux) that one unit of the scene's irradiance stands for: the
    /// default ambient, 0.25, is then the sky's 400 lux at sunset that [`twilight_factor`]
    /// starts from, so that the lamps and the twilight sky share one scale.
    pub const LUX_PER_UNIT: f64 = 1600.0;
    /// The width of the low beam's cut-off, degrees: from the hot spot to the stray light.
    pub const CUT_OFF_RAMP_DEG: f64 = 0.5;

    /// A beam's photometry (typical of a halogen lamp, after the ECE R112 and SAE J1383
    /// patterns): a low beam of 15 000 cd aimed 1° down, 12° by 4° (standard deviations),
    /// cut off at the lamp's horizontal with 5 % stray light above; a high beam of
    /// 40 000 cd, level, 15° by 5°, with no cut-off.
    pub fn of(beam: Beam) -> Headlamps {
        match beam {
            Beam::Low => Headlamps {
                peak_cd: 15_000.0,
                aim_deg: -1.0,
                sigma_h_deg: 12.0,
                sigma_v_deg: 4.0,
                cut_off_deg: Some(0.0),
                stray: 0.05,
            },
            Beam::High => Headlamps {
                peak_cd: 40_000.0,
                aim_deg: 0.0,
                sigma_h_deg: 15.0,
                sigma_v_deg: 5.0,
                cut_off_deg: None,
                stray: 1.0,
            },
        }
    }

    /// The two lamps' positions on the chase (vehicle frame: x forward, y up, z right;
    /// metres): at the hood's front edge, 0.6 of the hood's height above the ground, and
    /// 0.2 m in from each side of the hood.
    pub fn positions(chase: &ChaseVehicle) -> [[f64; 3]; 2] {
        let (x, y) = (chase.hood_front_m, 0.6 * chase.hood_height_m);
        let z = (0.5 * chase.hood_width_m - 0.2).max(0.0);
        [[x, y, -z], [x, y, z]]
    }

    /// The luminous intensity (cd) in a direction `h_deg` to the side of and `v_deg` above
    /// the chase's forward direction (the shader's formula).
    pub fn intensity_cd(&self, h_deg: f64, v_deg: f64) -> f64 {
        let dh = h_deg / self.sigma_h_deg;
        let dv = (v_deg - self.aim_deg) / self.sigma_v_deg;
        let spot = self.peak_cd * (-0.5 * (dh * dh + dv * dv)).exp();
        match self.cut_off_deg {
            None => spot,
            Some(c) => {
                let t = ((v_deg - c) / Self::CUT_OFF_RAMP_DEG).clamp(0.0, 1.0);
                let s = t * t * (3.0 - 2.0 * t);
                spot * (1.0 + (self.stray - 1.0) * s)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The twilight curve passes through its table and falls monotonically.
    #[test]
    fn twilight_follows_its_table() {
        for (e, lux) in TWILIGHT_LUX {
            let k = twilight_factor(e);
            assert!((k * 400.0 / lux - 1.0).abs() < 1e-9, "{e}: {k}");
        }
        let mut last = 2.0;
        for i in 0..=36 {
            let k = twilight_factor(-0.5 * f64::from(i));
            assert!(k < last);
            last = k;
        }
        assert_eq!(twilight_factor(5.0), 1.0);
    }

    /// Above the horizon the sun is left untouched; below, no direct light.
    #[test]
    fn lighting_branches_at_the_horizon() {
        let sun = Sun::default();
        assert_eq!(sun.lighting(), sun);
        let night = Sun {
            elevation_deg: -18.0,
            ..Sun::default()
        };
        let l = night.lighting();
        assert_eq!(l.strength, 0.0);
        assert!(l.ambient < 1e-6 && l.ambient > 0.0);
    }

    /// The low beam is cut off above the horizontal; the high beam is not.
    #[test]
    fn low_beam_is_cut_off() {
        let low = Headlamps::of(Beam::Low);
        let high = Headlamps::of(Beam::High);
        assert!(low.intensity_cd(0.0, 2.0) < 0.06 * low.intensity_cd(0.0, -1.0));
        assert!(high.intensity_cd(0.0, 2.0) > 0.8 * high.intensity_cd(0.0, 0.0));
    }
}

//! `[environment]`: the sun, the clutter's densities, the overpasses, the sensor, the road's
//! surface, the ground's textures, the fog and the rain.

use super::{check, Blame, MAX_BLUR_SIGMA_PX};
use crate::scenario::{EnvironmentFile, ScenarioError};
use sim_render::{
    AutoGain, Densities, Fog, Placement, Rain, RoadSurface, Sensor, Sun, Textures,
    MIN_SUN_ELEVATION_DEG,
};

/// The environment as validated (the distractors and overpasses are checked on their own).
pub(super) struct Environment {
    pub(super) sun: Sun,
    pub(super) densities: Densities,
    pub(super) sensor: Sensor,
    pub(super) road_surface: RoadSurface,
    pub(super) textures: Textures,
    pub(super) fog: Option<Fog>,
    pub(super) rain: Option<Rain>,
}

/// The environment's sun, clutter, sensor, road, textures and fog.
pub(super) fn environment(e: &EnvironmentFile, f: &Blame) -> Result<Environment, ScenarioError> {
    let sun = sun(e, f)?;
    let mut densities = Densities::default();
    let cl = &e.clutter;
    for (field, src, dst) in [
        ("trees_per_km", cl.trees_per_km, &mut densities.trees_per_km),
        ("poles_per_km", cl.poles_per_km, &mut densities.poles_per_km),
        (
            "houses_per_km",
            cl.houses_per_km,
            &mut densities.houses_per_km,
        ),
        (
            "buildings_per_km",
            cl.buildings_per_km,
            &mut densities.buildings_per_km,
        ),
        (
            "parked_vehicles_per_km",
            cl.parked_vehicles_per_km,
            &mut densities.parked_vehicles_per_km,
        ),
        (
            "oncoming_vehicles_per_km",
            cl.oncoming_vehicles_per_km,
            &mut densities.oncoming_vehicles_per_km,
        ),
        (
            "cracks_per_km",
            cl.cracks_per_km,
            &mut densities.cracks_per_km,
        ),
        (
            "patches_per_km",
            cl.patches_per_km,
            &mut densities.patches_per_km,
        ),
        (
            "potholes_per_km",
            cl.potholes_per_km,
            &mut densities.potholes_per_km,
        ),
    ] {
        if let Some(v) = src {
            f.at(
                &format!("environment.clutter.{field}"),
                check(
                    v.is_finite() && (0.0..=1000.0).contains(&v),
                    "must be 0–1000 per km",
                    v,
                ),
            )?;
            *dst = v;
        }
    }
    if let Some(v) = cl.street_lights_per_km {
        f.at(
            "environment.clutter.street_lights_per_km",
            check(
                v.is_finite() && (0.0..=MAX_STREET_LIGHTS_PER_KM).contains(&v),
                &format!("must be 0–{MAX_STREET_LIGHTS_PER_KM} per km"),
                v,
            ),
        )?;
        densities.street_lights_per_km = v;
    }
    let sensor = sensor(e, f)?;
    let road_surface = match e.road.surface.as_deref() {
        None => RoadSurface::default(),
        Some(name) => RoadSurface::parse(name).ok_or_else(|| {
            f.invalid(
                "environment.road.surface",
                format!("= {name:?}: must be \"asphalt\" or \"gravel\""),
            )
        })?,
    };
    let mut textures = Textures::default();
    if let Some(v) = e.textures.enabled {
        textures.enabled = v;
    }
    if let Some(v) = e.textures.contrast {
        textures.contrast = v;
    }
    f.at(
        "environment.textures.contrast",
        check(
            (0.0..=2.0).contains(&textures.contrast),
            "must be 0–2",
            textures.contrast,
        ),
    )?;

    let fog = fog(e, f)?;
    let rain = rain(e, f)?;

    Ok(Environment {
        sun,
        densities,
        sensor,
        road_surface,
        textures,
        fog,
        rain,
    })
}

/// The most street lights a kilometre takes: one every 10 m, closer than any road is lit
/// (EN 13201's geometry puts them 3–5 mounting heights apart, 24–40 m at 8 m).
const MAX_STREET_LIGHTS_PER_KM: f64 = 100.0;

/// The largest visual range `[environment.fog]` takes, metres: beyond it the air is clear
/// for any distance the camera resolves a target at.
const MAX_VISUAL_RANGE_M: f64 = 100_000.0;

/// `[environment.fog]`.
fn fog(e: &EnvironmentFile, f: &Blame) -> Result<Option<Fog>, ScenarioError> {
    let Some(fog) = &e.fog else {
        return Ok(None);
    };
    let v = fog.visual_range_m;
    f.at(
        "environment.fog.visual_range_m",
        check(
            v.is_finite() && (Fog::MIN_VISUAL_RANGE_M..=MAX_VISUAL_RANGE_M).contains(&v),
            &format!("must be {}–{MAX_VISUAL_RANGE_M} m", Fog::MIN_VISUAL_RANGE_M),
            v,
        ),
    )?;
    Ok(Some(Fog { visual_range_m: v }))
}

/// `[environment.rain]`.
fn rain(e: &EnvironmentFile, f: &Blame) -> Result<Option<Rain>, ScenarioError> {
    let Some(rain) = &e.rain else {
        return Ok(None);
    };
    let r = rain.rate_mm_h;
    f.at(
        "environment.rain.rate_mm_h",
        check(
            r.is_finite() && (0.0..=Rain::MAX_RATE_MM_H).contains(&r),
            &format!("must be 0–{} mm/h", Rain::MAX_RATE_MM_H),
            r,
        ),
    )?;
    let mut out = Rain::new(r);
    for (field, on, set) in [
        ("environment.rain.spray", rain.spray, &mut out.spray),
        (
            "environment.rain.lamp_reflections",
            rain.lamp_reflections,
            &mut out.lamp_reflections,
        ),
    ] {
        let on = on.unwrap_or(false);
        f.at(
            field,
            check(!on || r > 0.0, "needs rain: rate_mm_h over 0", on),
        )?;
        *set = on;
    }
    Ok(Some(out))
}

/// `[[environment.overpasses]]` on a route `length` metres long.
pub(super) fn overpasses(
    e: &EnvironmentFile,
    length: f64,
    f: &Blame,
) -> Result<Vec<Placement>, ScenarioError> {
    let mut placements = Vec::new();
    for (i, o) in e.overpasses.iter().enumerate() {
        let field = |name: &str| format!("environment.overpasses[{i}].{name}");
        f.at(
            &field("station_m"),
            check(
                o.station_m.is_finite() && (0.0..=length).contains(&o.station_m),
                &format!("must lie on the route, 0–{length:.0} m"),
                o.station_m,
            ),
        )?;
        let deck_m = o.deck_m.unwrap_or(10.0);
        f.at(
            &field("deck_m"),
            check((2.0..=60.0).contains(&deck_m), "must be 2–60 m", deck_m),
        )?;
        let height_m = o.height_m.unwrap_or(5.5);
        f.at(
            &field("height_m"),
            check(
                (4.5..=20.0).contains(&height_m),
                "must be 4.5–20 m",
                height_m,
            ),
        )?;
        placements.push(Placement::Overpass {
            station_m: o.station_m,
            deck_m,
            height_m,
        });
    }
    Ok(placements)
}

/// `[environment.sun]`.
fn sun(e: &EnvironmentFile, f: &Blame) -> Result<Sun, ScenarioError> {
    let mut sun = Sun::default();
    if let Some(v) = e.sun.azimuth_deg {
        sun.azimuth_deg = v;
    }
    if let Some(v) = e.sun.elevation_deg {
        sun.elevation_deg = v;
    }
    if let Some(v) = e.sun.strength {
        sun.strength = v;
    }
    if let Some(v) = e.sun.ambient {
        sun.ambient = v;
    }
    sun.soft_shadows = e.sun.soft_shadows.unwrap_or(false);
    f.at(
        "environment.sun.azimuth_deg",
        check(
            (-360.0..=360.0).contains(&sun.azimuth_deg),
            "must be -360–360 degrees",
            sun.azimuth_deg,
        ),
    )?;
    f.at(
        "environment.sun.elevation_deg",
        check(
            (MIN_SUN_ELEVATION_DEG..=90.0).contains(&sun.elevation_deg),
            "must be -18–90 degrees (at or below 0 the sun has set)",
            sun.elevation_deg,
        ),
    )?;
    f.at(
        "environment.sun.strength",
        check(
            (0.0..=2.0).contains(&sun.strength),
            "must be 0–2",
            sun.strength,
        ),
    )?;
    f.at(
        "environment.sun.ambient",
        check(
            (0.0..=2.0).contains(&sun.ambient),
            "must be 0–2",
            sun.ambient,
        ),
    )?;
    Ok(sun)
}

/// `[environment.sensor]`.
fn sensor(e: &EnvironmentFile, f: &Blame) -> Result<Sensor, ScenarioError> {
    let mut sensor = Sensor::default();
    if let Some(v) = e.sensor.gain {
        sensor.gain = v;
    }
    if let Some(v) = e.sensor.noise_sigma_grey {
        sensor.noise_sigma_grey = v;
    }
    sensor.blur_sigma_px = e.sensor.blur_sigma_px;
    f.at(
        "environment.sensor.gain",
        check(
            sensor.gain.is_finite() && (0.05..=20.0).contains(&sensor.gain),
            "must be 0.05–20",
            sensor.gain,
        ),
    )?;
    f.at(
        "environment.sensor.noise_sigma_grey",
        check(
            sensor.noise_sigma_grey.is_finite() && (0.0..=64.0).contains(&sensor.noise_sigma_grey),
            "must be 0–64 grey levels",
            sensor.noise_sigma_grey,
        ),
    )?;
    if let Some(sigma) = sensor.blur_sigma_px {
        f.at(
            "environment.sensor.blur_sigma_px",
            check(
                (0.0..=MAX_BLUR_SIGMA_PX).contains(&sigma),
                &format!("must be 0–{MAX_BLUR_SIGMA_PX} px"),
                sigma,
            ),
        )?;
    }
    if let Some(v) = e.sensor.vignetting {
        sensor.vignetting = v;
    }
    f.at(
        "environment.sensor.vignetting",
        check(
            (0.0..=1.0).contains(&sensor.vignetting),
            "must be 0–1",
            sensor.vignetting,
        ),
    )?;
    sensor.shot_noise_full_well_e = e.sensor.shot_noise_full_well_e;
    sensor.interlaced = e.sensor.interlaced.unwrap_or(false);
    if let Some(full_well_e) = sensor.shot_noise_full_well_e {
        f.at(
            "environment.sensor.shot_noise_full_well_e",
            check(
                (100.0..=1e7).contains(&full_well_e),
                "must be 100–1e7 electrons",
                full_well_e,
            ),
        )?;
    }
    sensor.read_noise_e = e.sensor.read_noise_e;
    if let Some(read_e) = sensor.read_noise_e {
        let field = "environment.sensor.read_noise_e";
        f.at(
            field,
            check(
                (0.0..=1000.0).contains(&read_e),
                "must be 0–1000 electrons",
                read_e,
            ),
        )?;
        f.at(
            field,
            check(
                sensor.shot_noise_full_well_e.is_some(),
                "needs environment.sensor.shot_noise_full_well_e (the electrons at grey 255)",
                read_e,
            ),
        )?;
    }
    if let Some(a) = &e.sensor.auto_gain {
        let mut auto_gain = AutoGain::default();
        for (field, value, into, lo, hi, unit) in [
            (
                "target_grey",
                a.target_grey,
                &mut auto_gain.target_grey,
                10.0,
                245.0,
                " grey levels",
            ),
            (
                "time_constant_s",
                a.time_constant_s,
                &mut auto_gain.time_constant_s,
                0.1,
                60.0,
                " s",
            ),
            (
                "max_gain",
                a.max_gain,
                &mut auto_gain.max_gain,
                1.0,
                64.0,
                "",
            ),
        ] {
            if let Some(v) = value {
                *into = v;
            }
            f.at(
                &format!("environment.sensor.auto_gain.{field}"),
                check(
                    (lo..=hi).contains(&*into),
                    &format!("must be {lo}–{hi}{unit}"),
                    *into,
                ),
            )?;
        }
        if let Some(share) = a.max_clipped_share {
            f.at(
                "environment.sensor.auto_gain.max_clipped_share",
                check(
                    (0.0..=0.5).contains(&share),
                    "must be 0–0.5 (a share of the metering window)",
                    share,
                ),
            )?;
            auto_gain.max_clipped_share = Some(share);
        }
        sensor.auto_gain = Some(auto_gain);
    }

    Ok(sensor)
}

//! Validation: a raw [`ScenarioFile`] (overrides applied) checked field by field against
//! its documented bounds, then built into a [`Scenario`] together with everything the
//! closed loop builds from it but the renderer (the drivers' route, the chase's start on
//! it, the physics ground, the controllers, the delay line, the first view of the
//! target), through the same functions, so that `ClosedLoop::new` refuses nothing that
//! passes.

use super::{Scenario, ScenarioError, ScenarioFile};
use crate::scene::{
    AutoGain, Densities, Distractor, DistractorKind, Placement, RoadSurface, RouteSegment,
    RouteSpec, Sensor, Sun, Textures,
};
use tracker::{Camera, TargetModel, TrackerConfig, TrackerMode};
use vehicle::{DelayLineConfig, ProfileBasis, SpeedProfile, WorldConfig};

/// Longest route, metres: 50 km, twice the longest shipped drive; it keeps the physics
/// ground (which reaches 200 m past the route) inside its 100 km limit and the drivers'
/// 1 m polyline to 50,000 points.
pub const MAX_ROUTE_M: f64 = 50_000.0;
/// Largest arc radius, metres: 10 km, already indistinguishable from a straight over the
/// camera's range.
pub const MAX_ARC_RADIUS_M: f64 = 10_000.0;
/// Smallest arc radius, metres: the vehicles' turning circles.
pub const MIN_ARC_RADIUS_M: f64 = 8.0;
/// Largest Gaussian blur of the sensor, pixels: beyond 10 px a 256-pixel frame holds no
/// edge at all.
pub const MAX_BLUR_SIGMA_PX: f64 = 10.0;
/// Focal length bounds, millimetres: fish-eye to long telephoto.
pub const FOCAL_LENGTH_MM: [f64; 2] = [1.0, 200.0];
/// Largest teleoperator placement error, pixels: half the frame.
pub const MAX_INIT_OFFSET_PX: f64 = 128.0;

/// Most breadcrumbs the chase controller may keep: 1,000,000 (250 km of path at the
/// default spacing).
pub const MAX_BREADCRUMBS: usize = 1_000_000;

/// Pure-pursuit look-ahead bounds: each distance finite, `base_m` 0–50 m, `gain_s` 0–10 s,
/// `min_m` 0.5–100 m and `max_m` from `min_m` to 200 m (the vehicle code clamps between
/// them, which needs `min_m <= max_m`). `Err` names the field.
fn check_lookahead(la: &vehicle::LookAhead) -> Result<(), (&'static str, String)> {
    let (base, gain, min, max) = (
        f64::from(la.base_m),
        f64::from(la.gain_s),
        f64::from(la.min_m),
        f64::from(la.max_m),
    );
    for (field, v, lo, hi, unit) in [
        ("base_m", base, 0.0, 50.0, "m"),
        ("gain_s", gain, 0.0, 10.0, "s"),
        ("min_m", min, 0.5, 100.0, "m"),
    ] {
        check(
            (lo..=hi).contains(&v),
            &format!("must be {lo}–{hi} {unit}"),
            v,
        )
        .map_err(|m| (field, m))?;
    }
    check(
        (min..=200.0).contains(&max),
        "must be from min_m to 200 m",
        max,
    )
    .map_err(|m| ("max_m", m))
}

/// Speed-loop gain bounds: finite, `kp_per_s` and `ki_per_s2` 0–100, `integral_limit_mps2`
/// 0–50 m/s². `Err` names the field.
fn check_speed_gains(g: &vehicle::SpeedGains) -> Result<(), (&'static str, String)> {
    for (field, v, hi) in [
        ("kp_per_s", f64::from(g.kp_per_s), 100.0),
        ("ki_per_s2", f64::from(g.ki_per_s2), 100.0),
        (
            "integral_limit_mps2",
            f64::from(g.integral_limit_mps2),
            50.0,
        ),
    ] {
        check((0.0..=hi).contains(&v), &format!("must be 0–{hi}"), v).map_err(|m| (field, m))?;
    }
    Ok(())
}

/// A vehicle crate's error as the dotted field it is about (under `prefix`) and what to
/// say of it.
fn vehicle_error(prefix: &str, e: &vehicle::VehicleError) -> (String, String) {
    match e {
        vehicle::VehicleError::InvalidParameter {
            field,
            value,
            allowed,
            ..
        } => (
            format!("{prefix}.{field}"),
            match allowed {
                Some([min, max]) => format!(
                    "= {}: must be finite and within {min}–{max}",
                    short(value.to_string())
                ),
                None => format!(
                    "= {}: out of its allowed range, or not finite",
                    short(value.to_string())
                ),
            },
        ),
        other => (prefix.to_string(), format!(": {other}")),
    }
}

/// Whether the override `assignment` (`key=value`) set `field` or a table holding it, or
/// a field inside it.
pub(super) fn override_names(assignment: &str, field: &str) -> bool {
    assignment.split_once('=').is_some_and(|(k, _)| {
        let k = k.trim();
        k == field
            || field
                .strip_prefix(k)
                .is_some_and(|rest| rest.starts_with('.'))
            || k.strip_prefix(field)
                .is_some_and(|rest| rest.starts_with('.'))
    })
}

/// A number as written for people: `1e300`, not three hundred digits.
fn short(text: String) -> String {
    match text.parse::<f64>() {
        Ok(v) if text.len() > 12 => format!("{v:e}"),
        _ => text,
    }
}

/// Width of a shadow distractor's band on the board, metres: wider than the target's
/// spacing of parallel features, so that one edge of it lies near the chosen feature.
const SHADOW_BAND_M: f64 = 0.5;

/// A speed profile from its file form (`SECTION.speed_basis`, `SECTION.speed_profile`);
/// `Err((field, message))` naming what is wrong.
fn speed_profile(
    section: &str,
    basis: &str,
    rows: &[[f64; 2]],
) -> Result<SpeedProfile, (String, String)> {
    let basis = match basis {
        "time" => ProfileBasis::Time,
        "distance" => ProfileBasis::Distance,
        other => {
            return Err((
                format!("{section}.speed_basis"),
                format!("= {other:?}: must be \"time\" or \"distance\""),
            ))
        }
    };
    let field = format!("{section}.speed_profile");
    for [k, v] in rows {
        check(
            k.abs() <= 1e7 && (0.0..=40.0).contains(v),
            "knots are [key, speed_mps] with the key within ±1e7 (s or m) and speed 0–40 m/s",
            format!("[{}, {}]", short(k.to_string()), short(v.to_string())),
        )
        .map_err(|m| (field.clone(), m))?;
    }
    let knots: Vec<(f32, f32)> = rows.iter().map(|[k, v]| (*k as f32, *v as f32)).collect();
    SpeedProfile::new(basis, &knots).map_err(|e| (field, format!(": {e}")))
}

/// Range check helper: `Err(message)` saying what is allowed.
fn check(ok: bool, allowed: &str, value: impl std::fmt::Display) -> Result<(), String> {
    if ok {
        Ok(())
    } else {
        Err(format!("= {}: {allowed}", short(value.to_string())))
    }
}

pub(super) fn validate(
    raw: ScenarioFile,
    overrides: &[String],
    invalid: impl Fn(&str, String) -> ScenarioError,
    load_target: impl Fn(&str) -> Result<TargetModel, ScenarioError>,
) -> Result<Scenario, ScenarioError> {
    let at = |field: &str, r: Result<(), String>| r.map_err(|m| invalid(field, m));
    let finite_pos = |v: f64| v.is_finite() && v > 0.0;

    at(
        "name",
        check(
            !raw.name.trim().is_empty()
                && raw
                    .name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_'),
            "must be non-empty, letters, digits, '-' or '_' (it names the output folder)",
            format!("{:?}", raw.name),
        ),
    )?;
    at(
        "duration_s",
        check(
            // At least one camera frame: the run records round(duration × 15 Hz) frames.
            raw.duration_s.is_finite()
                && raw.duration_s >= 1.0 / f64::from(vehicle::CAMERA_HZ)
                && raw.duration_s <= 86_400.0,
            "must be at least one camera frame (1/15 s) and at most 86400 seconds",
            raw.duration_s,
        ),
    )?;

    // Route.
    let r = &raw.route;
    at(
        "route.lane_width_m",
        check(
            r.lane_width_m.is_finite() && (2.0..=6.0).contains(&r.lane_width_m),
            "must be 2–6 metres",
            r.lane_width_m,
        ),
    )?;
    at(
        "route.segments",
        check(!r.segments.is_empty(), "needs at least one segment", "[]"),
    )?;
    let mut segments = Vec::new();
    for (i, s) in r.segments.iter().enumerate() {
        let field = "route.segments";
        let seg = match (s.straight_m, s.arc_radius_m, s.arc_angle_deg) {
            (Some(length_m), None, None) => {
                at(
                    field,
                    check(
                        finite_pos(length_m) && length_m <= MAX_ROUTE_M,
                        &format!("segment {i}: straight_m must be > 0 and at most {MAX_ROUTE_M} m"),
                        length_m,
                    ),
                )?;
                RouteSegment::Straight { length_m }
            }
            (None, Some(radius_m), Some(angle_deg)) => {
                at(
                    field,
                    check(
                        (MIN_ARC_RADIUS_M..=MAX_ARC_RADIUS_M).contains(&radius_m),
                        &format!(
                            "segment {i}: arc_radius_m must be {MIN_ARC_RADIUS_M}–{MAX_ARC_RADIUS_M} m \
                             (at least the vehicles' turning circles)"
                        ),
                        radius_m,
                    ),
                )?;
                at(
                    field,
                    check(
                        angle_deg.is_finite() && angle_deg != 0.0 && angle_deg.abs() <= 360.0,
                        &format!("segment {i}: arc_angle_deg must be non-zero, at most 360"),
                        angle_deg,
                    ),
                )?;
                RouteSegment::Arc {
                    radius_m,
                    angle_deg,
                }
            }
            _ => {
                return Err(invalid(field, format!("segment {i}: give either `straight_m`, or both `arc_radius_m` and `arc_angle_deg`")));
            }
        };
        segments.push(seg);
    }
    let route = RouteSpec {
        segments,
        intersections_m: r.intersections_m.clone(),
        lane_width_m: r.lane_width_m,
    };
    let length: f64 = route
        .segments
        .iter()
        .map(|s| match s {
            RouteSegment::Straight { length_m } => *length_m,
            RouteSegment::Arc {
                radius_m,
                angle_deg,
            } => radius_m * angle_deg.abs().to_radians(),
        })
        .sum();
    at(
        "route.segments",
        check(
            length <= MAX_ROUTE_M,
            &format!("the route must be at most {MAX_ROUTE_M} m long"),
            format!("{length:.0} m in all"),
        ),
    )?;
    for &x in &route.intersections_m {
        at(
            "route.intersections_m",
            check(
                x.is_finite() && x >= 0.0 && x <= length,
                &format!("stations must lie on the route, 0–{length:.0} m"),
                x,
            ),
        )?;
    }

    // Lead.
    let l = &raw.lead;
    at(
        "lead.start_m",
        check(
            l.start_m.is_finite() && l.start_m >= 0.0 && l.start_m < length,
            &format!("must lie on the route, 0–{length:.0} m"),
            l.start_m,
        ),
    )?;
    let lead_profile = speed_profile("lead", &l.speed_basis, &l.speed_profile)
        .map_err(|(field, message)| invalid(&field, message))?;
    let lead_initial_speed_mps = l
        .initial_speed_mps
        .unwrap_or_else(|| l.speed_profile.first().map_or(0.0, |k| k[1]));
    at(
        "lead.initial_speed_mps",
        check(
            lead_initial_speed_mps.is_finite() && (0.0..=40.0).contains(&lead_initial_speed_mps),
            "must be 0–40 m/s",
            lead_initial_speed_mps,
        ),
    )?;

    // Chase and camera.
    let initial_gap_m = raw.chase.initial_gap_m.unwrap_or(10.0);
    at(
        "chase.initial_gap_m",
        check(
            initial_gap_m.is_finite() && (3.0..=60.0).contains(&initial_gap_m),
            "must be 3–60 metres",
            initial_gap_m,
        ),
    )?;
    // What the camera's own sections set, the controller's copy may not.
    let controller = &raw.chase.controller;
    let defaults = vehicle::ChaseControllerConfig::default();
    for (field, set, by) in [
        (
            "chase.controller.camera_mount",
            controller.camera_mount != defaults.camera_mount,
            "`[camera.mount]`",
        ),
        (
            "chase.controller.pan_head",
            controller.pan_head != defaults.pan_head,
            "`[camera.pan]`",
        ),
        (
            "chase.controller.half_fov_deg",
            controller.half_fov_deg != defaults.half_fov_deg,
            "the camera's focal length and pixel size",
        ),
    ] {
        if set {
            return Err(invalid(field, format!("is set by {by}; remove it here")));
        }
    }
    at(
        "camera.mount.right_m",
        check(
            raw.camera.mount.right_m == 0.0,
            "must be 0: the renderer mounts the camera on the centreline",
            raw.camera.mount.right_m,
        ),
    )?;
    raw.camera.mount.validate().map_err(|e| {
        let (field, message) = vehicle_error("camera.mount", &e);
        invalid(&field, message)
    })?;
    raw.camera.pan.validate().map_err(|e| {
        let (field, message) = vehicle_error("camera.pan", &e);
        invalid(&field, message)
    })?;
    let mut chase = raw.chase.controller.clone();
    if let vehicle::SpeedMode::Manual { profile } = &chase.speed_mode {
        profile.validate().map_err(|e| {
            let (field, message) = vehicle_error("chase.controller.speed_mode.profile.knots", &e);
            invalid(&field, message)
        })?;
    }
    chase.camera_mount = raw.camera.mount;
    chase.pan_head = raw.camera.pan.clone();
    if let Some(rows) = &raw.chase.speed_profile {
        // The paper's manual throttle: the chase's speed follows a scripted driver and only
        // its steering is closed-loop.
        if chase.speed_mode != vehicle::SpeedMode::GapKeeping {
            return Err(invalid(
                "chase.speed_profile",
                ": give either chase.speed_profile or chase.controller.speed_mode, not both".into(),
            ));
        }
        let profile = speed_profile("chase", &raw.chase.speed_basis, rows)
            .map_err(|(field, message)| invalid(&field, message))?;
        chase.speed_mode = vehicle::SpeedMode::Manual { profile };
    } else if raw.chase.speed_basis != "time" {
        return Err(invalid(
            "chase.speed_basis",
            ": applies only with chase.speed_profile".into(),
        ));
    }
    let c = &raw.camera;
    let defaults = Camera::default();
    let camera = Camera {
        focal_length_mm: c.focal_length_mm.unwrap_or(defaults.focal_length_mm),
        pixel_size_mm: c.pixel_size_mm.unwrap_or(defaults.pixel_size_mm),
        image_center_px: c.image_center_px.unwrap_or(defaults.image_center_px),
    };
    at(
        "camera.focal_length_mm",
        check(
            (FOCAL_LENGTH_MM[0]..=FOCAL_LENGTH_MM[1]).contains(&camera.focal_length_mm),
            &format!("must be {}–{} mm", FOCAL_LENGTH_MM[0], FOCAL_LENGTH_MM[1]),
            camera.focal_length_mm,
        ),
    )?;
    at(
        "camera.image_center_px",
        check(
            (0.0..=255.0).contains(&camera.image_center_px[0])
                && (0.0..=241.0).contains(&camera.image_center_px[1]),
            "must lie in the 256 × 242 frame: [0–255, 0–241] px",
            format!("{:?}", camera.image_center_px),
        ),
    )?;
    at(
        "camera.pixel_size_mm",
        check(
            camera
                .pixel_size_mm
                .iter()
                .all(|&p| finite_pos(p) && p < 1.0),
            "must be two sizes in (0, 1) mm",
            format!("{:?}", camera.pixel_size_mm),
        ),
    )?;
    // The narrower half of the field of view, for the curve-aware gap keeping.
    let [fx, _] = camera.focal_px();
    let [cx, _] = camera.image_center_px;
    let half_fov_deg = ((cx + 0.5).min(255.5 - cx) / fx).atan().to_degrees();
    at(
        "camera.focal_length_mm",
        check(
            (vehicle::MIN_HALF_FOV_DEG..=vehicle::MAX_HALF_FOV_DEG).contains(&half_fov_deg),
            &format!(
                "with the pixel size and principal point, must give a half field of view \
                 (the narrower side) of {}–{}°",
                vehicle::MIN_HALF_FOV_DEG,
                vehicle::MAX_HALF_FOV_DEG
            ),
            format!("{} mm ({half_fov_deg:.4}°)", camera.focal_length_mm),
        ),
    )?;
    chase.half_fov_deg = half_fov_deg as f32;

    // Tracker.
    let t = &raw.tracker;
    let mut tracker = TrackerConfig::default();
    if let Some(v) = t.lambda {
        tracker.lambda = v;
    }
    if let Some(v) = t.delta_deg {
        tracker.delta_deg = v;
    }
    if let Some(v) = t.zeta_px {
        tracker.zeta_px = v;
    }
    if let Some(v) = t.edge_threshold {
        tracker.edge_threshold = v;
    }
    if let Some(v) = t.lost_after_s {
        tracker.lost_after_s = v;
    }
    if let Some(v) = t.subpixel_edges {
        tracker.subpixel_edges = v;
    }
    if let Some(v) = &t.mode {
        tracker.mode = TrackerMode::parse(v).ok_or_else(|| {
            invalid(
                "tracker.mode",
                format!("= {v:?}: must be \"paper\" or \"robust\""),
            )
        })?;
    }
    let rate_hz = raw.loop_.rate_hz.unwrap_or(15.0);
    at(
        "loop.rate_hz",
        check(
            rate_hz == f64::from(vehicle::CAMERA_HZ),
            "must be 15: the camera rate the physics clock is built on (8 steps of 1/120 s)",
            rate_hz,
        ),
    )?;
    tracker.rate_hz = rate_hz;
    tracker.validate().map_err(|e| {
        invalid(
            &format!("tracker.{}", e.field),
            format!("= {}: {}", e.value, e.allowed),
        )
    })?;
    let init_offset = t.init_offset.unwrap_or([0.0; 3]);
    at(
        "tracker.init_offset",
        check(
            init_offset[..2]
                .iter()
                .all(|v| (-MAX_INIT_OFFSET_PX..=MAX_INIT_OFFSET_PX).contains(v))
                && init_offset[2] > -0.5
                && init_offset[2] <= 1.0,
            &format!(
                "is [dx_px, dy_px, dscale] with |dx|, |dy| at most {MAX_INIT_OFFSET_PX} px \
                 and dscale in (-0.5, 1]"
            ),
            format!("{init_offset:?}"),
        ),
    )?;
    let target = load_target(&t.target)?;

    // Loop.
    let lp = &raw.loop_;
    let delay = DelayLineConfig {
        latency_ms: lp.latency_ms.unwrap_or(128.0),
        jitter_ms: lp.jitter_ms.unwrap_or(0.0),
        drop_probability: lp.drop_probability.unwrap_or(0.0),
        seed: raw.seed,
    };
    at(
        "loop.latency_ms",
        check(
            delay.latency_ms.is_finite() && (0.0..=2000.0).contains(&delay.latency_ms),
            "must be 0–2000 ms",
            delay.latency_ms,
        ),
    )?;
    at(
        "loop.jitter_ms",
        check(
            delay.jitter_ms.is_finite()
                && delay.jitter_ms >= 0.0
                && delay.jitter_ms <= delay.latency_ms,
            "must be ≥ 0 and at most latency_ms",
            delay.jitter_ms,
        ),
    )?;
    at(
        "loop.drop_probability",
        check(
            (0.0..1.0).contains(&delay.drop_probability),
            "must be in [0, 1)",
            delay.drop_probability,
        ),
    )?;

    // Environment.
    let e = &raw.environment;
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
    at(
        "environment.sun.azimuth_deg",
        check(
            (-360.0..=360.0).contains(&sun.azimuth_deg),
            "must be -360–360 degrees",
            sun.azimuth_deg,
        ),
    )?;
    at(
        "environment.sun.elevation_deg",
        check(
            sun.elevation_deg > 0.0 && sun.elevation_deg <= 90.0,
            "must be in (0, 90] degrees",
            sun.elevation_deg,
        ),
    )?;
    at(
        "environment.sun.strength",
        check(
            (0.0..=2.0).contains(&sun.strength),
            "must be 0–2",
            sun.strength,
        ),
    )?;
    at(
        "environment.sun.ambient",
        check(
            (0.0..=2.0).contains(&sun.ambient),
            "must be 0–2",
            sun.ambient,
        ),
    )?;
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
            at(
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
    // Controlled distractors and overpasses.
    let mut distractors = Vec::new();
    for (i, d) in e.distractors.iter().enumerate() {
        let field = |name: &str| format!("environment.distractors[{i}].{name}");
        let (kind, wanted) = match d.kind.as_str() {
            "pole" => (DistractorKind::Pole, Some(tracker::Orientation::Vertical)),
            "wire" => (DistractorKind::Wire, Some(tracker::Orientation::Horizontal)),
            // Placed once the route is known (below): the fin depends on the sun's direction
            // in the board's frame at the start.
            "shadow" => (
                DistractorKind::Shadow {
                    root_m: f64::NAN,
                    depth_m: f64::NAN,
                },
                None,
            ),
            other => {
                return Err(invalid(
                    &field("kind"),
                    format!("= {other:?}: must be \"pole\", \"wire\" or \"shadow\""),
                ))
            }
        };
        let segments = target.segments().len();
        at(
            &field("feature"),
            check(
                d.feature < segments,
                &format!("must be a segment of the target, 0–{}", segments - 1),
                d.feature,
            ),
        )?;
        let orientation = target
            .orientations()
            .nth(d.feature)
            .expect("feature index checked");
        if let Some(wanted) = wanted.filter(|&w| w != orientation) {
            return Err(invalid(
                &field("feature"),
                format!(
                    "= {}: segment {} is {}, and a {} runs beside a {} one",
                    d.feature,
                    d.feature,
                    orientation.as_str(),
                    d.kind,
                    wanted.as_str()
                ),
            ));
        }
        let px_m = target.nominal_range_m() / camera.focal_px()[0];
        let offset_m = match (d.offset_px, d.offset_m) {
            (Some(px), None) => {
                at(
                    &field("offset_px"),
                    check(
                        px.is_finite() && px.abs() <= 60.0,
                        "must be within ±60 px",
                        px,
                    ),
                )?;
                px * px_m
            }
            (None, Some(m)) => {
                at(
                    &field("offset_m"),
                    check(m.is_finite() && m.abs() <= 2.0, "must be within ±2 m", m),
                )?;
                m
            }
            _ => {
                return Err(invalid(
                    &field("offset_px"),
                    ": give exactly one of offset_px and offset_m".into(),
                ))
            }
        };
        let width_m = d.width_m.unwrap_or(match kind {
            DistractorKind::Wire => 0.02,
            _ => 0.05,
        });
        at(
            &field("width_m"),
            check(
                (0.005..=0.5).contains(&width_m),
                "must be 0.005–0.5 m",
                width_m,
            ),
        )?;
        let albedo = d.albedo.unwrap_or(0.1);
        at(
            &field("albedo"),
            check((0.0..=1.0).contains(&albedo), "must be 0–1", albedo),
        )?;
        distractors.push(Distractor {
            kind,
            feature: d.feature,
            offset_m,
            width_m,
            albedo,
        });
    }
    let mut placements = Vec::new();
    for (i, o) in e.overpasses.iter().enumerate() {
        let field = |name: &str| format!("environment.overpasses[{i}].{name}");
        at(
            &field("station_m"),
            check(
                o.station_m.is_finite() && (0.0..=length).contains(&o.station_m),
                &format!("must lie on the route, 0–{length:.0} m"),
                o.station_m,
            ),
        )?;
        let deck_m = o.deck_m.unwrap_or(10.0);
        at(
            &field("deck_m"),
            check((2.0..=60.0).contains(&deck_m), "must be 2–60 m", deck_m),
        )?;
        let height_m = o.height_m.unwrap_or(5.5);
        at(
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
    let mut sensor = Sensor::default();
    if let Some(v) = e.sensor.gain {
        sensor.gain = v;
    }
    if let Some(v) = e.sensor.noise_sigma_grey {
        sensor.noise_sigma_grey = v;
    }
    sensor.blur_sigma_px = e.sensor.blur_sigma_px;
    at(
        "environment.sensor.gain",
        check(
            sensor.gain.is_finite() && (0.05..=20.0).contains(&sensor.gain),
            "must be 0.05–20",
            sensor.gain,
        ),
    )?;
    at(
        "environment.sensor.noise_sigma_grey",
        check(
            sensor.noise_sigma_grey.is_finite() && (0.0..=64.0).contains(&sensor.noise_sigma_grey),
            "must be 0–64 grey levels",
            sensor.noise_sigma_grey,
        ),
    )?;
    if let Some(sigma) = sensor.blur_sigma_px {
        at(
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
    at(
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
        at(
            "environment.sensor.shot_noise_full_well_e",
            check(
                (100.0..=1e7).contains(&full_well_e),
                "must be 100–1e7 electrons",
                full_well_e,
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
            at(
                &format!("environment.sensor.auto_gain.{field}"),
                check(
                    (lo..=hi).contains(&*into),
                    &format!("must be {lo}–{hi}{unit}"),
                    *into,
                ),
            )?;
        }
        sensor.auto_gain = Some(auto_gain);
    }

    let road_surface = match e.road.surface.as_deref() {
        None => RoadSurface::default(),
        Some(name) => RoadSurface::parse(name).ok_or_else(|| {
            invalid(
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
    at(
        "environment.textures.contrast",
        check(
            (0.0..=2.0).contains(&textures.contrast),
            "must be 0–2",
            textures.contrast,
        ),
    )?;

    // Expectations.
    let x = &raw.expect;
    if let Some([lo, hi]) = x.gap_band_m {
        at(
            "expect.gap_band_m",
            check(
                lo.is_finite() && hi.is_finite() && 0.0 <= lo && lo < hi,
                "must be [min, max] metres with 0 ≤ min < max",
                format!("[{}, {}]", short(lo.to_string()), short(hi.to_string())),
            ),
        )?;
    }
    for (field, v) in [
        (
            "expect.max_time_outside_gap_band_s",
            x.max_time_outside_gap_band_s,
        ),
        ("expect.max_lost_s", x.max_lost_s),
        ("expect.max_lateral_deviation_m", x.max_lateral_deviation_m),
        ("expect.min_distance_m", x.min_distance_m),
        ("expect.max_range_error_p95_m", x.max_range_error_p95_m),
    ] {
        if let Some(v) = v {
            at(field, check(v.is_finite() && v >= 0.0, "must be ≥ 0", v))?;
        }
    }

    // What the closed loop builds from all this, built here so that `check`, a sweep's
    // pre-flight and `run` refuse the same scenarios, and `ClosedLoop::new` refuses none.
    let scene_route = crate::scene::Route::new(route.clone());
    // Shadow distractors: the fin that puts the shadow's edge at the offset, for the sun's
    // direction in the board's frame with the lead on its starting heading.
    for (i, d) in distractors.iter_mut().enumerate() {
        if let DistractorKind::Shadow { root_m, depth_m } = &mut d.kind {
            let lead_rotation = scene_route.pose_at(l.start_m, 0.0).rotation;
            let board_rotation =
                crate::scene::lead_from_target_of(&crate::scene::LeadVehicle::default()).rotation;
            let s = (lead_rotation * board_rotation).inverse()
                * nalgebra::Vector3::from(sun.direction());
            let field = format!("environment.distractors[{i}].kind");
            if s.z < 0.05 {
                return Err(invalid(
                    &field,
                    ": a shadow on the board needs the sun in front of it at the start, and \
                     it is behind or grazing it: turn the sun (environment.sun.azimuth_deg)"
                        .into(),
                ));
            }
            let slope = match target.orientations().nth(d.feature) {
                Some(tracker::Orientation::Vertical) => s.x / s.z,
                _ => s.y / s.z,
            };
            if slope.abs() < 0.1 {
                return Err(invalid(
                    &field,
                    ": the sun shines almost straight at the board, so no fin can cast a \
                     shadow edge across this feature: turn the sun"
                        .into(),
                ));
            }
            // A shadow band SHADOW_BAND_M wide: the fin stands that far out divided by the
            // slope, and its root lies the band's width from the edge, towards the sun.
            let (edge, _) = crate::scene::distractor_near_side(&target, d.feature, d.offset_m);
            *depth_m = (SHADOW_BAND_M / slope.abs()).min(3.0);
            *root_m = edge + *depth_m * slope;
        }
    }
    let (points, reach_m) =
        crate::closed_loop::lane_polyline(&scene_route, 0.5 * route.lane_width_m);
    let drivers_route =
        vehicle::Route::new(points).map_err(|e| invalid("route.segments", format!(": {e}")))?;
    let chase_start_m =
        crate::closed_loop::chase_start_m(l.start_m, initial_gap_m, chase.camera_mount.forward_m);
    if chase_start_m < 0.0 {
        // Three fields decide it; blame an override among them if there is one.
        let field = ["chase.initial_gap_m", "camera.mount.forward_m"]
            .into_iter()
            .find(|f| overrides.iter().any(|a| override_names(a, f)))
            .unwrap_or("lead.start_m");
        return Err(invalid(
            field,
            format!(
                "puts the chase vehicle {:.1} m before the route's start; raise lead.start_m to \
                 at least {:.1}",
                -chase_start_m,
                l.start_m - chase_start_m
            ),
        ));
    }
    let mut base = WorldConfig::default();
    base.ground.bumps = e.bumps.clone();
    let world = crate::closed_loop::world_config(&base, reach_m);
    vehicle::Ground::new(&world.ground).map_err(|e| match e {
        vehicle::VehicleError::InvalidParameter { field, .. } if field.starts_with("bumps.") => {
            let (field, message) = vehicle_error("environment", &e);
            invalid(&field, message)
        }
        other => invalid("route.segments", format!(": the physics ground: {other}")),
    })?;
    let v0 = lead_initial_speed_mps as f32;
    for (prefix, lookahead, gains) in [
        ("chase.controller", &chase.lookahead, &chase.speed_gains),
        ("lead.driver", &l.driver.lookahead, &l.driver.speed_gains),
    ] {
        check_lookahead(lookahead)
            .map_err(|(field, message)| invalid(&format!("{prefix}.lookahead.{field}"), message))?;
        check_speed_gains(gains).map_err(|(field, message)| {
            invalid(&format!("{prefix}.speed_gains.{field}"), message)
        })?;
    }
    at(
        "chase.controller.max_breadcrumbs",
        check(
            (2..=MAX_BREADCRUMBS).contains(&chase.max_breadcrumbs),
            &format!("must be 2–{MAX_BREADCRUMBS}"),
            chase.max_breadcrumbs,
        ),
    )?;
    chase.gap_keeper.validate().map_err(|e| {
        let (field, message) = vehicle_error("chase.controller.gap_keeper", &e);
        invalid(&field, message)
    })?;
    vehicle::ChaseController::new(chase.clone(), &vehicle::VehicleParams::hmmwv_m998(), v0)
        .map_err(|e| {
            let (field, message) = vehicle_error("chase.controller", &e);
            invalid(&field, message)
        })?;
    vehicle::LeadDriver::new(
        drivers_route.clone(),
        lead_profile.clone(),
        l.driver.clone(),
        &vehicle::VehicleParams::pickup(),
    )
    .map_err(|e| {
        let (field, message) = vehicle_error("lead.driver", &e);
        invalid(&field, message)
    })?;
    vehicle::DelayLine::<()>::new(&delay).map_err(|e| {
        let (field, message) = vehicle_error("loop", &e);
        invalid(&field, message)
    })?;

    let resolved = raw.clone();
    let ground = vehicle::Ground::new(&world.ground)
        .map_err(|e| invalid("route.segments", format!(": the physics ground: {e}")))?;
    let scenario = Scenario {
        chase_start_m,
        resolved,
        overrides: overrides.to_vec(),
        name: raw.name,
        description: raw.description,
        path: None,
        duration_s: raw.duration_s,
        seed: raw.seed,
        route,
        lead_start_m: l.start_m,
        lead_initial_speed_mps,
        lead_profile,
        lead_driver: l.driver.clone(),
        initial_gap_m,
        chase,
        camera,
        tracker,
        target,
        init_offset,
        delay,
        world,
        sun,
        densities,
        placements,
        distractors,
        sensor,
        road_surface,
        textures,
        expect: raw.expect,
    };
    // The last of the loop's set-up checks: the scene, and the target in view at t = 0.
    crate::closed_loop::check_start(&scenario, &drivers_route, &ground).map_err(
        |(field, message)| {
            // What decides the first view; blame an override among them if there is one.
            let field = [
                "camera.mount",
                "camera.focal_length_mm",
                "camera.pixel_size_mm",
                "camera.image_center_px",
                "chase.initial_gap_m",
                "lead.start_m",
                "route.segments",
                "environment",
            ]
            .into_iter()
            .find(|f| overrides.iter().any(|a| override_names(a, f)))
            .unwrap_or(field);
            invalid(field, message)
        },
    )?;
    Ok(scenario)
}

//! `[chase]` and `[camera]`: the chase's controller, its gap at the start, and the camera
//! on it (intrinsics, mount and pan head), which the controller's copy must not set.

use super::lead::speed_profile;
use super::{
    check, vehicle_error, Blame, FOCAL_LENGTH_MM, MAX_BREADCRUMBS, MAX_INITIAL_GAP_M,
    MAX_PLACED_GAP_M,
};
use crate::scenario::{ChaseFile, ScenarioError, ScenarioFile};
use tracker::Camera;
use vehicle::ChaseControllerConfig;

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

/// A chase starting far behind its lead, more than [`MAX_PLACED_GAP_M`]: no teleoperator
/// places the tracker on a target that far off, so the chase cruises at its cruise speed
/// (`chase.controller.cruise_speed_mps`, which this needs) and its tracker searches
/// (`tracker.start = "search"`, which this needs) until it finds the lead, and then
/// follows it.
pub(super) fn far_start(
    raw: &ScenarioFile,
    initial_gap_m: f64,
    search_start: bool,
    f: &Blame,
) -> Result<(), ScenarioError> {
    if initial_gap_m <= MAX_PLACED_GAP_M {
        return Ok(());
    }
    if raw.chase.controller.cruise_speed_mps.is_none() {
        return Err(f.invalid(
            "chase.controller.cruise_speed_mps",
            format!(
                "is needed with chase.initial_gap_m = {initial_gap_m} (over \
                 {MAX_PLACED_GAP_M} m): a chase that starts far behind cruises at it until \
                 its tracker finds the lead"
            ),
        ));
    }
    if !search_start {
        return Err(f.invalid(
            "tracker.start",
            format!(
                "must be \"search\" with chase.initial_gap_m = {initial_gap_m} (over \
                 {MAX_PLACED_GAP_M} m): no operator places the tracker on a target that far \
                 off; it searches until it finds it"
            ),
        ));
    }
    Ok(())
}

/// The chase's controller (with the camera's mount, pan head and field of view), the
/// camera, and the gap at the start, metres.
/// The chase's speed at t = 0, m/s: its cruise speed with `[chase] start_at_cruise_speed`
/// (refused without a `controller.cruise_speed_mps`), else the lead's initial speed
/// `lead_initial_speed_mps`.
pub(super) fn initial_speed(
    c: &ChaseFile,
    lead_initial_speed_mps: f64,
    f: &Blame,
) -> Result<f64, ScenarioError> {
    if !c.start_at_cruise_speed {
        return Ok(lead_initial_speed_mps);
    }
    match c.controller.cruise_speed_mps {
        Some(v) => Ok(f64::from(v)),
        None => Err(f.invalid(
            "chase.start_at_cruise_speed",
            "needs a cruise speed to start at (chase.controller.cruise_speed_mps)".into(),
        )),
    }
}

pub(super) fn chase_and_camera(
    raw: &ScenarioFile,
    f: &Blame,
) -> Result<(ChaseControllerConfig, Camera, f64), ScenarioError> {
    let finite_pos = |v: f64| v.is_finite() && v > 0.0;
    let initial_gap_m = raw.chase.initial_gap_m.unwrap_or(10.0);
    f.at(
        "chase.initial_gap_m",
        check(
            initial_gap_m.is_finite() && (3.0..=MAX_INITIAL_GAP_M).contains(&initial_gap_m),
            &format!(
                "must be 3–{MAX_INITIAL_GAP_M} metres (the renderer's far plane: nothing \
                 further is drawn)"
            ),
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
            return Err(f.invalid(field, format!("is set by {by}; remove it here")));
        }
    }
    f.at(
        "camera.mount.right_m",
        check(
            raw.camera.mount.right_m == 0.0,
            "must be 0: the renderer mounts the camera on the centreline",
            raw.camera.mount.right_m,
        ),
    )?;
    raw.camera.mount.validate().map_err(|e| {
        let (field, message) = vehicle_error("camera.mount", &e);
        f.invalid(&field, message)
    })?;
    raw.camera.pan.validate().map_err(|e| {
        let (field, message) = vehicle_error("camera.pan", &e);
        f.invalid(&field, message)
    })?;
    let mut chase = raw.chase.controller.clone();
    if let vehicle::SpeedMode::Manual { profile } = &chase.speed_mode {
        profile.validate().map_err(|e| {
            let (field, message) = vehicle_error("chase.controller.speed_mode.profile.knots", &e);
            f.invalid(&field, message)
        })?;
    }
    chase.camera_mount = raw.camera.mount;
    chase.pan_head = raw.camera.pan.clone();
    if let Some(rows) = &raw.chase.speed_profile {
        // The paper's manual throttle: the chase's speed follows a scripted driver and only
        // its steering is closed-loop.
        if chase.speed_mode != vehicle::SpeedMode::GapKeeping {
            return Err(f.invalid(
                "chase.speed_profile",
                ": give either chase.speed_profile or chase.controller.speed_mode, not both".into(),
            ));
        }
        let profile = speed_profile("chase", &raw.chase.speed_basis, rows)
            .map_err(|(field, message)| f.invalid(&field, message))?;
        chase.speed_mode = vehicle::SpeedMode::Manual { profile };
    } else if raw.chase.speed_basis != "time" {
        return Err(f.invalid(
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
    f.at(
        "camera.focal_length_mm",
        check(
            (FOCAL_LENGTH_MM[0]..=FOCAL_LENGTH_MM[1]).contains(&camera.focal_length_mm),
            &format!("must be {}–{} mm", FOCAL_LENGTH_MM[0], FOCAL_LENGTH_MM[1]),
            camera.focal_length_mm,
        ),
    )?;
    f.at(
        "camera.image_center_px",
        check(
            (0.0..=255.0).contains(&camera.image_center_px[0])
                && (0.0..=241.0).contains(&camera.image_center_px[1]),
            "must lie in the 256 × 242 frame: [0–255, 0–241] px",
            format!("{:?}", camera.image_center_px),
        ),
    )?;
    f.at(
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
    f.at(
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

    Ok((chase, camera, initial_gap_m))
}

/// The look-ahead, speed loop, breadcrumbs and gap keeper of both drivers.
pub(super) fn tuning(
    chase: &ChaseControllerConfig,
    lead: &vehicle::LeadDriverConfig,
    f: &Blame,
) -> Result<(), ScenarioError> {
    for (prefix, lookahead, gains) in [
        ("chase.controller", &chase.lookahead, &chase.speed_gains),
        ("lead.driver", &lead.lookahead, &lead.speed_gains),
    ] {
        check_lookahead(lookahead).map_err(|(field, message)| {
            f.invalid(&format!("{prefix}.lookahead.{field}"), message)
        })?;
        check_speed_gains(gains).map_err(|(field, message)| {
            f.invalid(&format!("{prefix}.speed_gains.{field}"), message)
        })?;
    }
    f.at(
        "chase.controller.max_breadcrumbs",
        check(
            (2..=MAX_BREADCRUMBS).contains(&chase.max_breadcrumbs),
            &format!("must be 2–{MAX_BREADCRUMBS}"),
            chase.max_breadcrumbs,
        ),
    )?;
    chase.gap_keeper.validate().map_err(|e| {
        let (field, message) = vehicle_error("chase.controller.gap_keeper", &e);
        f.invalid(&field, message)
    })?;
    Ok(())
}

/// `[chase.headlamps]`: the beam, or `None` with them off.
pub(super) fn headlamps(
    c: &ChaseFile,
    f: &Blame,
) -> Result<Option<sim_render::Beam>, ScenarioError> {
    let Some(h) = &c.headlamps else {
        return Ok(None);
    };
    match h.beam.as_str() {
        "off" => Ok(None),
        "low" => Ok(Some(sim_render::Beam::Low)),
        "high" => Ok(Some(sim_render::Beam::High)),
        other => Err(f.invalid(
            "chase.headlamps.beam",
            format!("= {other:?}: must be \"off\", \"low\" or \"high\""),
        )),
    }
}

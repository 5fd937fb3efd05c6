//! `[tracker]` and `[loop]`: the tracker's settings, the teleoperator's placement error,
//! the target model, and the delay line between the tracker and the controller.

use super::{check, Blame, MAX_INIT_OFFSET_PX};
use crate::scenario::{ScenarioError, ScenarioFile};
use tracker::{TargetModel, TrackerConfig, TrackerMode};
use vehicle::DelayLineConfig;

/// The tracker's settings, the placement error `[dx_px, dy_px, dscale]`, the target, and
/// whether the tracker starts by searching (`tracker.start = "search"`).
pub(super) fn tracker(
    raw: &ScenarioFile,
    f: &Blame,
    load_target: impl Fn(&str) -> Result<TargetModel, ScenarioError>,
) -> Result<(TrackerConfig, [f64; 3], TargetModel, bool), ScenarioError> {
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
            f.invalid(
                "tracker.mode",
                format!("= {v:?}: must be \"paper\" or \"robust\""),
            )
        })?;
    }
    let rate_hz = raw.loop_.rate_hz.unwrap_or(15.0);
    f.at(
        "loop.rate_hz",
        check(
            rate_hz == f64::from(vehicle::CAMERA_HZ),
            "must be 15: the camera rate the physics clock is built on (8 steps of 1/120 s)",
            rate_hz,
        ),
    )?;
    tracker.rate_hz = rate_hz;
    tracker.validate().map_err(|e| {
        f.invalid(
            &format!("tracker.{}", e.field),
            format!("= {}: {}", e.value, e.allowed),
        )
    })?;
    let init_offset = t.init_offset.unwrap_or([0.0; 3]);
    f.at(
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
    let search = match t.start.as_deref() {
        None | Some("operator") => false,
        Some("search") => true,
        Some(v) => {
            return Err(f.invalid(
                "tracker.start",
                format!("= {v:?}: must be \"operator\" or \"search\""),
            ))
        }
    };
    let target = load_target(&t.target)?;
    Ok((tracker, init_offset, target, search))
}

/// The delay line of `[loop]`.
pub(super) fn delay(raw: &ScenarioFile, f: &Blame) -> Result<DelayLineConfig, ScenarioError> {
    let lp = &raw.loop_;
    let delay = DelayLineConfig {
        latency_ms: lp.latency_ms.unwrap_or(128.0),
        jitter_ms: lp.jitter_ms.unwrap_or(0.0),
        drop_probability: lp.drop_probability.unwrap_or(0.0),
        seed: raw.seed,
    };
    f.at(
        "loop.latency_ms",
        check(
            delay.latency_ms.is_finite() && (0.0..=2000.0).contains(&delay.latency_ms),
            "must be 0–2000 ms",
            delay.latency_ms,
        ),
    )?;
    f.at(
        "loop.jitter_ms",
        check(
            delay.jitter_ms.is_finite()
                && delay.jitter_ms >= 0.0
                && delay.jitter_ms <= delay.latency_ms,
            "must be ≥ 0 and at most latency_ms",
            delay.jitter_ms,
        ),
    )?;
    f.at(
        "loop.drop_probability",
        check(
            (0.0..1.0).contains(&delay.drop_probability),
            "must be in [0, 1)",
            delay.drop_probability,
        ),
    )?;

    Ok(delay)
}

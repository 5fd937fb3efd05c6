//! `[[environment.distractors]]`: poles, wires and shadows held beside a feature of the
//! target, moving with the lead.

use super::{check, Blame};
use crate::scenario::{DistractorFile, ScenarioError};
use sim_render::{Distractor, DistractorKind, RouteSpec, Sun};
use tracker::{Camera, TargetModel};

/// Width of a shadow distractor's band on the board, metres: wider than the target's
/// spacing of parallel features, so that one edge of it lies near the chosen feature.
const SHADOW_BAND_M: f64 = 0.5;

/// The distractors, with each shadow's fin placed for the sun at the lead's start
/// (`lead_start_m` along `route`).
pub(super) fn distractors(
    given: &[DistractorFile],
    target: &TargetModel,
    camera: &Camera,
    route: &RouteSpec,
    lead_start_m: f64,
    sun: &Sun,
    f: &Blame,
) -> Result<Vec<Distractor>, ScenarioError> {
    let mut distractors = Vec::new();
    for (i, d) in given.iter().enumerate() {
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
                return Err(f.invalid(
                    &field("kind"),
                    format!("= {other:?}: must be \"pole\", \"wire\" or \"shadow\""),
                ))
            }
        };
        let segments = target.segments().len();
        f.at(
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
            return Err(f.invalid(
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
                f.at(
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
                f.at(
                    &field("offset_m"),
                    check(m.is_finite() && m.abs() <= 2.0, "must be within ±2 m", m),
                )?;
                m
            }
            _ => {
                return Err(f.invalid(
                    &field("offset_px"),
                    ": give exactly one of offset_px and offset_m".into(),
                ))
            }
        };
        let width_m = d.width_m.unwrap_or(match kind {
            DistractorKind::Wire => 0.02,
            _ => 0.05,
        });
        f.at(
            &field("width_m"),
            check(
                (0.005..=0.5).contains(&width_m),
                "must be 0.005–0.5 m",
                width_m,
            ),
        )?;
        let albedo = d.albedo.unwrap_or(0.1);
        f.at(
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
    let scene_route = sim_render::Route::new(route.clone());
    // Shadow distractors: the fin that puts the shadow's edge at the offset, for the sun's
    // direction in the board's frame with the lead on its starting heading.
    for (i, d) in distractors.iter_mut().enumerate() {
        if let DistractorKind::Shadow { root_m, depth_m } = &mut d.kind {
            let lead_rotation = scene_route.pose_at(lead_start_m, 0.0).rotation;
            let board_rotation =
                sim_render::lead_from_target_of(&sim_render::LeadVehicle::default()).rotation;
            let s = (lead_rotation * board_rotation).inverse()
                * nalgebra::Vector3::from(sun.direction());
            let field = format!("environment.distractors[{i}].kind");
            if sun.elevation_deg <= 0.0 {
                return Err(f.invalid(
                    &field,
                    ": a shadow on the board needs the sun above the horizon \
                     (environment.sun.elevation_deg > 0)"
                        .into(),
                ));
            }
            if s.z < 0.05 {
                return Err(f.invalid(
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
                return Err(f.invalid(
                    &field,
                    ": the sun shines almost straight at the board, so no fin can cast a \
                     shadow edge across this feature: turn the sun"
                        .into(),
                ));
            }
            // A shadow band SHADOW_BAND_M wide: the fin stands that far out divided by the
            // slope, and its root lies the band's width from the edge, towards the sun.
            let (edge, _) = sim_render::distractor_near_side(target, d.feature, d.offset_m);
            *depth_m = (SHADOW_BAND_M / slope.abs()).min(3.0);
            *root_m = edge + *depth_m * slope;
        }
    }
    Ok(distractors)
}

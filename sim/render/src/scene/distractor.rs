//! Controlled distractors: poles, wires and shadow-casting fins that move with the lead,
//! just in front of the board, beside the target's features.

use super::description::{distractor_near_side, Distractor, DistractorKind, LeadVehicle};
use super::mesh::Mesh;
use super::object_slot::ObjectSlot;
use super::target_board::{board_rect, on_lead, BOARD_ALBEDO};
use nalgebra::Isometry3;
use tracker::TargetModel;

/// How far a controlled distractor stands in front of the board, metres.
const DISTRACTOR_STANDOFF_M: f64 = 0.02;
/// Height of a distractor pole, metres (a telephone pole's).
const DISTRACTOR_POLE_M: f64 = 9.0;
/// How far a distractor wire runs to each side of the target's centre, metres.
const DISTRACTOR_REACH_M: f64 = 6.0;

/// The lead's controlled distractors, in the target frame mapped into the lead frame by
/// `lead_from_target`: a pole or a wire as a bar just in front of the board, a shadow as
/// the fin that casts it.
pub(super) fn distractors(
    mesh: &mut Mesh,
    lead: &LeadVehicle,
    lead_from_target: &Isometry3<f64>,
    target: &TargetModel,
) {
    for d in &lead.distractors {
        let (near, outward) = distractor_near_side(target, d.feature, d.offset_m);
        let far = near + outward * d.width_m;
        let (a, b) = (near.min(far), near.max(far));
        let ground = -lead.board_centre_height_m;
        let bounds = match d.kind {
            DistractorKind::Pole => [a, ground, b, ground + DISTRACTOR_POLE_M],
            DistractorKind::Wire => [-DISTRACTOR_REACH_M, a, DISTRACTOR_REACH_M, b],
            DistractorKind::Shadow { root_m, depth_m } => {
                fin(mesh, lead_from_target, target, d, ground, [root_m, depth_m]);
                continue;
            }
        };
        board_rect(
            mesh,
            lead_from_target,
            bounds,
            DISTRACTOR_STANDOFF_M,
            d.albedo,
        );
    }
}

/// A shadow distractor's fin, standing `depth_m` out of the board at `root_m` across its
/// feature (`[root_m, depth_m]`), from the ground (`ground`, in the target's frame) up
/// beside a vertical feature, across the board beside a horizontal one.
fn fin(
    mesh: &mut Mesh,
    lead_from_target: &Isometry3<f64>,
    target: &TargetModel,
    d: &Distractor,
    ground: f64,
    [root_m, depth_m]: [f64; 2],
) {
    let put = |x: f64, y: f64, z: f64| on_lead(lead_from_target, x, y, z);
    // A fin 1 cm thick, as the board's light paint, both faces drawn so that it casts a
    // shadow whichever side the sun is on.
    let vertical = target.orientations().nth(d.feature) == Some(tracker::Orientation::Vertical);
    let (along_lo, along_hi) = if vertical {
        (ground, ground + 4.0)
    } else {
        (-DISTRACTOR_REACH_M, DISTRACTOR_REACH_M)
    };
    for side in [-0.005, 0.005] {
        let c = root_m + side;
        let corners = if vertical {
            [
                put(c, along_lo, 0.0),
                put(c, along_lo, depth_m),
                put(c, along_hi, depth_m),
                put(c, along_hi, 0.0),
            ]
        } else {
            [
                put(along_lo, c, 0.0),
                put(along_hi, c, 0.0),
                put(along_hi, c, depth_m),
                put(along_lo, c, depth_m),
            ]
        };
        let corners = if side < 0.0 {
            [corners[3], corners[2], corners[1], corners[0]]
        } else {
            corners
        };
        mesh.polygon(&corners, BOARD_ALBEDO, ObjectSlot::LEAD);
    }
}

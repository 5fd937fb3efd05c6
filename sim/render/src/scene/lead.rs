//! The lead vehicle: a box truck with the target board on its back door and the controlled
//! distractors in front of it, in the lead's frame.

use super::description::SceneDescription;
use super::distractor::distractors;
use super::mesh::Mesh;
use super::object_slot::ObjectSlot;
use super::tail_lamps::TailLamps;
use super::target_board::{lead_from_target_of, paint};

/// The lead vehicle (a box truck) with the target board on its back door, painted by the
/// paint rule, and its controlled distractors, in the lead's frame.
pub(super) fn lead_vehicle(description: &SceneDescription) -> Mesh {
    let lead = &description.lead;
    let slot = ObjectSlot::LEAD;
    let (hl, hw) = (0.5 * lead.length_m, 0.5 * lead.width_m);
    let mut mesh = Mesh::default();
    mesh.aabb([-hl, 0.55, -hw], [hl, lead.height_m, hw], 0.55, slot);
    mesh.aabb(
        [hl, 0.55, -hw + 0.05],
        [hl + 1.6, 2.1, hw - 0.05],
        0.45,
        slot,
    );
    for (x, z) in [
        (-hl + 0.9, -hw + 0.3),
        (-hl + 0.9, hw - 0.3),
        (hl + 0.8, -hw + 0.3),
        (hl + 0.8, hw - 0.3),
    ] {
        mesh.aabb(
            [x - 0.45, 0.0, z - 0.2],
            [x + 0.45, 0.9, z + 0.2],
            0.05,
            slot,
        );
    }
    // The board, in the target frame, mapped into the lead frame.
    let to_lead = lead_from_target_of(lead);
    paint(&mut mesh, &to_lead, &description.target);
    // Controlled distractors, just in front of the board.
    distractors(&mut mesh, lead, &to_lead, &description.target);
    if lead.tail_lamps {
        TailLamps::add_to_lead(&mut mesh, slot, lead, &description.target);
    }
    mesh
}

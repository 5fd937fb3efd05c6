//! Moving objects: geometry in its own frame, placed each frame by a transform.

use super::mesh::Mesh;
use std::ops::Range;

/// What moves a dynamic object.
#[derive(Clone, Debug, PartialEq)]
pub enum Motion {
    /// Rigidly attached to the chase vehicle.
    Chase,
    /// Rigidly attached to the lead vehicle.
    Lead,
    /// Driving the opposite lane: station `start_m − speed_m_s · t`.
    Oncoming {
        /// Station at t = 0, metres.
        start_m: f64,
        /// Speed, m/s.
        speed_m_s: f64,
    },
    /// Actor `k` of the description (`SceneDescription::actors`), placed each frame where
    /// the caller poses it (`FrameInput::world_from_actors`).
    Actor(usize),
}

/// A moving object: geometry in its own frame (x forward, y up, z right, origin on the
/// ground), placed each frame by a transform.
#[derive(Clone, Debug, PartialEq)]
pub struct DynamicObject {
    /// Its slot (see [`ObjectSlot`](crate::scene::ObjectSlot)).
    pub slot: u32,
    /// Range of the scene's indices (see [`Scene`](crate::scene::Scene)).
    pub indices: Range<u32>,
    /// Bounding sphere centre, object frame.
    pub centre: [f64; 3],
    /// Bounding sphere radius, metres.
    pub radius: f64,
    /// Whether it is drawn into the shadow map.
    pub casts_shadow: bool,
    /// How it moves.
    pub motion: Motion,
}

impl DynamicObject {
    /// `part` (in the object's frame) appended to `mesh`, as the object in `slot` that
    /// `motion` moves.
    pub(super) fn appended(
        mesh: &mut Mesh,
        part: Mesh,
        slot: u32,
        casts_shadow: bool,
        motion: Motion,
    ) -> DynamicObject {
        let (centre, radius) = part.bounding_sphere();
        let start = mesh.indices.len() as u32;
        mesh.append(&part);
        DynamicObject {
            slot,
            indices: start..mesh.indices.len() as u32,
            centre,
            radius,
            casts_shadow,
            motion,
        }
    }
}

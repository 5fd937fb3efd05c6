//! Ground materials: which procedural texture the renderer lays on a ground surface.

use super::object_slot::ObjectSlot;

/// Ground materials: which procedural texture the renderer lays on a ground surface (see
/// [`crate::GroundTextures`]). A vertex carries its material in the bits of
/// [`Vertex::object`] above [`ObjectSlot::MASK`], or-ed with its slot; only the road's
/// surfaces and the grass carry one.
///
/// [`Vertex::object`]: super::mesh::Vertex::object
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Material;

impl Material {
    /// No texture: everything that stands up, and the moving objects.
    pub const NONE: u32 = 0;
    /// Asphalt: the paved road, crossing roads, cracks, patches and pot holes.
    pub const ASPHALT: u32 = 1 << 8;
    /// Grass: the ground and the verges.
    pub const GRASS: u32 = 2 << 8;
    /// Gravel: an unpaved road's surface.
    pub const GRAVEL: u32 = 3 << 8;
    /// Lane paint: the asphalt's texture, faint.
    pub const PAINT: u32 = 4 << 8;
    /// The material bits of a vertex's `object`.
    pub fn of(object: u32) -> u32 {
        object & !ObjectSlot::MASK
    }
}

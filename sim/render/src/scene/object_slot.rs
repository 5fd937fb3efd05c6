//! Object slots: which transform places a vertex in the world.

/// Object slots: which transform places a vertex in the world. The renderer keeps one
/// transform per slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ObjectSlot;

impl ObjectSlot {
    /// Static geometry, already in world coordinates.
    pub const WORLD: u32 = 0;
    /// The chase vehicle (its hood).
    pub const CHASE: u32 = 1;
    /// The lead vehicle and its board.
    pub const LEAD: u32 = 2;
    /// The first oncoming vehicle; the others follow.
    pub const FIRST_ONCOMING: u32 = 3;
    /// How many slots the renderer provides (its uniform array's length).
    pub const COUNT: u32 = 16;
    /// The bits of [`Vertex::object`] that hold the slot; the bits above hold the
    /// surface's [`Material`].
    ///
    /// [`Vertex::object`]: super::mesh::Vertex::object
    /// [`Material`]: super::material::Material
    pub const MASK: u32 = 0xff;
}

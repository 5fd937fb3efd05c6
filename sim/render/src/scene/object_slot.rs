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
    /// The most oncoming vehicles a scene has (their slots run from
    /// [`ObjectSlot::FIRST_ONCOMING`]): 13, the slots there were before the actors had any.
    pub const MAX_ONCOMING: u32 = 13;
    /// The first actor (a vehicle the description places in traffic and the caller
    /// poses each frame); the others follow, in the description's order.
    pub const FIRST_ACTOR: u32 = Self::FIRST_ONCOMING + Self::MAX_ONCOMING;
    /// The most actors a scene has.
    pub const MAX_ACTORS: u32 = 16;
    /// How many slots the renderer provides (its uniform array's length, `scene.wgsl`'s
    /// `Objects`).
    pub const COUNT: u32 = Self::FIRST_ACTOR + Self::MAX_ACTORS;
    /// The bits of [`Vertex::object`] that hold the slot; the bits above hold the
    /// surface's [`Material`].
    ///
    /// [`Vertex::object`]: super::mesh::Vertex::object
    /// [`Material`]: super::material::Material
    pub const MASK: u32 = 0xff;
}

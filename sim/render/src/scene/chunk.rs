//! Pieces of static geometry the renderer can cull: chunks, and the parts of a chunk.

use super::layer::Layer;
use std::ops::Range;

/// A piece of static geometry the renderer can cull: an index range and a bounding sphere
/// (world frame).
#[derive(Clone, Debug, PartialEq)]
pub struct Chunk {
    /// Range of the scene's indices (see [`Scene`](crate::scene::Scene)).
    pub indices: Range<u32>,
    /// Range of the scene's vertices its indices name.
    pub vertices: Range<u32>,
    /// Bounding sphere centre, world metres.
    pub centre: [f64; 3],
    /// Bounding sphere radius, metres.
    pub radius: f64,
    /// Whether it is drawn into the shadow map (ground, road and paint are not: they only
    /// receive shadows, and leaving them out halves the shadow pass's fill).
    pub casts_shadow: bool,
    /// What kind of geometry it holds; the renderer draws layers front to back.
    pub layer: Layer,
    /// Its pieces, in index order, together `indices`: each a run of the geometry (in the
    /// order it was laid) laid in one `PART_M` cell (see `bins`). Drawn in that
    /// order, coplanar pieces (overlapping patches on the road) show as they would drawn
    /// whole.
    pub parts: Vec<ChunkPart>,
}

/// A piece of a [`Chunk`] the renderer can cull on its own: an index range and a bounding
/// sphere (world frame).
#[derive(Clone, Debug, PartialEq)]
pub struct ChunkPart {
    /// Range of the scene's indices (see [`Scene`](crate::scene::Scene)).
    pub indices: Range<u32>,
    /// Bounding sphere centre, world metres.
    pub centre: [f64; 3],
    /// Bounding sphere radius, metres.
    pub radius: f64,
}

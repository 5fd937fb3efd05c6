//! Kinds of static geometry, in the order the renderer draws them.

/// Kinds of static geometry, in the order the renderer draws them: what stands up first, the
/// ground last, so that depth testing rejects hidden ground before it is shaded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Layer {
    /// Tree trunks, poles, houses, buildings, parked vehicles: they cast shadows.
    Clutter,
    /// Tree canopies: perforated (the renderer discards leaf-sized holes in them, from the
    /// camera and from the sun alike), so their shadows are dappled.
    Foliage,
    /// Telephone wires: thin, and too thin to cast a shadow worth a texel.
    Wires,
    /// The road, crossing roads, lane paint, cracks, patches and pot holes (just above the
    /// grass, so they hide it).
    Surface,
    /// The grass (and over bumps, the verges beside the road on the height field).
    Ground,
}

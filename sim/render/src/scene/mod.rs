//! The seeded, deterministic description of the world the chase camera sees, and the
//! geometry built from it: ground and grass shoulders, the road along the route with its
//! paint and marks, the lead vehicle with its target board, the chase vehicle's hood, and
//! the clutter of paper sections 2.3, 3 and 4 (trees, poles and wires, houses and buildings,
//! parked and oncoming vehicles), lit by one sun.

mod build;
mod builtin;
mod clutter;
mod description;
mod mesh;
mod rng;
mod route;
mod terrain;

pub use build::{
    lead_from_target_of, Chunk, ChunkPart, DynamicObject, Layer, Material, Motion, ObjectSlot,
    Scene, SceneError, BOARD_ALBEDO, BOARD_MARGIN_M, GRASS_ALBEDO, GRASS_ALBEDO_RANGE,
    GROUND_CELL_M, MAX_BUFFER_BYTES, STRIPE_ALBEDO, STRIPE_OVERRUN_M, STRIPE_WIDTH_M,
};
pub use builtin::{
    builtin_description, builtin_poses, builtin_target, BUILTIN_GAP_M, BUILTIN_SPEED_M_S,
};
pub use description::{
    distractor_near_side, AutoGain, CameraMount, ChaseVehicle, Densities, Distractor,
    DistractorKind, LeadVehicle, Placement, RoadSurface, SceneDescription, Sensor, Sun, Textures,
    FIELD_PERIOD_STEPS,
};
pub use mesh::{Mesh, Vertex};
pub use rng::stream;
pub use route::{Route, RouteSegment, RouteSpec};
pub use terrain::Terrain;

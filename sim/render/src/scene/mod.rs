//! The seeded, deterministic description of the world the chase camera sees, and the
//! geometry built from it: ground and grass shoulders, the road along the route with its
//! paint and marks, the lead vehicle with its target board, the chase vehicle's hood, and
//! the clutter of paper sections 2.3, 3 and 4 (trees, poles and wires, houses and buildings,
//! parked and oncoming vehicles), lit by one sun.
//!
//! Its modules, each using only those listed before it:
//! - the description: `route`, `error` ([`SceneError`]), `description`, `builtin`, `rng`
//!   (the scene's named random streams);
//! - the types the builders share: `mesh`, `object_slot`, `material`, `layer`, `chunk`,
//!   `dynamic_object`, `terrain` (the physics' height field), `bins` (static geometry
//!   binned by ground cell and layer, kept for the districts asked for, then concatenated
//!   into chunks), `districts` (the groups of districts built at once, and those kept),
//!   `site` (what every builder lays against: the route, the ground and the road's frame);
//! - what the standing clutter's shapes share: `standing` (an item built on flat ground,
//!   stood on the lowest ground under its footprint), `footing` (an object's frame on the
//!   ground), `wall` (walls, and the framed windows and doors on them);
//! - the builders, each laying one kind of thing, with the shapes they lay (each built in
//!   its own frame or placed by its footprint): `ground` (the grass; over bumps, the
//!   road's surfaces draped on the height field), `road` (its surface, edge and centre
//!   lines, crossing roads), `road_marks` (cracks, patches, pot holes), `verge`, `tree`,
//!   `pole` and `pole_line`, `street_lights`, `house`, `building`, `car` and `parked_car`, `truck`,
//!   `vehicle_kind` (the kinds of vehicle in traffic, [`VehicleKind`]), `overpass`,
//!   `placement` (the hand-placed clutter), `target_board`, `distractor`, `lead`, and
//!   `vehicles` (the moving objects);
//! - `back_model` ([`vehicle_back_model`]): the target model of each kind's back, from the
//!   numbers its shape is built from;
//! - `built_scene` ([`Scene`]), and on top `build` ([`Scene::build`], which reads as the
//!   order of what it lays).

mod back_model;
mod bins;
mod build;
mod building;
mod built_scene;
mod builtin;
mod car;
mod chunk;
mod description;
mod distractor;
mod districts;
mod dynamic_object;
mod elevation;
mod error;
mod footing;
mod ground;
mod house;
mod layer;
mod lead;
mod material;
mod mesh;
mod night;
mod object_slot;
mod overpass;
mod parked_car;
mod placement;
mod pole;
mod pole_line;
mod rain;
mod rng;
mod road;
mod road_marks;
mod route;
mod route_curve;
mod site;
mod spray;
mod standing;
mod street_lights;
mod tail_lamps;
mod target_board;
mod terrain;
#[cfg(test)]
mod test_support;
mod tree;
mod truck;
mod vehicle_kind;
mod vehicles;
mod verge;
mod wall;

pub use back_model::{
    back_model_centre_m, body_from_back_model, vehicle_back_model, BACK_MODEL_NOMINAL_RANGE_M,
};
pub use built_scene::Scene;
pub use builtin::{
    builtin_description, builtin_poses, builtin_target, BUILTIN_GAP_M, BUILTIN_SPEED_M_S,
};
pub use chunk::{Chunk, ChunkPart};
pub use description::{
    distractor_near_side, ActorBody, AutoGain, CameraMount, ChaseVehicle, Densities, Distractor,
    DistractorKind, Fog, LeadVehicle, Placement, RoadSurface, SceneDescription, Sensor, Sun,
    Textures, FIELD_PERIOD_STEPS,
};
pub use dynamic_object::{DynamicObject, Motion};
pub use elevation::{
    elevation_at, grade_at, ground_profile, PROFILE_CELL_M, PROFILE_MARGIN_M, PROFILE_STEP_M,
};
pub use error::{SceneError, MAX_BUFFER_BYTES};
pub use ground::{GRASS_ALBEDO, GRASS_ALBEDO_RANGE, GROUND_CELL_M};
pub use layer::Layer;
pub use material::Material;
pub use mesh::{Mesh, MeshPiece, Vertex};
pub use night::{twilight_factor, Beam, Headlamps, MIN_SUN_ELEVATION_DEG, TWILIGHT_LUX};
pub use object_slot::ObjectSlot;
pub use rain::{Rain, RainBand};
pub use rng::stream;
pub use route::{PRange, Route, RouteSegment, RouteSpec};
pub use spray::Spray;
pub use street_lights::StreetLights;
pub use tail_lamps::{Braking, TailLamps};
pub use target_board::{
    lead_from_target_of, BOARD_ALBEDO, BOARD_MARGIN_M, STRIPE_ALBEDO, STRIPE_OVERRUN_M,
    STRIPE_WIDTH_M,
};
pub use terrain::Terrain;
pub use vehicle_kind::VehicleKind;

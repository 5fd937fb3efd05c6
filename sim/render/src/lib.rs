//! carfollow's camera world: the seeded, deterministic scene the chase camera sees (road,
//! roadside clutter, the lead vehicle with its target board, the chase vehicle's hood, the
//! physics' own ground under it all) and the wgpu off-screen camera that renders it into
//! 256×242 8-bit grey frames with sun shadows, textures and a sensor model.
//!
//! It depends on `tracker` (the camera's intrinsics *are* a [`tracker::Camera`], so the
//! renderer and the tracker's stage 8 agree) and on `vehicle` (the physics ground, so the
//! road is drawn on the height field the wheels roll over), and on nothing of the loop:
//! no scenario files, no controllers, no records.
//!
//! - The scene: a [`SceneDescription`] (seed, route, densities, sun, sensor, target,
//!   vehicles, ground, and the actors in traffic) built into a [`Scene`] of static chunks
//!   and moving objects.
//! - The vehicles in traffic: a [`VehicleKind`] each, and the target model of each kind's
//!   back ([`vehicle_back_model`]), made from the numbers its shape is drawn from.
//! - The camera: a [`Renderer`] for a [`CameraRig`] draws a [`Frame`] (the image with its
//!   [`GroundTruth`]) for each [`FrameInput`] (the poses at capture), whole or in part.
//!
//! Image convention (shared with the tracker): origin at the top-left corner, **pixel
//! centres at integer coordinates** (pixel (i, j) is centred at x = i, y = j).
#![warn(missing_docs)]

mod camera;
mod scene;

pub use camera::{
    apply_sensor, blur_reach_px, ground_truth_of, sensor_noise_sigma_grey, shift_noise,
    target_occluded, Backend, BackendError, CameraRig, DrawStats, Field, Frame, FrameInput,
    GroundTextures, GroundTruth, RenderError, RenderOptions, Renderer, SoftwareContext,
    TextureLayer, FAR_M, LAYERS, NEAR_M, TEXTURE_SIZE, TILE_M,
};
pub use scene::{
    back_model_centre_m, body_from_back_model, builtin_description, builtin_poses, builtin_target,
    distractor_near_side, elevation_at, grade_at, ground_profile, lead_from_target_of, stream,
    twilight_factor, vehicle_back_model, ActorBody, AutoGain, Beam, Braking, CameraMount,
    ChaseVehicle, Chunk, ChunkPart, Densities, Distractor, DistractorKind, DynamicObject, Fog,
    Headlamps, Layer, LeadVehicle, Material, Mesh, MeshPiece, Motion, ObjectSlot, PRange,
    Placement, Rain, RainBand, RoadSurface, Route, RouteSegment, RouteSpec, Scene,
    SceneDescription, SceneError, Sensor, Spray, StreetLights, Sun, TailLamps, Terrain, Textures,
    VehicleKind, Vertex, BACK_MODEL_NOMINAL_RANGE_M, BOARD_ALBEDO, BOARD_MARGIN_M, BUILTIN_GAP_M,
    BUILTIN_SPEED_M_S, FIELD_PERIOD_STEPS, GRASS_ALBEDO, GRASS_ALBEDO_RANGE, GROUND_CELL_M,
    MAX_BUFFER_BYTES, MIN_SUN_ELEVATION_DEG, PROFILE_CELL_M, PROFILE_MARGIN_M, PROFILE_STEP_M,
    STRIPE_ALBEDO, STRIPE_OVERRUN_M, STRIPE_WIDTH_M, TWILIGHT_LUX,
};

//! Building the world's geometry from a [`SceneDescription`]: static geometry binned into
//! ground-plane cells (so the renderer can cull what it cannot see), and the moving objects
//! (chase hood, lead vehicle with its board, oncoming traffic) in their own frames.

use super::clutter::{
    building, car, ground_under, house, overpass, pole, stand, BuildingSpec, CarBody, HouseSpec,
    PoleFittings, POLE_ALBEDO, POLE_TOP_M,
};
use super::description::{DistractorKind, Placement, RoadSurface, SceneDescription};
use super::mesh::{Mesh, Vertex};
use super::rng::stream;
use super::route::Route;
use super::terrain::Terrain;
use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeMap;
use std::ops::Range;
use thiserror::Error;

/// Why a scene could not be built.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum SceneError {
    /// A field of the description is out of range.
    #[error("scene description: {field} {reason}")]
    Invalid {
        /// The field, as a dotted path.
        field: String,
        /// What is wrong with it.
        reason: String,
    },
    /// The geometry would not fit the renderer's buffers.
    #[error(
        "the scene's geometry needs {bytes} bytes of {buffer}, more than a renderer's buffer \
         holds ({limit}): shorten the route or lower the clutter's densities"
    )]
    TooLarge {
        /// `"vertices"` or `"indices"`.
        buffer: &'static str,
        /// The bytes it needs.
        bytes: u64,
        /// The most a buffer holds ([`MAX_BUFFER_BYTES`]).
        limit: u64,
    },
}

/// The most bytes the renderer's vertex or index buffer may hold: the `max_buffer_size` of
/// the limits it asks its device for (wgpu's WebGL2 downlevel defaults, 256 MiB).
pub const MAX_BUFFER_BYTES: u64 = 1 << 28;

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
    pub const MASK: u32 = 0xff;
}

/// Ground materials: which procedural texture the renderer lays on a ground surface (see
/// `sim::camera::GroundTextures`). A vertex carries its material in the bits of
/// [`Vertex::object`] above [`ObjectSlot::MASK`], or-ed with its slot; only the road's
/// surfaces and the grass carry one.
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

/// Side of the square ground cells static geometry is binned into, metres. 50 m keeps the
/// number of draw calls small (about 30 cells are in view) while culling most of a
/// kilometre-long route.
pub const BIN_M: f64 = 50.0;

/// Side of the square cells whose geometry a [`Chunk`] can cull one by one ([`ChunkPart`]),
/// metres: a frame rendered only in part (the tracker's window) then draws less of it; a
/// 50 m cell's clutter was 70 % of the triangles such a part drew.
pub const PART_M: f64 = 10.0;

/// Height of the road surface above the grass, metres; the crossing roads sit just below it
/// and the paint and marks just above, so nothing fights for depth.
const ROAD_Y_M: f64 = 0.02;
/// Height of crossing roads, metres.
const CROSS_ROAD_Y_M: f64 = 0.015;
/// Height of lane paint, cracks, patches and pot holes, metres.
const MARK_Y_M: f64 = 0.03;
/// Over bumps, how far the grass verges on the height field reach beyond the road's edge,
/// metres: the flat grass beyond is 5 m or more from the wheels, where a bump's rise of a
/// few centimetres is a pixel at the tracker's ranges.
const VERGE_M: f64 = 5.0;
/// Height of those verges above the ground, metres: above the flat grass, below the road.
const VERGE_Y_M: f64 = 0.005;
/// Longest edge of a verge's pieces on the height field, metres: grass has no paint to
/// fight for depth with, so it may depart from the field by a centimetre or two between
/// vertices (curvature ≤ 0.14 /m for the roughest shipped bumps: 1.7 cm over 1 m).
const VERGE_EDGE_M: f64 = 1.0;
/// How far the road continues straight past either end of the route, metres, so the camera
/// never sees the road end.
const ROAD_RUNOUT_M: f64 = 250.0;
/// Grass margin around the road's bounding box, metres: beyond the far plane's useful range.
const GROUND_MARGIN_M: f64 = 250.0;
/// Grass mottling cell, metres: the renderer gives each corner of a square lattice of this
/// pitch its own albedo, hashed from the scene's grass key, and interpolates between them.
pub const GROUND_CELL_M: f64 = 25.0;
/// The albedo that marks a vertex as grass: the renderer computes the real albedo per
/// fragment from the world position (see [`GROUND_CELL_M`], [`GRASS_ALBEDO_RANGE`]).
pub const GRASS_ALBEDO: f64 = -1.0;
/// Range of grass albedo, from dry to lush patches.
pub const GRASS_ALBEDO_RANGE: [f64; 2] = [0.17, 0.30];
/// Length of one road quad along an arc, metres (a 60 m arc bends < 2° per quad).
const ROAD_STEP_M: f64 = 2.0;
/// Length of one road quad along a straight, metres: long quads mean few triangles (the
/// road is flat, so length costs nothing in accuracy), and llvmpipe's cost grows with
/// every triangle set up.
const STRAIGHT_STEP_M: f64 = 20.0;
/// Straight pieces per wire span: three chords follow a 0.5 m sag over a ~45 m span to
/// within 6 cm (a pixel at 20 m), each an open beam of eight triangles (a flat ribbon
/// would be cheaper but vanishes edge-on when the wire passes above the camera).
const WIRE_PIECES: usize = 3;
/// Width of the paved shoulder beyond each lane, metres.
const SHOULDER_M: f64 = 0.5;
/// Lane paint width, metres (US practice: 4–6 in).
const PAINT_WIDTH_M: f64 = 0.12;
/// Centre-line dashes: dash and period, metres (US practice: 10 ft dash in a 40 ft cycle).
const DASH_M: f64 = 3.0;
/// Centre-line dash period, metres.
const DASH_PERIOD_M: f64 = 12.0;
/// Half length of a crossing road, metres.
const CROSS_ROAD_HALF_M: f64 = 120.0;
/// How far the board stands proud of the lead's back door, metres.
const BOARD_STANDOFF_M: f64 = 0.01;
/// How far the paint on the board stands proud of it, metres (depth-safe at 50 m).
const STRIPE_STANDOFF_M: f64 = 0.003;
/// How far a controlled distractor stands in front of the board, metres.
const DISTRACTOR_STANDOFF_M: f64 = 0.02;
/// Height of a distractor pole, metres (a telephone pole's).
const DISTRACTOR_POLE_M: f64 = 9.0;
/// How far a distractor wire runs to each side of the target's centre, metres.
const DISTRACTOR_REACH_M: f64 = 6.0;
/// The paint rule, shared with the tracker's synthetic frames.
pub use tracker::paint::{BOARD_MARGIN_M, STRIPE_EXTENSION_M as STRIPE_OVERRUN_M, STRIPE_WIDTH_M};
/// Albedo of the board's light paint.
pub const BOARD_ALBEDO: f64 = 0.85;
/// Albedo of the board's darkest paint (tone 0 of `tracker::paint::PaintRect`); other
/// tones lie between it and [`BOARD_ALBEDO`].
pub const STRIPE_ALBEDO: f64 = 0.06;

/// A piece of static geometry the renderer can cull: an index range and a bounding sphere
/// (world frame).
#[derive(Clone, Debug, PartialEq)]
pub struct Chunk {
    /// Range into [`Scene::mesh`]'s indices.
    pub indices: Range<u32>,
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
    /// order it was laid) laid in one [`PART_M`] cell. Drawn in that order, coplanar pieces
    /// (overlapping patches on the road) show as they would drawn whole.
    pub parts: Vec<ChunkPart>,
}

/// A piece of a [`Chunk`] the renderer can cull on its own: an index range and a bounding
/// sphere (world frame).
#[derive(Clone, Debug, PartialEq)]
pub struct ChunkPart {
    /// Range into [`Scene::mesh`]'s indices.
    pub indices: Range<u32>,
    /// Bounding sphere centre, world metres.
    pub centre: [f64; 3],
    /// Bounding sphere radius, metres.
    pub radius: f64,
}

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
}

/// A moving object: geometry in its own frame (x forward, y up, z right, origin on the
/// ground), placed each frame by a transform.
#[derive(Clone, Debug, PartialEq)]
pub struct DynamicObject {
    /// Its slot (see [`ObjectSlot`]).
    pub slot: u32,
    /// Range into [`Scene::mesh`]'s indices.
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

/// The built world: one mesh with static chunks and dynamic objects, plus the description.
#[derive(Clone, Debug)]
pub struct Scene {
    description: SceneDescription,
    route: Route,
    terrain: Option<Terrain>,
    mesh: Mesh,
    chunks: Vec<Chunk>,
    objects: Vec<DynamicObject>,
}

/// A point in the road's frame: station along the centreline and lateral offset (right).
struct RoadFrame<'a> {
    route: &'a Route,
    /// The ground's height field, if it has bumps: strips over it are cut into cells.
    terrain: Option<&'a Terrain>,
}

impl RoadFrame<'_> {
    fn world(&self, s: f64, lateral: f64, y: f64) -> [f64; 3] {
        let [x, z] = self.route.point(s, lateral);
        [x, y, z]
    }
}

/// Static geometry binned by ground cell and by layer. Within a bin, each run of geometry
/// added in one [`PART_M`] cell is a part of its own (see [`ChunkPart`]).
#[derive(Default)]
pub(super) struct Bins {
    bins: BTreeMap<(i64, i64, Layer), Bin>,
}

/// One bin's geometry, and where each of its parts starts: the index and the part's cell.
#[derive(Default)]
pub(super) struct Bin {
    mesh: Mesh,
    parts: Vec<(usize, (i64, i64))>,
}

impl Bins {
    /// The mesh of the bin of ground point (`x`, `z`) and layer `layer`, for geometry there
    /// to be added to it.
    pub(super) fn at(&mut self, x: f64, z: f64, layer: Layer) -> &mut Mesh {
        let cell = |m: f64| ((x / m).floor() as i64, (z / m).floor() as i64);
        let (cx, cz) = cell(BIN_M);
        let bin = self.bins.entry((cx, cz, layer)).or_default();
        let part = cell(PART_M);
        if bin.parts.last().is_none_or(|&(_, last)| last != part) {
            bin.parts.push((bin.mesh.indices.len(), part));
        }
        &mut bin.mesh
    }
}

impl Scene {
    /// Builds the world. Deterministic: the same description gives the same mesh, vertex for
    /// vertex.
    pub fn build(description: SceneDescription) -> Result<Scene, SceneError> {
        Self::build_within(description, MAX_BUFFER_BYTES)
    }

    /// [`Scene::build`], refusing geometry whose vertices or indices take more than
    /// `limit` bytes.
    pub(crate) fn build_within(
        description: SceneDescription,
        limit: u64,
    ) -> Result<Scene, SceneError> {
        description.validate()?;
        let route = Route::new(description.route.clone());
        let terrain = Terrain::new(&description.ground)?;
        let mut bins = Bins::default();
        let seed = description.seed;
        let road = RoadFrame {
            route: &route,
            terrain: terrain.as_ref(),
        };
        let lane = description.route.lane_width_m;
        let road_half = lane + SHOULDER_M;
        let length = route.length_m();
        let d = &description.densities;
        let count = |per_km: f64, span_m: f64| (per_km * span_m / 1000.0).round() as usize;

        // Ground: a mottled grass grid covering the road's bounding box.
        let (mut min, mut max) = ([f64::MAX; 2], [f64::MIN; 2]);
        let mut s = -ROAD_RUNOUT_M;
        while s <= length + ROAD_RUNOUT_M {
            let [x, z] = route.point(s, 0.0);
            min = [min[0].min(x), min[1].min(z)];
            max = [max[0].max(x), max[1].max(z)];
            s += 10.0;
        }
        let origin = [min[0] - GROUND_MARGIN_M, min[1] - GROUND_MARGIN_M];
        let cells = [
            ((max[0] - min[0] + 2.0 * GROUND_MARGIN_M) / GROUND_CELL_M).ceil() as usize,
            ((max[1] - min[1] + 2.0 * GROUND_MARGIN_M) / GROUND_CELL_M).ceil() as usize,
        ];
        // One quad: the mottling is computed per fragment from the world position (see
        // `GRASS_ALBEDO`), so the grass costs two triangles instead of a grid.
        let size = [
            cells[0] as f64 * GROUND_CELL_M,
            cells[1] as f64 * GROUND_CELL_M,
        ];
        bins.at(
            origin[0] + 0.5 * size[0],
            origin[1] + 0.5 * size[1],
            Layer::Ground,
        )
        .polygon(
            &[
                [origin[0], 0.0, origin[1]],
                [origin[0] + size[0], 0.0, origin[1]],
                [origin[0] + size[0], 0.0, origin[1] + size[1]],
                [origin[0], 0.0, origin[1] + size[1]],
            ],
            GRASS_ALBEDO,
            ObjectSlot::WORLD | Material::GRASS,
        );

        // Road strip, edge lines and the dashed centre line.
        const ASPHALT: f64 = 0.30;
        const PAINT: f64 = 0.75;
        let road_object = ObjectSlot::WORLD
            | match description.road_surface {
                RoadSurface::Asphalt => Material::ASPHALT,
                RoadSurface::Gravel => Material::GRAVEL,
            };
        let paint_object = ObjectSlot::WORLD | Material::PAINT;
        let grass_object = ObjectSlot::WORLD | Material::GRASS;
        let mut s = -ROAD_RUNOUT_M;
        while s < length + ROAD_RUNOUT_M {
            let straight =
                route.curvature_at(s) == 0.0 && route.curvature_at(s + STRAIGHT_STEP_M) == 0.0;
            let s1 = s + if straight {
                STRAIGHT_STEP_M
            } else {
                ROAD_STEP_M
            };
            let mid = road.world(0.5 * (s + s1), 0.0, 0.0);
            if let Some(t) = terrain.as_ref().filter(|t| t.covers(mid[0], mid[2])) {
                // Over bumps, grass verges on the height field too, so the road does not
                // stand out of the flat grass.
                let mut verges = Mesh::default();
                for (l0, l1) in [
                    (-road_half - VERGE_M, -road_half),
                    (road_half, road_half + VERGE_M),
                ] {
                    let (y, albedo) = (VERGE_Y_M, GRASS_ALBEDO);
                    strip(&mut verges, &road, [s, s1, l0, l1], y, albedo, grass_object);
                }
                bins.at(mid[0], mid[2], Layer::Ground)
                    .append(&t.drape(&verges, VERGE_EDGE_M));
            }
            let mesh = bins.at(mid[0], mid[2], Layer::Surface);
            let lateral = [s, s1, -road_half, road_half];
            strip(mesh, &road, lateral, ROAD_Y_M, ASPHALT, road_object);
            for side in [-1.0, 1.0] {
                let l = side * (lane + 0.1);
                let mut a = s;
                // Edge lines stop across intersections: in short pieces near one, else in
                // one piece per road quad.
                let clear = !route.near_intersection(0.5 * (s + s1), road_half + 1.0 + (s1 - s));
                let piece = if clear { s1 - s } else { ROAD_STEP_M };
                while a < s1 {
                    let b = (a + piece).min(s1);
                    if !route.near_intersection(0.5 * (a + b), road_half + 1.0) {
                        let w = 0.5 * PAINT_WIDTH_M;
                        strip(
                            mesh,
                            &road,
                            [a, b, l - w, l + w],
                            MARK_Y_M,
                            PAINT,
                            paint_object,
                        );
                    }
                    a = b;
                }
            }
            s = s1;
        }
        let mut s = -ROAD_RUNOUT_M;
        while s < length + ROAD_RUNOUT_M {
            if !route.near_intersection(s + 0.5 * DASH_M, road_half + 1.0) {
                let mid = road.world(s + 0.5 * DASH_M, 0.0, 0.0);
                let mesh = bins.at(mid[0], mid[2], Layer::Surface);
                let w = 0.5 * PAINT_WIDTH_M;
                strip(
                    mesh,
                    &road,
                    [s, s + DASH_M, -w, w],
                    MARK_Y_M,
                    PAINT,
                    paint_object,
                );
            }
            s += DASH_PERIOD_M;
        }

        // Crossing roads at intersections, at right angles to the route.
        for &c in &description.route.intersections_m {
            let [x, z, heading] = route.at(c);
            let along = [heading.sin(), heading.cos()]; // the route's right = the crossing's direction
            let across = [heading.cos(), -heading.sin()];
            let mut t = -CROSS_ROAD_HALF_M;
            while t < CROSS_ROAD_HALF_M {
                let t1 = t + 10.0;
                let p = |t: f64, w: f64| {
                    [
                        x + t * along[0] + w * across[0],
                        CROSS_ROAD_Y_M,
                        z + t * along[1] + w * across[1],
                    ]
                };
                let centre = p(t + 5.0, 0.0);
                bins.at(centre[0], centre[2], Layer::Surface).polygon(
                    &[
                        p(t, -road_half),
                        p(t1, -road_half),
                        p(t1, road_half),
                        p(t, road_half),
                    ],
                    ASPHALT * 0.95,
                    road_object,
                );
                t = t1;
            }
        }

        // Cracks, patches and pot holes: dark marks on the road.
        let mut marks = stream(seed, "road-marks");
        let mut road_marks: Vec<([f64; 3], Mesh)> = Vec::new();
        for _ in 0..count(d.cracks_per_km, length) {
            let mut s = marks.random_range(0.0..length);
            let mut l = marks.random_range(-lane..lane);
            let transverse = marks.random_bool(0.4);
            let mut mesh = Mesh::default();
            for _ in 0..marks.random_range(3..7) {
                let (ds, dl) = if transverse {
                    (marks.random_range(-0.3..0.3), marks.random_range(0.3..0.8))
                } else {
                    (
                        marks.random_range(0.4..1.0),
                        marks.random_range(-0.25..0.25),
                    )
                };
                let (s1, l1) = (s + ds, (l + dl).clamp(-road_half, road_half));
                let w = 0.025;
                mesh.polygon(
                    &[
                        road.world(s, l - w, MARK_Y_M),
                        road.world(s1, l1 - w, MARK_Y_M),
                        road.world(s1, l1 + w, MARK_Y_M),
                        road.world(s, l + w, MARK_Y_M),
                    ],
                    0.10,
                    road_object,
                );
                (s, l) = (s1, l1);
            }
            road_marks.push((road.world(s, l, 0.0), mesh));
        }
        for _ in 0..count(d.patches_per_km, length) {
            let s = marks.random_range(0.0..length);
            let l = marks.random_range(-lane..lane);
            let (hs, hl) = (marks.random_range(0.5..1.5), marks.random_range(0.4..1.0));
            let albedo = if marks.random_bool(0.5) { 0.18 } else { 0.40 };
            let mut mesh = Mesh::default();
            mesh.polygon(
                &[
                    road.world(s - hs, l - hl, MARK_Y_M),
                    road.world(s + hs, l - hl, MARK_Y_M),
                    road.world(s + hs, l + hl, MARK_Y_M),
                    road.world(s - hs, l + hl, MARK_Y_M),
                ],
                albedo,
                road_object,
            );
            road_marks.push((road.world(s, l, 0.0), mesh));
        }
        for _ in 0..count(d.potholes_per_km, length) {
            let s = marks.random_range(0.0..length);
            let l = marks.random_range(-lane..lane);
            let r = marks.random_range(0.2..0.5);
            let corners: Vec<[f64; 3]> = (0..8)
                .map(|k| {
                    let a = k as f64 * std::f64::consts::TAU / 8.0;
                    let rr = r * marks.random_range(0.7..1.2);
                    road.world(s + rr * a.cos(), l + rr * a.sin(), MARK_Y_M)
                })
                .collect();
            let mut mesh = Mesh::default();
            mesh.polygon(&corners, 0.06, road_object);
            road_marks.push((road.world(s, l, 0.0), mesh));
        }
        for (p, mesh) in &road_marks {
            bins.at(p[0], p[2], Layer::Surface).append(mesh);
        }

        // Trees: trunk and a canopy of clumps with gaps between them, each clump's surface
        // perforated by the renderer (`Layer::Foliage`), so their shadows dapple.
        let mut trees = stream(seed, "trees");
        let tree_at = |bins: &mut Bins, rng: &mut ChaCha8Rng, x: f64, z: f64| {
            let trunk = rng.random_range(2.5..4.0);
            let base = ground_under(
                terrain.as_ref(),
                &[[x - 0.15, z - 0.15], [x + 0.15, z + 0.15]],
            );
            bins.at(x, z, Layer::Clutter).upright_box(
                x,
                z,
                0.0,
                0.15,
                0.15,
                base,
                trunk + 1.0,
                0.22,
            );
            let mesh = bins.at(x, z, Layer::Foliage);
            for _ in 0..rng.random_range(5..9) {
                let c = [
                    x + rng.random_range(-1.6..1.6),
                    trunk + rng.random_range(1.0..3.2),
                    z + rng.random_range(-1.6..1.6),
                ];
                let r = rng.random_range(0.7..1.6);
                mesh.octahedron(
                    c,
                    [r, r * rng.random_range(0.7..1.1), r],
                    rng.random_range(0.13..0.22),
                );
            }
        };
        for _ in 0..count(d.trees_per_km, length + 150.0) {
            let s = trees.random_range(-50.0..length + 100.0);
            let side = if trees.random_bool(0.5) { 1.0 } else { -1.0 };
            let l = side * (road_half + trees.random_range(4.0..22.0));
            if route.near_intersection(s, road_half + 6.0) {
                continue;
            }
            let [x, z] = route.point(s, l);
            tree_at(&mut bins, &mut trees, x, z);
        }

        // Telephone poles on the right, with cross-arms, insulators and sagging wires
        // between them; some carry a lower cross-arm or a transformer.
        let mut poles = stream(seed, "poles");
        let mut fittings = stream(seed, "pole-fittings");
        if d.poles_per_km > 0.0 {
            // Capped, so that the first pole's draw below stays finite for any positive
            // density (1000 / 1e-320 is infinite); a pole every 1e9 m is none on a route.
            let spacing = (1000.0 / d.poles_per_km).min(1e9);
            let mut s = poles.random_range(-50.0..-50.0 + spacing);
            let mut previous: Option<[[f64; 3]; 2]> = None;
            while s < length + 100.0 {
                let here = s;
                s += spacing * poles.random_range(0.85..1.15);
                if route.near_intersection(here, road_half + 4.0) {
                    continue;
                }
                let l = road_half + 2.0;
                let heading = route.at(here)[2];
                let [px, pz] = route.point(here, l);
                let mut item = Mesh::default();
                let kind = PoleFittings::pick(fittings.random_range(0.0..1.0));
                let mut ends = pole(&mut item, [px, pz], heading, kind);
                let base = stand(terrain.as_ref(), &mut item);
                for end in &mut ends {
                    end[1] += base;
                }
                bins.at(px, pz, Layer::Clutter).append(&item);
                if let Some(prev) = previous {
                    let wires = bins.at(px, pz, Layer::Wires);
                    for k in 0..2 {
                        let (a, b) = (prev[k], ends[k]);
                        const SAG_M: f64 = 0.5;
                        let point = |t: f64| {
                            [
                                a[0] + t * (b[0] - a[0]),
                                a[1] + t * (b[1] - a[1]) - 4.0 * SAG_M * t * (1.0 - t),
                                a[2] + t * (b[2] - a[2]),
                            ]
                        };
                        for i in 0..WIRE_PIECES {
                            wires.beam(
                                point(i as f64 / WIRE_PIECES as f64),
                                point((i + 1) as f64 / WIRE_PIECES as f64),
                                0.02,
                                0.12,
                            );
                        }
                    }
                }
                previous = Some(ends);
            }
        }

        // Houses (gabled, windows on every wall) and taller buildings with a window grid.
        let mut houses = stream(seed, "houses");
        let mut house_details = stream(seed, "house-details");
        for _ in 0..count(d.houses_per_km, length + 150.0) {
            let s = houses.random_range(-50.0..length + 100.0);
            if route.near_intersection(s, road_half + 16.0) {
                continue;
            }
            let side = if houses.random_bool(0.5) { 1.0 } else { -1.0 };
            let half = [houses.random_range(4.0..6.5), houses.random_range(3.5..5.0)];
            let l = side * (road_half + houses.random_range(10.0..22.0) + half[1]);
            let walls = if houses.random_bool(0.3) { 5.8 } else { 3.0 };
            let [x, z] = route.point(s, l);
            let heading = route.at(s)[2] + houses.random_range(-0.1..0.1);
            let wall_albedo = houses.random_range(0.45..0.8);
            let roof_albedo = houses.random_range(0.12..0.3);
            // The details from their own stream, so the houses stand where they did.
            let door_at = house_details.random_range(0.0..1.0);
            let chimney = house_details.random_range(0.0..1.0);
            let chimney_at = house_details.random_bool(0.5).then_some(chimney);
            let mut item = Mesh::default();
            house(
                &mut item,
                [x, z],
                heading,
                &HouseSpec {
                    half,
                    walls,
                    wall_albedo,
                    roof_albedo,
                    road_side: -side,
                    door_at,
                    chimney_at,
                },
            );
            stand(terrain.as_ref(), &mut item);
            bins.at(x, z, Layer::Clutter).append(&item);
        }
        let mut buildings = stream(seed, "buildings");
        let mut building_details = stream(seed, "building-details");
        for _ in 0..count(d.buildings_per_km, length + 150.0) {
            let s = buildings.random_range(-50.0..length + 100.0);
            if route.near_intersection(s, road_half + 20.0) {
                continue;
            }
            let side = if buildings.random_bool(0.5) {
                1.0
            } else {
                -1.0
            };
            let half = [
                buildings.random_range(6.0..12.0),
                buildings.random_range(5.0..9.0),
            ];
            let l = side * (road_half + buildings.random_range(12.0..30.0) + half[1]);
            let height = buildings.random_range(8.0..20.0);
            let [x, z] = route.point(s, l);
            let heading = route.at(s)[2];
            let albedo = buildings.random_range(0.35..0.7);
            let mut item = Mesh::default();
            building(
                &mut item,
                [x, z],
                heading,
                &BuildingSpec {
                    half,
                    height,
                    albedo,
                    road_side: -side,
                    entrance_at: building_details.random_range(0.0..1.0),
                },
            );
            stand(terrain.as_ref(), &mut item);
            bins.at(x, z, Layer::Clutter).append(&item);
        }

        // Parked vehicles on the right shoulder.
        let mut parked = stream(seed, "parked-vehicles");
        let mut parked_bodies = stream(seed, "parked-vehicle-bodies");
        for _ in 0..count(d.parked_vehicles_per_km, length) {
            let s = parked.random_range(0.0..length);
            if route.near_intersection(s, road_half + 8.0) {
                continue;
            }
            let pose = route.pose_at(s, road_half + 1.3);
            let mut car_mesh = Mesh::default();
            car(
                &mut car_mesh,
                ObjectSlot::WORLD,
                parked.random_range(0.1..0.8),
                CarBody::pick(parked_bodies.random_range(0.0..1.0)),
            );
            for v in &mut car_mesh.vertices {
                let p = pose
                    * Point3::new(
                        f64::from(v.position[0]),
                        f64::from(v.position[1]),
                        f64::from(v.position[2]),
                    );
                let n = pose.rotation
                    * Vector3::new(
                        f64::from(v.normal[0]),
                        f64::from(v.normal[1]),
                        f64::from(v.normal[2]),
                    );
                v.position = [p.x as f32, p.y as f32, p.z as f32];
                v.normal = [n.x as f32, n.y as f32, n.z as f32];
            }
            stand(terrain.as_ref(), &mut car_mesh);
            let t = pose.translation.vector;
            bins.at(t.x, t.z, Layer::Clutter).append(&car_mesh);
        }

        // Hand-placed clutter.
        let mut placed = stream(seed, "placements");
        for placement in &description.placements {
            match *placement {
                Placement::Pole { x_m, z_m } => {
                    let mut item = Mesh::default();
                    item.upright_box(x_m, z_m, 0.0, 0.13, 0.13, 0.0, POLE_TOP_M, POLE_ALBEDO);
                    stand(terrain.as_ref(), &mut item);
                    bins.at(x_m, z_m, Layer::Clutter).append(&item);
                }
                Placement::Tree { x_m, z_m } => tree_at(&mut bins, &mut placed, x_m, z_m),
                Placement::Overpass {
                    station_m,
                    deck_m,
                    height_m,
                } => overpass(
                    &mut bins,
                    &route,
                    terrain.as_ref(),
                    road_half,
                    station_m,
                    deck_m,
                    height_m,
                ),
            }
        }

        // Over bumps, the road's surfaces lie on the physics' height field.
        if let Some(t) = &terrain {
            for (&(_, _, layer), bin) in bins.bins.iter_mut() {
                if layer == Layer::Surface {
                    // Strips come in cells already; the diagonal of a cell is the longest
                    // edge that needs no cutting.
                    let mut marks: Vec<usize> = bin.parts.iter().map(|&(at, _)| at).collect();
                    bin.mesh = t.drape_marked(
                        &bin.mesh,
                        t.cell_m() * std::f64::consts::SQRT_2,
                        &mut marks,
                    );
                    for (part, at) in bin.parts.iter_mut().zip(marks) {
                        part.0 = at;
                    }
                }
            }
        }

        // Concatenate the bins into one mesh, recording each as a chunk.
        let mut mesh = Mesh::default();
        let mut chunks = Vec::new();
        for (&(_, _, layer), Bin { mesh: bin, parts }) in &bins.bins {
            if bin.indices.is_empty() {
                continue;
            }
            let (centre, radius) = bin.bounding_sphere();
            let start = mesh.indices.len() as u32;
            mesh.append(bin);
            // Each part runs to where the next starts (a part may have added nothing).
            let ends = parts
                .iter()
                .skip(1)
                .map(|&(at, _)| at)
                .chain([bin.indices.len()]);
            let parts = parts
                .iter()
                .zip(ends)
                .filter(|((at, _), end)| end > at)
                .map(|(&(at, _), end)| {
                    let (centre, radius) = bin.bounding_sphere_of(at..end);
                    ChunkPart {
                        indices: start + at as u32..start + end as u32,
                        centre,
                        radius,
                    }
                })
                .collect();
            chunks.push(Chunk {
                indices: start..mesh.indices.len() as u32,
                centre,
                radius,
                casts_shadow: matches!(layer, Layer::Clutter | Layer::Foliage),
                layer,
                parts,
            });
        }

        // Dynamic objects: the chase hood, the lead with its board, oncoming traffic.
        let mut objects = Vec::new();
        let mut push_object = |mesh: &mut Mesh, part: Mesh, slot, casts, motion| {
            let (centre, radius) = part.bounding_sphere();
            let start = mesh.indices.len() as u32;
            mesh.append(&part);
            objects.push(DynamicObject {
                slot,
                indices: start..mesh.indices.len() as u32,
                centre,
                radius,
                casts_shadow: casts,
                motion,
            });
        };
        let chase = &description.chase;
        let mut hood = Mesh::default();
        hood.aabb(
            [
                chase.hood_back_m,
                chase.hood_height_m - 0.6,
                -0.5 * chase.hood_width_m,
            ],
            [
                chase.hood_front_m,
                chase.hood_height_m,
                0.5 * chase.hood_width_m,
            ],
            0.45,
            ObjectSlot::CHASE,
        );
        push_object(&mut mesh, hood, ObjectSlot::CHASE, false, Motion::Chase);
        let lead_mesh = lead_vehicle(&description);
        push_object(&mut mesh, lead_mesh, ObjectSlot::LEAD, true, Motion::Lead);
        let mut oncoming = stream(seed, "oncoming-vehicles");
        let mut oncoming_bodies = stream(seed, "oncoming-vehicle-bodies");
        let span = length + d.oncoming_speed_m_s * 60.0;
        let n = count(d.oncoming_vehicles_per_km, span)
            .min((ObjectSlot::COUNT - ObjectSlot::FIRST_ONCOMING) as usize);
        for k in 0..n {
            let slot = ObjectSlot::FIRST_ONCOMING + k as u32;
            let mut part = Mesh::default();
            car(
                &mut part,
                slot,
                oncoming.random_range(0.1..0.8),
                CarBody::pick(oncoming_bodies.random_range(0.0..1.0)),
            );
            let start_m = oncoming.random_range(0.0..span);
            push_object(
                &mut mesh,
                part,
                slot,
                true,
                Motion::Oncoming {
                    start_m,
                    speed_m_s: d.oncoming_speed_m_s,
                },
            );
        }

        mesh.orient_faces();
        for (buffer, bytes) in [
            ("vertices", std::mem::size_of_val(&mesh.vertices[..])),
            ("indices", std::mem::size_of_val(&mesh.indices[..])),
        ] {
            if bytes as u64 > limit {
                return Err(SceneError::TooLarge {
                    buffer,
                    bytes: bytes as u64,
                    limit,
                });
            }
        }
        Ok(Scene {
            description,
            route,
            terrain,
            mesh,
            chunks,
            objects,
        })
    }

    /// The description this scene was built from.
    pub fn description(&self) -> &SceneDescription {
        &self.description
    }

    /// The ground's height field, when the ground has bumps.
    pub fn terrain(&self) -> Option<&Terrain> {
        self.terrain.as_ref()
    }

    /// The route.
    pub fn route(&self) -> &Route {
        &self.route
    }

    /// All geometry, static then dynamic.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The static, cullable chunks.
    pub fn chunks(&self) -> &[Chunk] {
        &self.chunks
    }

    /// The moving objects.
    pub fn objects(&self) -> &[DynamicObject] {
        &self.objects
    }

    /// Where a dynamic object is at time `time_s`, given the two vehicles' poses. `None`
    /// when it is off the route (an oncoming vehicle not yet or no longer on the road).
    pub fn world_from_object(
        &self,
        object: &DynamicObject,
        world_from_chase: &Isometry3<f64>,
        world_from_lead: &Isometry3<f64>,
        time_s: f64,
    ) -> Option<Isometry3<f64>> {
        match object.motion {
            Motion::Chase => Some(*world_from_chase),
            Motion::Lead => Some(*world_from_lead),
            Motion::Oncoming { start_m, speed_m_s } => {
                let s = start_m - speed_m_s * time_s;
                if !(-ROAD_RUNOUT_M..self.route.length_m() + ROAD_RUNOUT_M).contains(&s) {
                    return None;
                }
                let lane = self.description.route.lane_width_m;
                let pose = self.route.pose_at(s, -0.5 * lane);
                let turn =
                    UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::PI);
                Some(Isometry3::from_parts(
                    pose.translation,
                    pose.rotation * turn,
                ))
            }
        }
    }

    /// The key of the grass lattice's hash (below 2²³, so it travels exactly as an f32),
    /// drawn from the scene's `"grass"` stream.
    pub fn grass_key(&self) -> u32 {
        stream(self.description.seed, "grass").random::<u32>() & 0x7f_ffff
    }

    /// The target's frame in the lead vehicle's frame: origin at the target model's centre,
    /// x right and y up as the chase camera sees the board (the model's axes), z out of the
    /// board towards the chase vehicle.
    pub fn lead_from_target(&self) -> Isometry3<f64> {
        lead_from_target(&self.description)
    }
}

fn lead_from_target(description: &SceneDescription) -> Isometry3<f64> {
    lead_from_target_of(&description.lead)
}

/// The target board's frame in the lead's scene frame (body centre), for a lead body: on its
/// back door, facing backwards.
pub fn lead_from_target_of(lead: &super::LeadVehicle) -> Isometry3<f64> {
    // Columns: target x = lead +z (the chase's right), target y = lead +y, target z = lead −x.
    let rotation = Rotation3::from_matrix_unchecked(Matrix3::new(
        0.0, 0.0, -1.0, //
        0.0, 1.0, 0.0, //
        1.0, 0.0, 0.0,
    ));
    Isometry3::from_parts(
        Translation3::new(
            -0.5 * lead.length_m - BOARD_STANDOFF_M,
            lead.board_centre_height_m,
            0.0,
        ),
        UnitQuaternion::from_rotation_matrix(&rotation),
    )
}

/// The lead vehicle (a box truck) with the target board on its back door, painted by the
/// paint rule, in the lead's frame.
fn lead_vehicle(description: &SceneDescription) -> Mesh {
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
    let to_lead = lead_from_target(description);
    let put = |x: f64, y: f64, z: f64| {
        let p = to_lead * Point3::new(x, y, z);
        [p.x, p.y, p.z]
    };
    let normal = [-1.0, 0.0, 0.0];
    let target = &description.target;
    // Validated with the target file; a model that cannot be painted with steps (only a
    // library caller could build one) is painted with stripes.
    let rects = tracker::paint::layout(target).unwrap_or_else(|_| tracker::paint::stripes(target));
    for (k, r) in rects.iter().enumerate() {
        let [x0, y0, x1, y1] = r.bounds_m;
        // The board lies on the door; what is painted on it stands just proud of it.
        let z = if k == 0 { 0.0 } else { STRIPE_STANDOFF_M };
        mesh.quad_with_normal(
            [
                put(x0, y0, z),
                put(x1, y0, z),
                put(x1, y1, z),
                put(x0, y1, z),
            ],
            normal,
            STRIPE_ALBEDO + r.tone * (BOARD_ALBEDO - STRIPE_ALBEDO),
            slot,
        );
    }
    // Controlled distractors, just in front of the board.
    for d in &lead.distractors {
        let orientation = target.orientations().nth(d.feature);
        let (near, outward) = super::distractor_near_side(target, d.feature, d.offset_m);
        let far = near + outward * d.width_m;
        let (a, b) = (near.min(far), near.max(far));
        let z = DISTRACTOR_STANDOFF_M;
        let ground = -lead.board_centre_height_m;
        let [x0, y0, x1, y1] = match d.kind {
            DistractorKind::Pole => [a, ground, b, ground + DISTRACTOR_POLE_M],
            DistractorKind::Wire => [-DISTRACTOR_REACH_M, a, DISTRACTOR_REACH_M, b],
            DistractorKind::Shadow { root_m, depth_m } => {
                // A fin 1 cm thick, as the board's light paint, both faces drawn so that it
                // casts a shadow whichever side the sun is on.
                let vertical = orientation == Some(tracker::Orientation::Vertical);
                let (along_lo, along_hi) = if vertical {
                    (ground, ground + 4.0)
                } else {
                    (-DISTRACTOR_REACH_M, DISTRACTOR_REACH_M)
                };
                for side in [-0.005, 0.005] {
                    let c = root_m + side;
                    let corners = if vertical {
                        [
                            put(c, along_lo, 0.0),
                            put(c, along_lo, depth_m),
                            put(c, along_hi, depth_m),
                            put(c, along_hi, 0.0),
                        ]
                    } else {
                        [
                            put(along_lo, c, 0.0),
                            put(along_hi, c, 0.0),
                            put(along_hi, c, depth_m),
                            put(along_lo, c, depth_m),
                        ]
                    };
                    let corners = if side < 0.0 {
                        [corners[3], corners[2], corners[1], corners[0]]
                    } else {
                        corners
                    };
                    mesh.polygon(&corners, BOARD_ALBEDO, slot);
                }
                continue;
            }
        };
        mesh.quad_with_normal(
            [
                put(x0, y0, z),
                put(x1, y0, z),
                put(x1, y1, z),
                put(x0, y1, z),
            ],
            normal,
            d.albedo,
            slot,
        );
    }
    mesh
}

/// A strip of road-parallel surface from station `s0` to `s1`, lateral `l0` to `l1`
/// (`[s0, s1, l0, l1]`), static, its vertices' `object` being `object` (the world's slot
/// and a [`Material`]).
fn strip(
    mesh: &mut Mesh,
    road: &RoadFrame<'_>,
    [s0, s1, l0, l1]: [f64; 4],
    y: f64,
    albedo: f64,
    object: u32,
) {
    let corners = [
        road.world(s0, l0, y),
        road.world(s1, l0, y),
        road.world(s1, l1, y),
        road.world(s0, l1, y),
    ];
    let pitch = road
        .terrain
        .filter(|t| corners.iter().any(|c| t.covers(c[0], c[2])))
        .map(|t| t.cell_m());
    let Some(pitch) = pitch else {
        mesh.polygon(&corners, albedo, object);
        return;
    };
    // Over bumps, a grid of pieces no longer than a cell, sharing vertices, for
    // `Terrain::drape` to raise.
    let (ns, nl) = (
        ((s1 - s0) / pitch).ceil().max(1.0) as usize,
        ((l1 - l0).abs() / pitch).ceil().max(1.0) as usize,
    );
    let base = mesh.vertices.len() as u32;
    for i in 0..=ns {
        for j in 0..=nl {
            let p = road.world(
                s0 + (s1 - s0) * i as f64 / ns as f64,
                l0 + (l1 - l0) * j as f64 / nl as f64,
                y,
            );
            mesh.vertices.push(Vertex {
                position: p.map(|x| x as f32),
                normal: [0.0, 1.0, 0.0],
                albedo: albedo as f32,
                object,
            });
        }
    }
    let at = |i: usize, j: usize| base + (i * (nl + 1) + j) as u32;
    for i in 0..ns {
        for j in 0..nl {
            // The winding of the polygon above: (s0, l0), (s1, l0), (s1, l1), (s0, l1).
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            mesh.indices.extend_from_slice(&[a, b, c, a, c, d]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{builtin_description, builtin_target, Distractor};

    /// A fingerprint of everything built: every vertex's and index's bits, every chunk and
    /// part (ranges, spheres, layer, shadows) and every object, in order (FNV-1a over their
    /// bytes). Equal fingerprints are the same scene, bit for bit, drawn in the same order.
    pub(in crate::scene) fn fingerprint(scene: &Scene) -> u64 {
        let mut bytes: Vec<u8> = Vec::new();
        let mut put = |words: &[u64]| {
            for w in words {
                bytes.extend_from_slice(&w.to_le_bytes());
            }
        };
        let mesh = scene.mesh();
        put(&[mesh.vertices.len() as u64, mesh.indices.len() as u64]);
        for v in &mesh.vertices {
            let [x, y, z] = v.position.map(|c| u64::from(c.to_bits()));
            let [nx, ny, nz] = v.normal.map(|c| u64::from(c.to_bits()));
            put(&[x, y, z, nx, ny, nz, u64::from(v.albedo.to_bits())]);
            put(&[u64::from(v.object)]);
        }
        put(&mesh
            .indices
            .iter()
            .map(|&i| u64::from(i))
            .collect::<Vec<_>>());
        let bits = |centre: [f64; 3], radius: f64| {
            let [x, y, z] = centre.map(f64::to_bits);
            [x, y, z, radius.to_bits()]
        };
        for c in scene.chunks() {
            put(&[u64::from(c.indices.start), u64::from(c.indices.end)]);
            put(&bits(c.centre, c.radius));
            put(&[c.casts_shadow as u64, c.layer as u64]);
            put(&[c.parts.len() as u64]);
            for part in &c.parts {
                put(&[u64::from(part.indices.start), u64::from(part.indices.end)]);
                put(&bits(part.centre, part.radius));
            }
        }
        for o in scene.objects() {
            put(&[u64::from(o.slot), u64::from(o.indices.start)]);
            put(&[u64::from(o.indices.end), o.casts_shadow as u64]);
            put(&bits(o.centre, o.radius));
            put(&[vehicle::fnv1a64(format!("{:?}", o.motion).as_bytes())]);
        }
        vehicle::fnv1a64(&bytes)
    }

    /// Descriptions that between them exercise every builder: the built-in scene at two
    /// seeds; over bumps, on gravel, with every hand placement, every kind of distractor
    /// and denser clutter.
    fn fingerprinted_descriptions() -> Vec<(&'static str, SceneDescription)> {
        let builtin = |seed| builtin_description(builtin_target(), seed);
        let mut everything = builtin(7);
        everything.ground = crate::scene::terrain::tests::bumpy_ground();
        everything.road_surface = RoadSurface::Gravel;
        everything.densities.houses_per_km *= 3.0;
        everything.densities.buildings_per_km += 8.0;
        everything.densities.parked_vehicles_per_km += 10.0;
        everything.densities.oncoming_vehicles_per_km += 10.0;
        everything.placements = vec![
            Placement::Pole {
                x_m: 4.0,
                z_m: 30.0,
            },
            Placement::Tree {
                x_m: -9.0,
                z_m: 45.0,
            },
            Placement::Overpass {
                station_m: 60.0,
                deck_m: 8.0,
                height_m: 5.0,
            },
        ];
        let distractor = |kind, feature| Distractor {
            kind,
            feature,
            offset_m: 0.05,
            width_m: 0.04,
            albedo: 0.2,
        };
        everything.lead.distractors = vec![
            distractor(DistractorKind::Pole, 0),
            distractor(DistractorKind::Wire, 1),
            distractor(
                DistractorKind::Shadow {
                    root_m: 0.1,
                    depth_m: 0.05,
                },
                0,
            ),
            distractor(
                DistractorKind::Shadow {
                    root_m: 0.1,
                    depth_m: 0.05,
                },
                1,
            ),
        ];
        vec![
            ("builtin seed 2", builtin(2)),
            ("builtin seed 3", builtin(3)),
            ("everything", everything),
        ]
    }

    /// The same description builds the same scene, bit for bit. Prints each description's
    /// [`fingerprint`] (`cargo test --release -p sim scene_fingerprints -- --nocapture`):
    /// a change meant to leave the scene as it was (a refactoring of the builders) must
    /// leave these numbers as they were before it.
    #[test]
    fn scene_fingerprints() {
        for (name, d) in fingerprinted_descriptions() {
            let print = fingerprint(&Scene::build(d.clone()).expect("scene"));
            assert_eq!(
                print,
                fingerprint(&Scene::build(d).expect("scene")),
                "{name}"
            );
            println!("scene fingerprint {name}: {print:016x}");
        }
    }

    /// The limit is the one the renderer's device has, and a scene over it is refused
    /// (not left for wgpu to panic on when the renderer uploads it).
    #[test]
    fn geometry_beyond_a_buffer_is_refused() {
        assert_eq!(
            MAX_BUFFER_BYTES,
            wgpu::Limits::downlevel_webgl2_defaults().max_buffer_size
        );
        let d = builtin_description(builtin_target(), 3);
        let scene = Scene::build(d.clone()).expect("the built-in scene fits");
        let bytes = std::mem::size_of_val(&scene.mesh().vertices[..]) as u64;
        assert!(Scene::build_within(d.clone(), bytes).is_ok());
        match Scene::build_within(d, bytes - 1) {
            Err(SceneError::TooLarge { buffer, limit, .. }) => {
                assert_eq!((buffer, limit), ("vertices", bytes - 1))
            }
            other => panic!("{:?}", other.map(|_| ())),
        }
    }

    /// Grass faces (albedo below 0, coloured per fragment) lie in the ground layer alone,
    /// and no object has any: the renderer draws the other layers and the objects with
    /// pipelines that leave the grass out. On flat ground and over bumps (the verges).
    #[test]
    fn grass_faces_lie_in_the_ground_layer_alone() {
        for ground in [
            vehicle::GroundConfig::default(),
            crate::scene::terrain::tests::bumpy_ground(),
        ] {
            let mut d = builtin_description(builtin_target(), 3);
            d.ground = ground;
            let scene = Scene::build(d).expect("scene");
            let mesh = scene.mesh();
            let grass = |range: &std::ops::Range<u32>| {
                mesh.indices[range.start as usize..range.end as usize]
                    .iter()
                    .filter(|&&i| mesh.vertices[i as usize].albedo < 0.0)
                    .count()
            };
            let mut in_ground = 0;
            for chunk in scene.chunks() {
                let n = grass(&chunk.indices);
                if chunk.layer == Layer::Ground {
                    in_ground += n;
                } else {
                    assert_eq!(n, 0, "grass faces in a {:?} chunk", chunk.layer);
                }
            }
            assert!(in_ground > 0, "the ground layer draws the grass");
            for object in scene.objects() {
                assert_eq!(
                    grass(&object.indices),
                    0,
                    "grass faces on {:?}",
                    object.slot
                );
            }
        }
    }

    /// The materials each surface carries: the road's as its surface says, the paint's, the
    /// grass's; canopies in their own layer, casting shadows; the slots unchanged.
    #[test]
    fn surfaces_carry_their_material_and_canopies_their_layer() {
        for (surface, road) in [
            (RoadSurface::Asphalt, Material::ASPHALT),
            (RoadSurface::Gravel, Material::GRAVEL),
        ] {
            let mut d = builtin_description(builtin_target(), 2);
            d.road_surface = surface;
            let scene = Scene::build(d).expect("scene");
            let materials = |layer: Layer| -> std::collections::BTreeSet<u32> {
                scene
                    .chunks()
                    .iter()
                    .filter(|c| c.layer == layer)
                    .flat_map(|c| {
                        &scene.mesh().indices[c.indices.start as usize..c.indices.end as usize]
                    })
                    .map(|&i| scene.mesh().vertices[i as usize].object)
                    .collect()
            };
            assert_eq!(
                materials(Layer::Surface),
                [road, Material::PAINT].into_iter().collect()
            );
            assert_eq!(
                materials(Layer::Ground),
                [Material::GRASS].into_iter().collect()
            );
            assert_eq!(
                materials(Layer::Clutter),
                [Material::NONE].into_iter().collect()
            );
            let foliage: Vec<&Chunk> = scene
                .chunks()
                .iter()
                .filter(|c| c.layer == Layer::Foliage)
                .collect();
            assert!(!foliage.is_empty() && foliage.iter().all(|c| c.casts_shadow));
            for object in scene.objects() {
                let range = object.indices.start as usize..object.indices.end as usize;
                assert!(scene.mesh().indices[range]
                    .iter()
                    .all(|&i| scene.mesh().vertices[i as usize].object == object.slot));
            }
        }
    }
}

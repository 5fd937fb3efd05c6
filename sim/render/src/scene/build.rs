//! Building the world's geometry from a [`SceneDescription`]: static geometry binned into
//! ground-plane cells (so the renderer can cull what it cannot see), and the moving objects
//! (chase hood, lead vehicle with its board, oncoming traffic) in their own frames.
//!
//! [`lay_static`] lays the world in a fixed order, which is part of what it builds: the
//! renderer draws each chunk's parts in the order they were laid, so coplanar pieces show
//! as they would drawn whole, and each builder draws from its own named random stream.
//! [`Scene::build`] runs it first to survey the districts laid in, then once for each group
//! of them (see `districts`), keeping each chunk's outline and the first groups' geometry.

use super::bins::{Bins, Cell, Keep, Survey};
use super::built_scene::Scene;
use super::chunk::{Chunk, ChunkPart};
use super::description::SceneDescription;
use super::districts::{self, Districts, Home, CACHED_GROUPS, GROUP_INDICES};
use super::error::{SceneError, MAX_BUFFER_BYTES};
use super::layer::Layer;
use super::mesh::{Mesh, Vertex};
use super::route::Route;
use super::site::Site;
use super::terrain::Terrain;
use super::{
    building, ground, house, parked_car, placement, pole_line, road, road_marks, street_lights,
    tree, vehicles, verge,
};
use std::collections::BTreeSet;
use std::ops::Range;
use std::sync::Arc;

impl Scene {
    /// Builds the world. Deterministic: the same description gives the same geometry,
    /// vertex for vertex.
    pub fn build(description: SceneDescription) -> Result<Scene, SceneError> {
        Self::build_within(description, MAX_BUFFER_BYTES, GROUP_INDICES)
    }

    /// [`Scene::build`], refusing geometry whose vertices or indices take more than
    /// `limit` bytes in all, its districts grouped by `budget` indices.
    pub(crate) fn build_within(
        description: SceneDescription,
        limit: u64,
        budget: usize,
    ) -> Result<Scene, SceneError> {
        description.validate()?;
        let route = Route::new(description.route.clone());
        let terrain = Terrain::new(&description.ground)?;
        let site = Site::new(&description, &route, terrain.as_ref());
        let survey = lay_static(&site, Keep::Survey(Survey::default())).into_survey();
        let groups = districts::group(&survey, budget);
        // Each group's chunks, with their cells and layers, and the first groups' meshes.
        let mut found: Vec<((Cell, Layer), Chunk, usize)> = Vec::new();
        let mut built = Vec::new();
        for (g, group) in groups.iter().enumerate() {
            let (mesh, chunks, keys) = static_geometry(&site, group);
            found.extend(
                keys.into_iter()
                    .zip(chunks)
                    .map(|(key, chunk)| (key, chunk, g)),
            );
            if g < CACHED_GROUPS {
                built.push((g, Arc::new(mesh)));
            }
        }
        // The chunks in the order of their cells and layers, as if laid in one mesh.
        found.sort_by_key(|(key, _, _)| *key);
        let (mut chunks, mut homes) = (Vec::new(), Vec::new());
        let (mut indices, mut vertices) = (0u32, 0u32);
        for (_, chunk, group) in found {
            let home = Home {
                group,
                indices: chunk.indices.clone(),
                vertices: chunk.vertices.clone(),
            };
            // Moved from where the chunk starts in its group's mesh to where it starts here.
            let from_group = |r: &Range<u32>, group: &Range<u32>, here: u32| {
                r.start - group.start + here..r.end - group.start + here
            };
            let parts = (chunk.parts.iter())
                .map(|p| ChunkPart {
                    indices: from_group(&p.indices, &chunk.indices, indices),
                    ..p.clone()
                })
                .collect();
            let chunk = Chunk {
                indices: from_group(&chunk.indices, &chunk.indices, indices),
                vertices: from_group(&chunk.vertices, &chunk.vertices, vertices),
                parts,
                ..chunk
            };
            (indices, vertices) = (chunk.indices.end, chunk.vertices.end);
            chunks.push(chunk);
            homes.push(home);
        }
        // The moving objects, after the static chunks.
        let mut objects_mesh = Mesh::default();
        let mut objects = vehicles::lay_objects(&site, &mut objects_mesh);
        objects_mesh.orient_faces();
        for object in &mut objects {
            object.indices = object.indices.start + indices..object.indices.end + indices;
        }
        fits(
            vertices as usize + objects_mesh.vertices.len(),
            indices as usize + objects_mesh.indices.len(),
            limit,
        )?;
        Ok(Scene {
            description,
            route,
            terrain,
            chunks,
            objects,
            objects_mesh,
            objects_start: indices,
            districts: Districts::new(groups, homes, built),
        })
    }

    /// Builds the static geometry of group `g` of the districts.
    pub(super) fn build_group(&self, g: usize) -> Mesh {
        let site = Site::new(&self.description, &self.route, self.terrain.as_ref());
        static_geometry(&site, &self.districts.groups[g]).0
    }
}

/// The static geometry laid in `districts`, its faces oriented, as chunks, with the cell and
/// layer of each.
fn static_geometry(
    site: &Site<'_>,
    districts: &BTreeSet<Cell>,
) -> (Mesh, Vec<Chunk>, Vec<(Cell, Layer)>) {
    let (mut mesh, chunks, keys) =
        lay_static(site, Keep::Districts(districts.clone())).into_chunks();
    mesh.orient_faces();
    (mesh, chunks, keys)
}

/// Lays the world's static geometry into bins keeping what `keep` says.
fn lay_static(site: &Site<'_>, keep: Keep) -> Bins {
    // The ground and the road,
    let mut bins = Bins::new(keep);
    ground::lay_grass(site, &mut bins);
    verge::lay(site, &mut bins);
    road::lay_surface(site, &mut bins);
    road::lay_centre_line(site, &mut bins);
    road::lay_crossings(site, &mut bins);
    road_marks::lay(site, &mut bins);
    // the roadside and the standing clutter,
    tree::lay_row(site, &mut bins);
    pole_line::lay(site, &mut bins);
    street_lights::lay(site, &mut bins);
    house::lay_row(site, &mut bins);
    building::lay_row(site, &mut bins);
    parked_car::lay_row(site, &mut bins);
    placement::lay(site, &mut bins);
    // and over bumps, the road's surfaces laid on the ground.
    ground::drape_surfaces(site, &mut bins);
    bins
}

/// Refuses geometry of `vertices` and `indices` if either takes more than `limit` bytes.
fn fits(vertices: usize, indices: usize, limit: u64) -> Result<(), SceneError> {
    for (buffer, bytes) in [
        ("vertices", vertices * std::mem::size_of::<Vertex>()),
        ("indices", indices * std::mem::size_of::<u32>()),
    ] {
        if bytes as u64 > limit {
            return Err(SceneError::TooLarge {
                buffer,
                bytes: bytes as u64,
                limit,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::chunk::Chunk;
    use crate::scene::description::{Distractor, DistractorKind, Placement, RoadSurface};
    use crate::scene::layer::Layer;
    use crate::scene::material::Material;
    use crate::scene::{builtin_description, builtin_target};

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
        let mesh = &scene.whole_mesh();
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

    /// Rain draws from no stream the scene's builders use: the cluttered scene (every
    /// builder) in heavy rain builds the same scene, bit for bit, as dry.
    #[test]
    fn rain_moves_no_draw_of_the_scene() {
        for (name, d) in fingerprinted_descriptions() {
            let dry = fingerprint(&Scene::build(d.clone()).expect("scene"));
            let mut wet = d;
            wet.rain = Some(crate::scene::Rain::new(16.0));
            assert_eq!(
                fingerprint(&Scene::build(wet).expect("scene")),
                dry,
                "{name}"
            );
        }
    }

    /// A scene built a district at a time, or in groups of a few, or all at once, is the
    /// same scene, bit for bit; and asked for again after its groups were let go, the same
    /// geometry comes back, while no more than [`CACHED_GROUPS`] groups are kept.
    #[test]
    fn a_scene_built_a_district_at_a_time_is_the_scene_built_whole() {
        for (name, d) in fingerprinted_descriptions() {
            let build = |budget| Scene::build_within(d.clone(), MAX_BUFFER_BYTES, budget);
            let whole = build(usize::MAX).expect("scene");
            assert_eq!(whole.districts.groups.len(), 1, "{name}");
            let print = fingerprint(&whole);
            for budget in [0, 20_000, GROUP_INDICES] {
                let scene = build(budget).expect("scene");
                assert_eq!(scene.chunks(), whole.chunks(), "{name}, {budget}");
                assert_eq!(fingerprint(&scene), print, "{name}, {budget}");
                assert!(scene.districts.kept() <= CACHED_GROUPS);
            }
            let apart = build(0).expect("scene");
            assert!(apart.districts.groups.len() > CACHED_GROUPS, "{name}");
            // Backwards, then forwards again: every group built again at least once.
            let n = apart.chunks().len();
            let visit = |order: Vec<usize>| {
                let mut pieces = Vec::new();
                apart.visit_chunks(order, |k, p| {
                    pieces.push((k, p.vertices.to_vec(), p.indices.to_vec(), p.base))
                });
                pieces
            };
            let pieces = visit((0..n).rev().collect());
            let mut again = visit((0..n).collect());
            again.reverse();
            assert_eq!(pieces, again, "{name}");
            assert!(apart.districts.kept() <= CACHED_GROUPS);
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
        let bytes = std::mem::size_of_val(&scene.whole_mesh().vertices[..]) as u64;
        assert!(Scene::build_within(d.clone(), bytes, GROUP_INDICES).is_ok());
        match Scene::build_within(d, bytes - 1, GROUP_INDICES) {
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
            let mesh = &scene.whole_mesh();
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
            let mesh = &scene.whole_mesh();
            let materials = |layer: Layer| -> std::collections::BTreeSet<u32> {
                scene
                    .chunks()
                    .iter()
                    .filter(|c| c.layer == layer)
                    .flat_map(|c| &mesh.indices[c.indices.start as usize..c.indices.end as usize])
                    .map(|&i| mesh.vertices[i as usize].object)
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
                assert!(mesh.indices[range]
                    .iter()
                    .all(|&i| mesh.vertices[i as usize].object == object.slot));
            }
        }
    }
}

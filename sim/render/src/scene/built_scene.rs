//! The built world: the `Scene` type, what it holds, and where its moving objects are.
//! (`Scene::build`, which lays it, is in `build.rs`.)

use super::chunk::Chunk;
use super::description::SceneDescription;
use super::districts::Districts;
use super::dynamic_object::{DynamicObject, Motion};
use super::mesh::{Mesh, MeshPiece};
use super::rng::stream;
use super::route::Route;
use super::site::ROAD_RUNOUT_M;
use super::target_board::lead_from_target_of;
use super::terrain::Terrain;
use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use rand::Rng;
use std::ops::Range;

/// The built world: static chunks and moving objects, plus the description.
///
/// Its geometry lies in one index space, as if in one mesh: the static chunks' indices in
/// the order of their cells and layers, then the moving objects'. The objects' geometry is
/// kept; the chunks' is built a group of districts at a time when asked for, and only the
/// groups used last are kept (see `districts`), so a long route costs little more memory
/// than a short one. Asked for again, a chunk's geometry is the same, vertex for vertex.
#[derive(Clone, Debug)]
pub struct Scene {
    pub(super) description: SceneDescription,
    pub(super) route: Route,
    pub(super) terrain: Option<Terrain>,
    pub(super) chunks: Vec<Chunk>,
    pub(super) objects: Vec<DynamicObject>,
    /// The moving objects' geometry, its indices naming its own vertices.
    pub(super) objects_mesh: Mesh,
    /// Where the objects' indices start in the scene's index space.
    pub(super) objects_start: u32,
    /// Where the static chunks' geometry lies, and what of it is built.
    pub(super) districts: Districts,
}

impl Scene {
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

    /// The static, cullable chunks.
    pub fn chunks(&self) -> &[Chunk] {
        &self.chunks
    }

    /// The moving objects.
    pub fn objects(&self) -> &[DynamicObject] {
        &self.objects
    }

    /// The moving objects' indices in the scene's index space: after every static chunk's,
    /// to the end.
    pub fn objects_indices(&self) -> Range<u32> {
        let start = self.objects_start;
        start..start + self.objects_mesh.indices.len() as u32
    }

    /// The moving objects' geometry.
    pub fn objects_geometry(&self) -> MeshPiece<'_> {
        MeshPiece {
            vertices: &self.objects_mesh.vertices,
            indices: &self.objects_mesh.indices,
            base: 0,
        }
    }

    /// Calls `f` with each of `chunks` (indices into [`Scene::chunks`]), in order, and its
    /// geometry, built if it is not kept.
    pub fn visit_chunks(
        &self,
        chunks: impl IntoIterator<Item = usize>,
        mut f: impl FnMut(usize, MeshPiece<'_>),
    ) {
        let chunks: Vec<usize> = chunks.into_iter().collect();
        if chunks.is_empty() {
            return;
        }
        let homes = &self.districts.homes;
        let mut groups: Vec<usize> = chunks.iter().map(|&k| homes[k].group).collect();
        groups.sort_unstable();
        groups.dedup();
        let meshes = self.districts.meshes(&groups, |g| self.build_group(g));
        for k in chunks {
            let home = &homes[k];
            let mesh = &meshes[groups
                .binary_search(&home.group)
                .expect("its group is built")];
            let (v, i) = (&home.vertices, &home.indices);
            f(
                k,
                MeshPiece {
                    vertices: &mesh.vertices[v.start as usize..v.end as usize],
                    indices: &mesh.indices[i.start as usize..i.end as usize],
                    base: v.start,
                },
            );
        }
    }

    /// All the scene's geometry in one mesh, its index space the scene's (every chunk's
    /// [`Chunk::indices`] and every object's [`DynamicObject::indices`] index it): for
    /// tests and tools, since it is as large as the whole route's.
    pub fn whole_mesh(&self) -> Mesh {
        let mut mesh = Mesh::default();
        self.visit_chunks(0..self.chunks.len(), |_, piece| mesh.append_piece(piece));
        mesh.append_piece(self.objects_geometry());
        mesh
    }

    /// Where a dynamic object is at time `time_s`, given the two vehicles' poses and the
    /// actors' (`world_from_actors`, one per description actor, in order). `None` when it
    /// is off the route (an oncoming vehicle not yet or no longer on the road), or an actor
    /// `world_from_actors` has no pose for.
    pub fn world_from_object(
        &self,
        object: &DynamicObject,
        world_from_chase: &Isometry3<f64>,
        world_from_lead: &Isometry3<f64>,
        world_from_actors: &[Isometry3<f64>],
        time_s: f64,
    ) -> Option<Isometry3<f64>> {
        match object.motion {
            Motion::Chase => Some(*world_from_chase),
            Motion::Lead => Some(*world_from_lead),
            Motion::Actor(k) => world_from_actors.get(k).copied(),
            Motion::Oncoming { start_m, speed_m_s } => {
                let s = start_m - speed_m_s * time_s;
                if !(-ROAD_RUNOUT_M..self.route.length_m() + ROAD_RUNOUT_M).contains(&s) {
                    return None;
                }
                // Lane 1 of the oncoming side, beside the centre line.
                let lateral = -self.description.route.lane_centre_m(1);
                let pose = self.route.pose_at(s, lateral);
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
        lead_from_target_of(&self.description.lead)
    }
}

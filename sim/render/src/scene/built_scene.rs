//! The built world: the `Scene` type, what it holds, and where its moving objects are.
//! (`Scene::build`, which lays it, is in `build.rs`.)

use super::chunk::Chunk;
use super::description::SceneDescription;
use super::dynamic_object::{DynamicObject, Motion};
use super::mesh::Mesh;
use super::rng::stream;
use super::route::Route;
use super::site::ROAD_RUNOUT_M;
use super::target_board::lead_from_target_of;
use super::terrain::Terrain;
use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use rand::Rng;

/// The built world: one mesh with static chunks and dynamic objects, plus the description.
#[derive(Clone, Debug)]
pub struct Scene {
    pub(super) description: SceneDescription,
    pub(super) route: Route,
    pub(super) terrain: Option<Terrain>,
    pub(super) mesh: Mesh,
    pub(super) chunks: Vec<Chunk>,
    pub(super) objects: Vec<DynamicObject>,
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
        lead_from_target_of(&self.description.lead)
    }
}

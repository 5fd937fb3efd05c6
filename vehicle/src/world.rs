//! The physics world: the ground, the vehicles and the fixed 120 Hz step.

use crate::clock::{Step, PHYSICS_DT_S};
use crate::controls::Controls;
use crate::error::VehicleError;
use crate::ground::{Ground, GroundConfig};
use crate::ray_cast_vehicle::{Vehicle, VehicleState};
use crate::vehicle_params::{VehicleParams, GRAVITY_MPS2};
use rapier3d::parry::utils::Array2;
use rapier3d::prelude::*;
use serde::{Deserialize, Serialize};

/// Thickness of the flat ground slab under y = 0, m (thick enough that nothing tunnels).
const GROUND_SLAB_M: f32 = 1.0;

/// Which vehicle of a [`World`]: handed out by [`World::add_vehicle`].
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct VehicleId(usize);

/// The physics world's configuration.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct WorldConfig {
    /// The ground's shape.
    pub ground: GroundConfig,
}

/// Rapier's world with the ground and the vehicles, stepped at the fixed physics rate.
///
/// Each [`World::step`] advances exactly one physics step of 1/120 s; the clock is the
/// step count ([`World::now`]).
pub struct World {
    physics: PhysicsWorld,
    ground: Ground,
    vehicles: Vec<Vehicle>,
    now: Step,
}

impl World {
    /// A world with its ground and no vehicles, at step 0.
    pub fn new(config: &WorldConfig) -> Result<World, VehicleError> {
        let ground = Ground::new(&config.ground)?;
        let mut physics = PhysicsWorld::new();
        physics.gravity = Vector::new(0.0, -GRAVITY_MPS2, 0.0);
        physics.integration_parameters.dt = PHYSICS_DT_S;
        let h = config.ground.half_extent_m;
        let grid = ground.shared_grid();
        // Under a profile the slab's top is the heightfield's lowest point (or y = 0), so
        // that it never stands above the ground the wheels roll on.
        let slab_top = match (&config.ground.profile, &grid) {
            (Some(_), Some(g)) => g.heights.iter().fold(0.0f32, |m, &v| m.min(v)),
            _ => 0.0,
        };
        physics.insert_collider(
            ColliderBuilder::cuboid(h, 0.5 * GROUND_SLAB_M, h).translation(Vector::new(
                0.0,
                slab_top - 0.5 * GROUND_SLAB_M,
                0.0,
            )),
            None,
        );
        if let Some(g) = grid {
            let size = Vector::new(
                g.cell_m * (g.cols - 1) as f32,
                1.0,
                g.cell_m * (g.rows - 1) as f32,
            );
            // Rapier centres a heightfield on its collider's origin.
            let centre = Vector::new(0.5 * (g.x0_m + g.x1_m()), 0.0, 0.5 * (g.z0_m + g.z1_m()));
            let mut builder =
                ColliderBuilder::heightfield(Array2::new(g.rows, g.cols, g.heights.clone()), size);
            if config.ground.profile.is_some() {
                builder = builder.translation(centre);
            }
            physics.insert_collider(builder, None);
        }
        Ok(World {
            physics,
            ground,
            vehicles: Vec::new(),
            now: Step::ZERO,
        })
    }

    /// Adds a vehicle with its frame at `world_from_vehicle` (lifted onto the ground there)
    /// moving forward at `speed_mps`.
    pub fn add_vehicle(
        &mut self,
        params: &VehicleParams,
        world_from_vehicle: Pose,
        speed_mps: f32,
    ) -> Result<VehicleId, VehicleError> {
        params.validate()?;
        let mut placed = world_from_vehicle;
        let t = placed.translation;
        placed.translation.y = self.ground.height_m(t.x, t.z);
        let vehicle = Vehicle::spawn(&mut self.physics, params, placed, speed_mps);
        self.vehicles.push(vehicle);
        Ok(VehicleId(self.vehicles.len() - 1))
    }

    /// Sets what the vehicle's actuators are asked to do from the next step on.
    pub fn set_controls(&mut self, id: VehicleId, controls: Controls) {
        self.vehicles[id.0].set_command(controls);
    }

    /// Advances the world by one physics step (1/120 s).
    pub fn step(&mut self) {
        for vehicle in &mut self.vehicles {
            vehicle.apply(&mut self.physics);
        }
        self.physics.step();
        self.now = self.now.next();
    }

    /// The present time, in physics steps since the start.
    pub fn now(&self) -> Step {
        self.now
    }

    /// The vehicle's state from the physics (ground truth).
    pub fn vehicle_state(&self, id: VehicleId) -> VehicleState {
        self.vehicles[id.0].state(&self.physics.bodies)
    }

    /// The vehicle itself (parameters, wheels, handles).
    pub fn vehicle(&self, id: VehicleId) -> &Vehicle {
        &self.vehicles[id.0]
    }

    /// The vehicle with this index, if there is one (for ids read back from elsewhere).
    pub fn vehicle_id(&self, index: usize) -> Result<VehicleId, VehicleError> {
        if index < self.vehicles.len() {
            Ok(VehicleId(index))
        } else {
            Err(VehicleError::UnknownVehicle(index))
        }
    }

    /// Rapier's world, read-only (for scene queries and debug drawing; stepping and
    /// changes go through [`World`] so the clock stays true).
    pub fn physics(&self) -> &PhysicsWorld {
        &self.physics
    }

    /// The ids of all vehicles, in the order they were added.
    pub fn vehicle_ids(&self) -> impl Iterator<Item = VehicleId> {
        (0..self.vehicles.len()).map(VehicleId)
    }

    /// The ground.
    pub fn ground(&self) -> &Ground {
        &self.ground
    }

    /// Whether the two vehicles' bodies are touching now.
    pub fn vehicles_touch(&self, a: VehicleId, b: VehicleId) -> bool {
        let ca = self.vehicles[a.0].chassis_collider();
        let cb = self.vehicles[b.0].chassis_collider();
        self.physics
            .contact_pair(ca, cb)
            .is_some_and(|pair| pair.has_any_active_contact())
    }
}

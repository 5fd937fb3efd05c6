//! One vehicle in the physics world: a rapier chassis on four ray-cast wheels, with its
//! steering, throttle and brake actuators.

use crate::actuator::Actuator;
use crate::clock::PHYSICS_DT_S;
use crate::controls::Controls;
use crate::vehicle_params::{VehicleParams, GRAVITY_MPS2};
use rapier3d::control::{DynamicRayCastVehicleController, WheelTuning};
use rapier3d::prelude::*;

/// Wheel order in [`Vehicle::wheels`]: front-left, front-right, rear-left, rear-right.
const WHEEL_COUNT: usize = 4;
/// Below this brake command (0..1) the brake is taken as released and the engine may drive.
const BRAKE_RELEASED: f32 = 0.01;
/// Each suspension may push up to this many times its static share of the weight (bumps and
/// hard braking load the springs; rapier's default cap of 6 kN is for a much lighter car).
const SUSPENSION_FORCE_HEADROOM: f32 = 4.0;

/// What a vehicle is doing right now, read from the physics (ground truth).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct VehicleState {
    /// The vehicle frame in the world frame (origin at the middle of the rear axle, at
    /// ground level at nominal ride height; x forward, y up, z right).
    pub world_from_vehicle: Pose,
    /// Speed along the vehicle's x axis, m/s (negative when reversing).
    pub forward_speed_mps: f32,
    /// Velocity of the vehicle-frame origin in the world frame, m/s.
    pub velocity_mps: Vector,
    /// Yaw rate about the world's +y, rad/s (positive turning left).
    pub yaw_rate_radps: f32,
    /// Pitch, rad (positive nose up).
    pub pitch_rad: f32,
    /// Roll, rad (positive right side down).
    pub roll_rad: f32,
    /// Road-wheel angle the steering actuator has reached, rad (positive left).
    pub steer_rad: f32,
    /// Throttle the actuator has reached, 0..1.
    pub throttle: f32,
    /// Brake the actuator has reached, 0..1.
    pub brake: f32,
}

/// A ray-cast vehicle: chassis handles, the rapier wheel controller and the actuators.
#[derive(Clone, Debug)]
pub struct Vehicle {
    params: VehicleParams,
    chassis: RigidBodyHandle,
    chassis_collider: ColliderHandle,
    wheels: DynamicRayCastVehicleController,
    steer: Actuator,
    throttle: Actuator,
    brake: Actuator,
    command: Controls,
}

impl Vehicle {
    /// Builds the chassis and wheels in `physics` with the vehicle frame at `world_from_vehicle`
    /// (its origin on the ground) moving forward at `speed_mps`. `params` must be valid.
    pub(crate) fn spawn(
        physics: &mut PhysicsWorld,
        params: &VehicleParams,
        world_from_vehicle: Pose,
        speed_mps: f32,
    ) -> Vehicle {
        let forward = world_from_vehicle.rotation * Vector::X;
        let body = RigidBodyBuilder::dynamic()
            .pose(world_from_vehicle)
            .linvel(forward * speed_mps)
            .can_sleep(false);
        let half = Vector::new(
            0.5 * params.length_m,
            0.5 * params.body_height_m,
            0.5 * params.width_m,
        );
        let centre = Vector::new(
            0.5 * (params.front_bumper_x_m() + params.rear_bumper_x_m()),
            params.ground_clearance_m + half.y,
            0.0,
        );
        let collider = ColliderBuilder::cuboid(half.x, half.y, half.z)
            .translation(centre)
            .mass(params.mass_kg);
        let (chassis, chassis_collider) = physics.insert(body, collider);

        let stiffness = params.suspension_stiffness_per_s2();
        let damping = params.suspension_damping_per_s();
        let tuning = WheelTuning {
            suspension_stiffness: stiffness,
            suspension_compression: damping,
            suspension_damping: damping,
            max_suspension_travel: params.suspension_travel_m,
            side_friction_stiffness: 1.0,
            friction_slip: params.tyre_friction,
            max_suspension_force: SUSPENSION_FORCE_HEADROOM * params.mass_kg * GRAVITY_MPS2
                / WHEEL_COUNT as f32,
        };
        // The hard point sits so that at static load the wheel just touches y = 0.
        let hard_point_y =
            params.wheel_radius_m + params.suspension_rest_m - params.static_compression_m();
        let mut wheels = DynamicRayCastVehicleController::new(chassis);
        let half_track = 0.5 * params.track_m;
        for (x, z) in [
            (params.wheelbase_m, -half_track),
            (params.wheelbase_m, half_track),
            (0.0, -half_track),
            (0.0, half_track),
        ] {
            wheels.add_wheel(
                Vector::new(x, hard_point_y, z),
                -Vector::Y,
                Vector::Z,
                params.suspension_rest_m,
                params.wheel_radius_m,
                &tuning,
            );
        }
        Vehicle {
            params: params.clone(),
            chassis,
            chassis_collider,
            wheels,
            steer: Actuator::new(params.steer_limits(), 0.0),
            throttle: Actuator::new(params.throttle_limits(), 0.0),
            brake: Actuator::new(params.brake_limits(), 0.0),
            command: Controls::default(),
        }
    }

    /// The vehicle's parameters.
    pub fn params(&self) -> &VehicleParams {
        &self.params
    }

    /// The chassis rigid body.
    pub fn chassis(&self) -> RigidBodyHandle {
        self.chassis
    }

    /// The chassis collider.
    pub fn chassis_collider(&self) -> ColliderHandle {
        self.chassis_collider
    }

    /// The rapier wheels (for drawing them: centres, steering, spin).
    pub fn wheels(&self) -> &[rapier3d::control::Wheel] {
        self.wheels.wheels()
    }

    /// The last command given.
    pub fn command(&self) -> Controls {
        self.command
    }

    /// Sets the command the actuators will follow from the next step on.
    pub(crate) fn set_command(&mut self, command: Controls) {
        self.command = command;
    }

    /// Reads the vehicle's state from the physics.
    pub(crate) fn state(&self, bodies: &RigidBodySet) -> VehicleState {
        let body = &bodies[self.chassis];
        let world_from_vehicle = *body.position();
        let rotation = world_from_vehicle.rotation;
        let forward = rotation * Vector::X;
        let right = rotation * Vector::Z;
        let velocity = body.velocity_at_point(world_from_vehicle.translation);
        VehicleState {
            world_from_vehicle,
            forward_speed_mps: velocity.dot(forward),
            velocity_mps: velocity,
            yaw_rate_radps: body.angvel().y,
            pitch_rad: forward.y.clamp(-1.0, 1.0).asin(),
            roll_rad: (-right.y).clamp(-1.0, 1.0).asin(),
            steer_rad: self.steer.value(),
            throttle: self.throttle.value(),
            brake: self.brake.value(),
        }
    }

    /// Advances the actuators one step and hands their outputs to the wheels and chassis;
    /// then lets the ray-cast wheels push on the chassis. Call once per physics step, before
    /// the rapier step.
    pub(crate) fn apply(&mut self, physics: &mut PhysicsWorld) {
        let dt = PHYSICS_DT_S;
        let steer = self.steer.update(self.command.steer_rad, dt);
        let mut throttle = self.throttle.update(self.command.throttle, dt);
        let brake = self.brake.update(self.command.brake, dt);
        if brake > BRAKE_RELEASED {
            throttle = 0.0;
        }

        let speed = self.state(&physics.bodies).forward_speed_mps;
        let p = &self.params;
        let driven = if p.four_wheel_drive { 4.0 } else { 2.0 };
        let drive_per_wheel = throttle * p.available_drive_force_n(speed) / driven;
        let brake_impulse_per_wheel = brake * p.max_brake_force_n / WHEEL_COUNT as f32 * dt;
        // Ackermann: each front wheel points at the turn centre of the bicycle model.
        let curvature = steer.tan() / p.wheelbase_m;
        for (i, wheel) in self.wheels.wheels_mut().iter_mut().enumerate() {
            let front = i < 2;
            let z = if i % 2 == 0 { -0.5 } else { 0.5 } * p.track_m;
            wheel.steering = if front {
                (p.wheelbase_m * curvature / (1.0 + curvature * z)).atan()
            } else {
                0.0
            };
            let is_driven = p.four_wheel_drive || !front;
            wheel.engine_force = if is_driven { drive_per_wheel } else { 0.0 };
            wheel.brake = brake_impulse_per_wheel;
        }

        // Air drag and rolling resistance, against the horizontal velocity.
        let body = &mut physics.bodies[self.chassis];
        let v = body.linvel();
        let horizontal = Vector::new(v.x, 0.0, v.z);
        let speed_h = horizontal.length();
        if speed_h > 1e-3 {
            let resistance = p.resistance_n(speed_h);
            body.apply_impulse(-horizontal / speed_h * resistance * dt, true);
        }

        let queries = physics.broad_phase.as_query_pipeline_mut(
            physics.narrow_phase.query_dispatcher(),
            &mut physics.bodies,
            &mut physics.colliders,
            QueryFilter::exclude_dynamic(),
        );
        self.wheels.update_vehicle(dt, queries);
    }
}

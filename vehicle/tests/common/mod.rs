//! A closed loop for the integration tests: the physics world, the lead driver, the chase
//! controller and the delay line, with a perfect (ground-truth) sensor in place of the
//! camera and tracker. This is the loop `sim` runs, minus rendering and tracking.

#![allow(dead_code)]

pub mod events;

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use vehicle::*;

/// Gaussian sensor noise on the stand-in tracker's output (camera frame).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SensorNoise {
    /// Standard deviation across the image (camera x and y), m.
    pub lateral_sigma_m: f32,
    /// Standard deviation of the range as a fraction of it (the tracker's scale error).
    pub range_sigma_fraction: f32,
    pub seed: u64,
}

/// Height of the tracked target on the lead's back above the ground, m.
pub const TARGET_HEIGHT_M: f32 = 1.2;

/// What the stand-in sensor reports.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Sensor {
    /// The true position every frame, status tracking.
    Perfect,
    /// Perfect until this time (s), then every frame says `lost`.
    LostAfter(f64),
    /// Perfect until this time (s), then nothing at all.
    SilentAfter(f64),
    /// Perfect until this time (s), then every frame says `coasting` (with the true
    /// position: a prediction).
    CoastingAfter(f64),
}

/// How to set up a run.
pub struct RigOptions {
    pub route: Route,
    pub profile: SpeedProfile,
    pub lead_config: LeadDriverConfig,
    pub chase_config: ChaseControllerConfig,
    pub delay: DelayLineConfig,
    pub world: WorldConfig,
    /// Arc length of the lead's rear axle at the start, m.
    pub lead_start_m: f32,
    /// Initial camera-to-target gap, m.
    pub initial_gap_m: f32,
    /// Initial speed of both vehicles, m/s.
    pub initial_speed_mps: f32,
    pub sensor: Sensor,
    pub noise: Option<SensorNoise>,
}

impl RigOptions {
    /// Straight route, lead at 10 m/s, 10 m gap, default configs.
    pub fn straight(length_m: f32, profile: SpeedProfile) -> RigOptions {
        RigOptions {
            route: RouteBuilder::new(Vector::ZERO, 0.0)
                .straight(length_m)
                .build()
                .unwrap(),
            profile,
            lead_config: LeadDriverConfig::default(),
            chase_config: ChaseControllerConfig::default(),
            delay: DelayLineConfig::default(),
            world: WorldConfig::default(),
            lead_start_m: 40.0,
            initial_gap_m: 10.0,
            initial_speed_mps: 10.0,
            sensor: Sensor::Perfect,
            noise: None,
        }
    }
}

/// One physics step of truth and commands.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Sample {
    pub step: Step,
    pub chase: VehicleState,
    pub lead: VehicleState,
    /// Horizontal distance from the chase camera to the target, m (what the gap keeper holds).
    pub gap_m: f32,
    /// Lead's rear bumper ahead of the chase's front bumper along the chase's x, m.
    pub bumper_gap_m: f32,
    pub chase_controls: Controls,
    pub telemetry: ChaseTelemetry,
    pub touching: bool,
}

/// The closed loop.
pub struct Rig {
    pub world: World,
    pub chase_id: VehicleId,
    pub lead_id: VehicleId,
    pub chase: ChaseController,
    pub lead: LeadDriver,
    pub delay: DelayLine<LeadEstimate>,
    pub vehicle_from_camera: Pose,
    pub target_in_lead: Vector,
    pub sensor: Sensor,
    pub noise: Option<(SensorNoise, ChaCha8Rng)>,
    pub samples: Vec<Sample>,
}

/// One standard normal draw (Box–Muller).
fn gaussian(rng: &mut ChaCha8Rng) -> f32 {
    let u1: f32 = rng.random_range(f32::EPSILON..1.0);
    let u2: f32 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (std::f32::consts::TAU * u2).cos()
}

impl Rig {
    pub fn new(opts: RigOptions) -> Rig {
        let mut world = World::new(&opts.world).unwrap();
        let chase_params = VehicleParams::hmmwv_m998();
        let lead_params = VehicleParams::pickup();
        let route = opts.route;
        let heading_at = |s: f32| direction_heading(route.tangent_at(s));
        let pose_at =
            |s: f32| Pose::from_parts(route.point_at(s), Rotation::from_rotation_y(heading_at(s)));
        let lead_id = world
            .add_vehicle(
                &lead_params,
                pose_at(opts.lead_start_m),
                opts.initial_speed_mps,
            )
            .unwrap();
        let mount = opts.chase_config.camera_mount;
        // Camera-to-target gap along a straight start: the target is on the lead's rear
        // bumper, the camera `forward_m` ahead of the chase's rear axle.
        let chase_s = opts.lead_start_m + lead_params.rear_bumper_x_m()
            - opts.initial_gap_m
            - mount.forward_m;
        let chase_id = world
            .add_vehicle(&chase_params, pose_at(chase_s), opts.initial_speed_mps)
            .unwrap();
        let chase =
            ChaseController::new(opts.chase_config, &chase_params, opts.initial_speed_mps).unwrap();
        let lead = LeadDriver::new(route, opts.profile, opts.lead_config, &lead_params).unwrap();
        Rig {
            world,
            chase_id,
            lead_id,
            chase,
            lead,
            delay: DelayLine::new(&opts.delay).unwrap(),
            vehicle_from_camera: mount.vehicle_from_camera(),
            target_in_lead: Vector::new(lead_params.rear_bumper_x_m(), TARGET_HEIGHT_M, 0.0),
            sensor: opts.sensor,
            noise: opts
                .noise
                .map(|n| (n, named_stream(n.seed, "sensor_noise"))),
            samples: Vec::new(),
        }
    }

    /// The perfect sensor's reading for the frame captured now.
    fn sense(&mut self, now: Step) -> Option<LeadEstimate> {
        let chase = self.world.vehicle_state(self.chase_id);
        let lead = self.world.vehicle_state(self.lead_id);
        let world_from_camera = chase.world_from_vehicle * self.vehicle_from_camera;
        let target_world = lead.world_from_vehicle.transform_point(self.target_in_lead);
        let mut target_in_camera_m = world_from_camera.inverse_transform_point(target_world);
        if let Some((noise, rng)) = &mut self.noise {
            let scale = 1.0 + noise.range_sigma_fraction * gaussian(rng);
            let dx = noise.lateral_sigma_m * gaussian(rng);
            let dy = noise.lateral_sigma_m * gaussian(rng);
            target_in_camera_m = target_in_camera_m * scale + Vector::new(dx, dy, 0.0);
        }
        let t = now.seconds();
        let status = match self.sensor {
            Sensor::Perfect => TrackStatus::Tracking,
            Sensor::LostAfter(after) if t >= after => TrackStatus::Lost,
            Sensor::CoastingAfter(after) if t >= after => TrackStatus::Coasting,
            Sensor::SilentAfter(after) if t >= after => return None,
            _ => TrackStatus::Tracking,
        };
        Some(LeadEstimate {
            capture_step: now,
            target_in_camera_m,
            status,
            camera_pan_rad: 0.0,
        })
    }

    /// One physics step of the whole loop.
    pub fn step(&mut self) {
        let now = self.world.now();
        if now.is_frame_start() {
            if let Some(estimate) = self.sense(now) {
                self.delay.push(now, estimate);
            }
        }
        for estimate in self.delay.pop_due(now) {
            self.chase.receive(estimate);
        }
        let chase = self.world.vehicle_state(self.chase_id);
        let lead = self.world.vehicle_state(self.lead_id);
        let odometry = Odometry {
            step: now,
            world_from_chase: chase.world_from_vehicle,
            forward_speed_mps: chase.forward_speed_mps,
            camera_pan_rad: 0.0,
        };
        let chase_controls = self.chase.update(&odometry);
        let lead_controls = self.lead.update(now, &lead);
        self.world.set_controls(self.chase_id, chase_controls);
        self.world.set_controls(self.lead_id, lead_controls);

        let target_world = lead.world_from_vehicle.transform_point(self.target_in_lead);
        let target_in_chase = chase
            .world_from_vehicle
            .inverse_transform_point(target_world);
        let camera = self.vehicle_from_camera.translation;
        let gap_m = ((target_in_chase.x - camera.x).powi(2)
            + (target_in_chase.z - camera.z).powi(2))
        .sqrt();
        let chase_params = self.world.vehicle(self.chase_id).params();
        let bumper_gap_m = target_in_chase.x - chase_params.front_bumper_x_m();
        self.samples.push(Sample {
            step: now,
            chase,
            lead,
            gap_m,
            bumper_gap_m,
            chase_controls,
            telemetry: *self.chase.telemetry(),
            touching: self.world.vehicles_touch(self.chase_id, self.lead_id),
        });
        self.world.step();
    }

    /// Runs for `seconds` of simulated time.
    pub fn run_for(&mut self, seconds: f64) {
        let steps = (seconds * f64::from(PHYSICS_HZ)).round() as u64;
        for _ in 0..steps {
            self.step();
        }
    }

    /// Samples from `from_s` seconds on.
    pub fn samples_after(&self, from_s: f64) -> impl Iterator<Item = &Sample> {
        self.samples
            .iter()
            .filter(move |s| s.step.seconds() >= from_s)
    }
}

/// Distance from `p` to the polyline `path` in the ground plane.
pub fn distance_to_polyline(path: &[Vector], p: Vector) -> f32 {
    let flat = |v: Vector| Vector::new(v.x, 0.0, v.z);
    let p = flat(p);
    path.windows(2)
        .map(|w| {
            let (a, b) = (flat(w[0]), flat(w[1]));
            let ab = b - a;
            let t = if ab.length_squared() > 0.0 {
                ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            p.distance(a + ab * t)
        })
        .fold(f32::INFINITY, f32::min)
}

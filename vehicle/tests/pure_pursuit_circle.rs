//! Guarantees that pure pursuit on a circular path of known radius R converges to the
//! curvature 1/R: first for an ideal kinematic bicycle started off the circle (the law
//! itself), then for the rapier HMMWV driven by the lead driver's pure pursuit (the law
//! with tyres, actuators and suspension).
//!
//! Run: `CARGO_TARGET_DIR=/work/main/target cargo test -p vehicle --release --test pure_pursuit_circle`

mod common;
use vehicle::*;

fn circle(radius_m: f32, laps: f32) -> Route {
    RouteBuilder::new(Vector::ZERO, 0.0)
        .arc(radius_m, laps * std::f32::consts::TAU)
        .build()
        .unwrap()
}

#[test]
fn kinematic_bicycle_converges_to_one_over_r() {
    let r = 20.0f32;
    let route = circle(r, 1.5);
    let path = route.points().to_vec();
    let lookahead = LookAhead::default();
    let wheelbase = 3.3f32;
    let speed = 8.0f32;
    let dt = PHYSICS_DT_S;
    // Start 1.5 m outside the circle (to the right of +x at the origin) with a heading error.
    let mut p = Vector::new(0.0, 0.0, 1.5);
    let mut heading = -0.15f32;
    let mut curvature = 0.0;
    let mut progress = 0usize;
    for _ in 0..(20.0 / dt) as usize {
        let world_from_vehicle = Pose::from_parts(p, Rotation::from_rotation_y(heading));
        // Search from a little behind the closest point, as the breadcrumb trail does.
        let s = route.project_near(p, progress as f32, 30.0).s_m;
        progress = s as usize;
        let start = path.partition_point(|q| route.project_near(*q, s, 30.0).s_m < s - 1.0);
        let target = lookahead_point(&path[start..], p, lookahead.distance_m(speed)).unwrap();
        curvature = curvature_toward(&world_from_vehicle, target);
        let steer = steer_for_curvature(curvature, wheelbase).clamp(-0.6, 0.6);
        let k = steer.tan() / wheelbase;
        heading += speed * k * dt;
        p += heading_direction(heading) * speed * dt;
    }
    let centre = Vector::new(0.0, 0.0, -r);
    let radius_now = p.distance(centre);
    println!(
        "kinematic: curvature {curvature:.5} (1/R = {:.5}), radius {radius_now:.3}",
        1.0 / r
    );
    assert!(
        (curvature - 1.0 / r).abs() < 0.01 / r,
        "curvature {curvature}"
    );
    assert!((radius_now - r).abs() < 0.05, "radius {radius_now}");
}

#[test]
fn rapier_vehicle_under_pure_pursuit_converges_to_one_over_r() {
    let r = 25.0f32;
    let route = circle(r, 2.0);
    let params = VehicleParams::hmmwv_m998();
    let mut world = World::new(&WorldConfig::default()).unwrap();
    let speed = 6.0;
    let id = world
        .add_vehicle(
            &params,
            Pose::from_translation(Vector::new(0.0, 0.0, 1.0)),
            speed,
        )
        .unwrap();
    let mut driver = LeadDriver::new(
        route,
        SpeedProfile::constant(speed),
        LeadDriverConfig::default(),
        &params,
    )
    .unwrap();
    let mut curvatures = Vec::new();
    let mut radii = Vec::new();
    let centre = Vector::new(0.0, 0.0, -r);
    for i in 0..(25 * PHYSICS_HZ) {
        let state = world.vehicle_state(id);
        let controls = driver.update(world.now(), &state);
        world.set_controls(id, controls);
        world.step();
        if i >= 15 * PHYSICS_HZ {
            let s = world.vehicle_state(id);
            curvatures.push(s.yaw_rate_radps / s.forward_speed_mps);
            radii.push(s.world_from_vehicle.translation.distance(centre));
        }
    }
    let mean = curvatures.iter().sum::<f32>() / curvatures.len() as f32;
    let worst_radius = radii.iter().map(|q| (q - r).abs()).fold(0.0f32, f32::max);
    println!(
        "rapier: path curvature {mean:.5} (1/R = {:.5}), worst radius error {worst_radius:.3} m",
        1.0 / r
    );
    assert!((mean - 1.0 / r).abs() < 0.03 / r, "curvature {mean}");
    assert!(worst_radius < 0.3, "radius error {worst_radius}");
}

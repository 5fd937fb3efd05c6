//! A road that rises and falls: on a ground with a profile, a vehicle driving the road has
//! its height and pitch follow the road's, and the ground beside the road is as high as the
//! road abreast.
//!
//! Run: `cargo test -p vehicle --release --test ground_profile`

use vehicle::*;

/// The road's height at x (m), written out independently of the crate: a crest (grade
/// +6 % to −6 %, vertical radius 2,500 m) over 0–300 m, a sag back to level over 300–450 m,
/// level before and after.
fn road_height(x: f64) -> f64 {
    let x = x.clamp(0.0, 450.0);
    if x <= 300.0 {
        0.06 * x - 0.0002 * x * x
    } else {
        let d = x - 300.0;
        -0.06 * d + 0.0002 * d * d
    }
}

/// The road as a ground profile: its centreline along +x sampled every metre.
fn ground() -> GroundConfig {
    let points = (-100..=600)
        .map(|k| {
            let x = k as f64;
            [x, 0.0, road_height(x)]
        })
        .collect();
    GroundConfig {
        profile: Some(GroundProfile {
            points,
            cell_m: 1.0,
            margin_m: 40.0,
        }),
        ..GroundConfig::default()
    }
}

#[test]
fn the_ground_beside_the_road_is_the_road_abreast() {
    let g = Ground::new(&ground()).unwrap();
    for k in 0..400 {
        let x = -20.0 + 1.37 * k as f64;
        let z = -35.0 + 0.17 * k as f64;
        let h = f64::from(g.height_m(x as f32, z as f32));
        assert!((h - road_height(x)).abs() < 1e-3, "({x}, {z}): {h}");
    }
    let grid = g.grid().unwrap();
    assert_eq!(grid.cell_m, 1.0);
    assert!(grid.x0_m <= -140.0 && grid.x1_m() >= 640.0);
    assert!(grid.z0_m <= -40.0 && grid.z1_m() >= 40.0);
}

#[test]
fn a_vehicle_driving_the_profile_rises_falls_and_pitches_with_it() {
    let mut world = World::new(&WorldConfig { ground: ground() }).unwrap();
    let params = VehicleParams::hmmwv_m998();
    let id = world
        .add_vehicle(&params, Pose::from_translation(Vector::ZERO), 8.0)
        .unwrap();
    let mut speed = SpeedController::new(&params, SpeedGains::default());
    let wheelbase = f64::from(params.wheelbase_m);
    let (mut worst_h, mut worst_pitch, mut highest, mut lowest) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for i in 0..(60 * PHYSICS_HZ) {
        let state = world.vehicle_state(id);
        let p = speed.update(8.0, 0.0, state.forward_speed_mps, PHYSICS_DT_S);
        world.set_controls(
            id,
            Controls {
                steer_rad: 0.0,
                throttle: p.throttle,
                brake: p.brake,
            },
        );
        world.step();
        if i < 2 * PHYSICS_HZ {
            continue;
        }
        let t = state.world_from_vehicle.translation;
        let (x, y) = (f64::from(t.x), f64::from(t.y));
        if x > 500.0 {
            break;
        }
        // The rear axle's origin rides on the ground under it; the chassis lies along the
        // chord from the rear axle's ground to the front axle's.
        let chord = ((road_height(x + wheelbase) - road_height(x)) / wheelbase).atan();
        worst_h = worst_h.max((y - road_height(x)).abs());
        worst_pitch = worst_pitch.max((f64::from(state.pitch_rad) - chord).abs());
        (highest, lowest) = (highest.max(y), lowest.min(y));
    }
    println!(
        "on the profile: height within {worst_h:.3} m, pitch within {:.2}° of the road's; \
         rode from {lowest:.2} m to {highest:.2} m",
        worst_pitch.to_degrees()
    );
    assert!(highest > 4.3 && lowest < -4.3, "{lowest} – {highest}");
    assert!(worst_h < 0.03, "height off by {worst_h} m");
    assert!(
        worst_pitch < 0.3f64.to_radians(),
        "pitch off by {worst_pitch} rad"
    );
}

/// The physics and the renderer build their grounds from one configuration: its profile's
/// grid is filled once and shared, with the very heights `grid` fills; another profile
/// gets its own.
#[test]
fn one_profile_grid_is_filled_once_and_shared() {
    let a = Ground::new(&ground()).unwrap();
    let first = a.shared_grid().unwrap();
    let again = Ground::new(&ground()).unwrap().shared_grid().unwrap();
    assert!(std::sync::Arc::ptr_eq(&first, &again));
    assert_eq!(*first, a.grid().unwrap());
    let mut other = ground();
    other.profile.as_mut().unwrap().margin_m = 20.0;
    let b = Ground::new(&other).unwrap();
    let theirs = b.shared_grid().unwrap();
    assert!(!std::sync::Arc::ptr_eq(&first, &theirs));
    assert_eq!(*theirs, b.grid().unwrap());
    // Flat ground has none; bumps alone are not shared.
    assert!(Ground::new(&GroundConfig::default())
        .unwrap()
        .shared_grid()
        .is_none());
}

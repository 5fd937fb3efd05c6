//! The standing clutter's guarantees, on the built scene (and one rendered frame):
//! - over a bump field, every static item (poles, houses, buildings, parked cars, tree
//!   trunks, hand-placed poles) stands on the lowest ground under its footprint, to within
//!   a centimetre, and nowhere floats above it; on flat ground it stands at y = 0 and the
//!   other kinds' placements are those of the flat scene;
//! - the same description builds the same mesh, vertex for vertex;
//! - a parked car seen from close by shows many edges inside its outline (glass, pillars,
//!   bumpers, lamps, wheels), not only its silhouette.
//!
//! Run: `cargo test -p sim --release --test clutter`.

use image::GrayImage;
use nalgebra::Point3;
use sim_render::{
    builtin_description, builtin_poses, builtin_target, Densities, Layer, Placement, RouteSegment,
    Scene, SceneDescription,
};
use sim_render::{Backend, CameraRig, FrameInput, RenderOptions, Renderer};
use std::collections::BTreeMap;

/// A straight road with the given clutter and nothing else.
fn street(seed: u64, densities: Densities) -> SceneDescription {
    let mut d = builtin_description(builtin_target(), seed);
    d.route.segments = vec![RouteSegment::Straight { length_m: 300.0 }];
    d.route.intersections_m.clear();
    d.densities = Densities {
        cracks_per_km: 0.0,
        patches_per_km: 0.0,
        potholes_per_km: 0.0,
        oncoming_vehicles_per_km: 0.0,
        ..densities
    };
    d.sensor.noise_sigma_grey = 0.0;
    d
}

fn busy_street(seed: u64) -> SceneDescription {
    let mut d = street(
        seed,
        Densities {
            trees_per_km: 40.0,
            poles_per_km: 30.0,
            houses_per_km: 30.0,
            buildings_per_km: 15.0,
            parked_vehicles_per_km: 30.0,
            ..Densities::default()
        },
    );
    for k in 0..4 {
        d.placements.push(Placement::Pole {
            x_m: -9.0 + 1.3 * k as f64,
            z_m: 40.0 + 31.0 * k as f64,
        });
    }
    d
}

fn bumps() -> vehicle::BumpsConfig {
    vehicle::BumpsConfig {
        amplitude_m: 0.12,
        wavelength_m: 7.0,
        half_extent_m: 450.0,
        cell_m: 0.5,
        seed: 4,
    }
}

/// The clutter's vertices, chunk by chunk.
fn clutter(scene: &Scene) -> Vec<Vec<[f64; 3]>> {
    let mesh = scene.whole_mesh();
    scene
        .chunks()
        .iter()
        .filter(|c| c.layer == Layer::Clutter)
        .map(|c| {
            let mut seen = std::collections::BTreeSet::new();
            mesh.indices[c.indices.start as usize..c.indices.end as usize]
                .iter()
                .filter(|&&i| seen.insert(i))
                .map(|&i| mesh.vertices[i as usize].position.map(f64::from))
                .collect()
        })
        .collect()
}

#[test]
fn clutter_stands_on_the_ground_under_its_footprint() {
    let flat_description = busy_street(5);
    let mut bumpy_description = flat_description.clone();
    bumpy_description.ground.bumps = Some(bumps());
    let flat = Scene::build(flat_description).unwrap();
    let bumpy = Scene::build(bumpy_description).unwrap();
    let terrain = bumpy.terrain().expect("bumps");
    let (flat, bumpy) = (clutter(&flat), clutter(&bumpy));
    assert_eq!(flat.len(), bumpy.len(), "the same chunks");
    let mut items = 0;
    for (f, b) in flat.iter().zip(&bumpy) {
        assert_eq!(f.len(), b.len(), "the same vertices");
        // On flat ground, everything stands at y = 0.
        let lowest = f.iter().map(|p| p[1]).fold(f64::MAX, f64::min);
        assert_eq!(lowest, 0.0);
        // Over bumps, each item moved rigidly in height, the same in plan: its feet (the
        // vertices at y = 0 on flat ground), grouped by how far they moved, are its
        // footprint.
        let mut feet: BTreeMap<i64, Vec<[f64; 2]>> = BTreeMap::new();
        for (p, q) in f.iter().zip(b) {
            assert_eq!([p[0], p[2]], [q[0], q[2]], "moved in plan");
            if p[1] == 0.0 {
                let dy = q[1] - p[1];
                assert!(
                    dy <= terrain.height_m(q[0], q[2]) + 0.01,
                    "floats {:.3} m over the ground at ({:.1}, {:.1})",
                    dy - terrain.height_m(q[0], q[2]),
                    q[0],
                    q[2]
                );
                feet.entry((dy * 1e4).round() as i64)
                    .or_default()
                    .push([q[0], q[2]]);
            }
        }
        for (dy, footprint) in feet {
            let base = dy as f64 * 1e-4;
            // The lowest ground under the footprint, sampled every 10 cm over its bounding
            // box; a footprint is at most a building's (15 m across or so).
            let lo = |k: usize| footprint.iter().map(|p| p[k]).fold(f64::MAX, f64::min);
            let hi = |k: usize| footprint.iter().map(|p| p[k]).fold(f64::MIN, f64::max);
            assert!(hi(0) - lo(0) < 40.0 && hi(1) - lo(1) < 40.0, "one item");
            let mut ground = f64::MAX;
            let mut x = lo(0);
            while x <= hi(0) + 1e-9 {
                let mut z = lo(1);
                while z <= hi(1) + 1e-9 {
                    ground = ground.min(terrain.height_m(x, z));
                    z += 0.1;
                }
                x += 0.1;
            }
            assert!(
                (base - ground).abs() < 0.01,
                "an item at ({:.1}, {:.1}) stands at {base:.3} m, the ground under it \
                 reaches down to {ground:.3} m",
                lo(0),
                lo(1)
            );
            items += 1;
        }
    }
    assert!(items > 40, "only {items} items");
}

#[test]
fn the_same_description_builds_the_same_clutter() {
    let a = Scene::build(busy_street(9)).unwrap();
    let b = Scene::build(busy_street(9)).unwrap();
    assert_eq!(a.whole_mesh(), b.whole_mesh());
    assert_eq!(a.chunks(), b.chunks());
    assert_eq!(a.objects(), b.objects());
    let c = Scene::build(busy_street(10)).unwrap();
    assert_ne!(a.whole_mesh(), c.whole_mesh());
}

/// Pixels of `image` inside `rect` (x0, y0, x1, y1, inclusive) where the grey level steps
/// by at least `step` to the next pixel right or below.
fn strong_edges(image: &GrayImage, rect: [u32; 4], step: i32) -> usize {
    let [x0, y0, x1, y1] = rect;
    let mut n = 0;
    for y in y0..y1 {
        for x in x0..x1 {
            let g = |x: u32, y: u32| i32::from(image.get_pixel(x, y)[0]);
            let here = g(x, y);
            if (g(x + 1, y) - here).abs() >= step || (g(x, y + 1) - here).abs() >= step {
                n += 1;
            }
        }
    }
    n
}

#[test]
fn a_parked_car_seen_close_shows_its_parts_edges() {
    let d = street(
        2,
        Densities {
            trees_per_km: 0.0,
            poles_per_km: 0.0,
            houses_per_km: 0.0,
            buildings_per_km: 0.0,
            parked_vehicles_per_km: 10.0,
            ..Densities::default()
        },
    );
    let scene = std::sync::Arc::new(Scene::build(d.clone()).unwrap());
    // The parked cars: the only clutter; grouped along the road.
    let mut points: Vec<[f64; 3]> = clutter(&scene).concat();
    points.sort_by(|a, b| a[2].total_cmp(&b[2]).then(a[0].total_cmp(&b[0])));
    let rig = CameraRig::default();
    let mut r = Renderer::new(
        scene.clone(),
        rig.clone(),
        &RenderOptions {
            backend: Backend::choose(None).expect("backend"),
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let mut best: Option<(f64, [u32; 4], f64)> = None;
    for step in 0..120 {
        let time_s = 0.5 * step as f64;
        let (chase, _) = builtin_poses(&d, scene.route(), &rig.mount, time_s);
        let camera = rig.world_from_camera(&chase);
        // The car 8 to 40 m ahead of the camera (the nearest one wholly in view is kept).
        let ahead: Vec<&[f64; 3]> = points
            .iter()
            .filter(|p| {
                let c = camera.inverse() * Point3::new(p[0], p[1], p[2]);
                (8.0..40.0).contains(&c.z)
            })
            .collect();
        if ahead.len() < 50 {
            continue;
        }
        let projected: Option<Vec<[f64; 2]>> = ahead
            .iter()
            .map(|p| rig.project_world(&chase, **p))
            .collect();
        let Some(projected) = projected else { continue };
        let lo = |k: usize| projected.iter().map(|p| p[k]).fold(f64::MAX, f64::min);
        let hi = |k: usize| projected.iter().map(|p| p[k]).fold(f64::MIN, f64::max);
        if lo(0) < 2.0 || hi(0) > 253.0 || lo(1) < 2.0 || hi(1) > 239.0 {
            continue;
        }
        let area = (hi(0) - lo(0)) * (hi(1) - lo(1));
        if best.is_none_or(|b| area > b.0) {
            let rect = [lo(0), lo(1), hi(0), hi(1)].map(|v| v.round() as u32);
            best = Some((area, rect, time_s));
        }
    }
    let (_, rect, time_s) = best.expect("a parked car in view, close");
    let (chase, lead) = builtin_poses(&d, scene.route(), &rig.mount, time_s);
    // The lead far ahead, out of the way.
    let lead = nalgebra::Translation3::new(0.0, 0.0, 150.0) * lead;
    let frame = r
        .render(&FrameInput::fixed_camera(0, time_s, chase, lead))
        .expect("frame");
    // Inside the outline, two pixels in from it: the silhouette's edges left out.
    let inner = [rect[0] + 2, rect[1] + 2, rect[2] - 2, rect[3] - 2];
    let edges = strong_edges(&frame.image, inner, 24);
    let [w, h] = [inner[2] - inner[0], inner[3] - inner[1]];
    eprintln!("car at t = {time_s} s: {w} × {h} px, {edges} strong edge pixels inside its outline");
    // A plain box shows at most the seams between two or three faces inside its outline:
    // about a width and a height of edge pixels. The car's parts give several times that.
    assert!(w >= 20 && h >= 10, "{w} × {h} px");
    assert!(
        edges as u32 >= 3 * (w + h),
        "{edges} edge pixels in {w} × {h} px"
    );
}

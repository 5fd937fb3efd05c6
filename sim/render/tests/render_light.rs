//! The renderer's ground textures and shadows: an untextured frame is the untextured
//! renderer's bit for bit; textures add detail to the road and keep its grey; a tree's
//! shadow on the road is dappled; cached static shadows are those drawn every frame, and a
//! frame is the same whatever the cache held before it.
//!
//! Run: `cargo test -p sim-render --release --test render_light`.

use image::GrayImage;
use sim_render::{
    builtin_description, builtin_target, FrameInput, Placement, RenderOptions, Renderer,
    SceneDescription,
};

mod common;
use common::{bare, builtin_frame, options, reference, renderer};

/// Compares `image` with the reference `tests/golden/{name}.png` bit for bit (a missing
/// reference is written fresh).
fn golden_exact(name: &str, image: &GrayImage) {
    let (dir, Some(reference)) = reference(name, image) else {
        return;
    };
    let differ = image
        .pixels()
        .zip(reference.pixels())
        .filter(|(a, b)| a != b)
        .count();
    if reference.dimensions() != image.dimensions() || differ > 0 {
        image.save(dir.join(format!("{name}-actual.png"))).unwrap();
        panic!("{name}: {differ} pixels differ from the reference; see {name}-actual.png");
    }
}

/// Untextured frames (the scene without trees, whose canopies are perforated) without the
/// static shadow cache are the frames the renderer drew before ground textures existed
/// (and, with soft shadows, before only the draws that can lie within the board's fine map
/// took the soft-shadow pipelines), bit for bit: the references were rendered by the
/// renderer without textures, then again when the poles gained their insulators (the only
/// pixels that changed: 366, all on the poles and their wires).
#[test]
fn untextured_frames_are_the_untextured_renderers_bit_for_bit() {
    for soft in [false, true] {
        let mut d = builtin_description(builtin_target(), 1);
        d.densities.trees_per_km = 0.0;
        d.sensor.noise_sigma_grey = 0.0;
        d.sun.soft_shadows = soft;
        d.textures.enabled = false;
        // And without the static shadow cache, which came later.
        let uncached = RenderOptions {
            cached_shadows: false,
            ..options()
        };
        let mut renderer = renderer(d, &uncached);
        let name = if soft {
            "untextured-soft-t12"
        } else {
            "untextured-t12"
        };
        golden_exact(name, &builtin_frame(&mut renderer, 12.0).image);
        // With soft shadows, only what can lie within the board's fine map pays for it.
        let stats = renderer.stats();
        if soft {
            assert!(
                stats.soft_triangles > 0 && stats.soft_triangles < stats.main_triangles / 2,
                "{stats:?}"
            );
        } else {
            assert_eq!(stats.soft_triangles, 0);
        }
    }
}

/// A frame of a `bare` scene from the camera in the right lane at station `chase_s`, the
/// lead far ahead (200 m) out of the way.
fn bare_frame(renderer: &mut Renderer, chase_s: f64) -> GrayImage {
    let route = renderer.scene().route();
    let lane = renderer.scene().description().route.lane_width_m;
    let world_from_chase = route.pose_at(chase_s, 0.5 * lane);
    let world_from_lead = route.pose_at(chase_s + 200.0, 0.5 * lane);
    renderer
        .render(&FrameInput::fixed_camera(
            0,
            0.0,
            world_from_chase,
            world_from_lead,
        ))
        .expect("frame")
        .image
}

/// Mean grey and gradient energy (mean squared difference of horizontal and of vertical
/// neighbours) of `image` over rows `rows` and columns `columns`.
fn grey_and_gradient_energy(
    image: &GrayImage,
    rows: std::ops::Range<u32>,
    columns: std::ops::Range<u32>,
) -> (f64, f64) {
    let at = |x: u32, y: u32| f64::from(image.get_pixel(x, y)[0]);
    let (mut sum, mut energy, mut n) = (0.0, 0.0, 0.0);
    for y in rows {
        for x in columns.clone() {
            sum += at(x, y);
            energy += (at(x + 1, y) - at(x, y)).powi(2) + (at(x, y + 1) - at(x, y)).powi(2);
            n += 1.0;
        }
    }
    (sum / n, energy / n)
}

/// With textures on, the road straight ahead (rows 140–210, 6–20 m away, and the 36 middle
/// columns, clear of paint) has at least twice the gradient energy it has with them off,
/// and its mean grey stays within 3 grey levels; the same seed gives the same frame, and
/// another seed another texture.
#[test]
fn textures_add_gradient_energy_to_the_road_and_keep_its_grey() {
    let frame = |seed: u64, enabled: bool| {
        let mut d = bare(seed);
        d.textures.enabled = enabled;
        bare_frame(&mut renderer(d, &options()), 60.0)
    };
    let (off, on) = (frame(3, false), frame(3, true));
    let region = |image: &GrayImage| grey_and_gradient_energy(image, 140..210, 110..146);
    let ((grey_off, energy_off), (grey_on, energy_on)) = (region(&off), region(&on));
    assert!(
        energy_on > 2.0 * energy_off && energy_on > 1.0,
        "gradient energy: {energy_on:.2} with textures, {energy_off:.2} without"
    );
    assert!(
        (grey_on - grey_off).abs() < 3.0,
        "mean grey: {grey_on:.1} with textures, {grey_off:.1} without"
    );
    assert_eq!(on, frame(3, true), "same seed, same frame");
    assert_ne!(on, frame(4, true), "another seed, another texture");
}

/// A tree beside the road, the sun low on the road's left: the canopy's shadow falls
/// across the lane ahead, and it is dappled: inside it, sunlit pixels (the sunlight through
/// the canopy's holes) lie between shadowed ones, along rows and along columns. The same
/// seed gives the same frame.
#[test]
fn a_tree_shadow_on_the_road_is_dappled() {
    let scene_with = |tree: bool| {
        let mut d = bare(5);
        let route = sim_render::Route::new(d.route.clone());
        let [_, _, heading] = route.at(80.0);
        // The sun on the road's left, 40° up: shadows fall to the right, across the road.
        d.sun.azimuth_deg = (-heading.cos()).atan2(-heading.sin()).to_degrees();
        d.sun.elevation_deg = 40.0;
        if tree {
            let [x_m, z_m] = route.point(80.0, -6.5);
            d.placements.push(Placement::Tree { x_m, z_m });
        }
        d
    };
    let with = bare_frame(&mut renderer(scene_with(true), &options()), 71.0);
    let without = bare_frame(&mut renderer(scene_with(false), &options()), 71.0);
    assert_eq!(
        with,
        bare_frame(&mut renderer(scene_with(true), &options()), 71.0),
        "same seed, same frame"
    );
    // Per pixel of the road below the horizon: shadowed (below 60 % of its light without
    // the tree), sunlit (above 80 %), or in between.
    let (w, h) = with.dimensions();
    let state = |x: u32, y: u32| {
        let (a, b) = (
            f64::from(with.get_pixel(x, y)[0]),
            f64::from(without.get_pixel(x, y)[0]),
        );
        let ratio = a / b.max(1.0);
        if ratio < 0.6 {
            -1
        } else if ratio > 0.8 {
            1
        } else {
            0
        }
    };
    let rows = 125..h - 30;
    let shadowed = rows
        .clone()
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| state(x, y) == -1)
        .count();
    assert!(shadowed > 200, "only {shadowed} shadowed pixels");
    // A hole: a sunlit pixel with shadow within 5 px on both sides in its row, and within
    // 5 px above or below it.
    let shadow_near = |x: u32, y: u32, dx: i64, dy: i64| {
        (1..=5i64).any(|k| {
            let (px, py) = (x as i64 + k * dx, y as i64 + k * dy);
            px >= 0
                && py >= 0
                && px < w as i64
                && py < h as i64
                && state(px as u32, py as u32) == -1
        })
    };
    let holes = rows
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            state(x, y) == 1
                && shadow_near(x, y, 1, 0)
                && shadow_near(x, y, -1, 0)
                && (shadow_near(x, y, 0, 1) || shadow_near(x, y, 0, -1))
        })
        .count();
    eprintln!("{holes} sunlit holes among {shadowed} shadowed pixels");
    assert!(
        holes >= 10,
        "{holes} sunlit holes inside the canopy's shadow ({shadowed} shadowed pixels)"
    );
}

/// The built-in scene without sensor noise, for comparing renderers' frames.
fn quiet_builtin() -> SceneDescription {
    let mut d = builtin_description(builtin_target(), 1);
    d.sensor.noise_sigma_grey = 0.0;
    d
}

/// Mean absolute difference of two frames, and the share of pixels more than 8 grey
/// levels apart.
fn difference(a: &GrayImage, b: &GrayImage) -> (f64, f64) {
    let d: Vec<i32> = a
        .pixels()
        .zip(b.pixels())
        .map(|(p, q)| (i32::from(p[0]) - i32::from(q[0])).abs())
        .collect();
    let n = d.len() as f64;
    (
        d.iter().sum::<i32>() as f64 / n,
        d.iter().filter(|&&v| v > 8).count() as f64 / n,
    )
}

/// Static shadows from the cache are the ones drawn into every frame's map. Where frames
/// differ, it is along shadow edges (the tiles' texels are 10 cm, the frame's map's
/// 11–13 cm). Without the tiles' shadows these frames differ on 0.7–1 % of their pixels
/// (by a mean of 0.2 grey levels); with them, on 0.2 %.
#[test]
fn cached_static_shadows_are_the_ones_drawn_every_frame() {
    let uncached = RenderOptions {
        cached_shadows: false,
        ..options()
    };
    let mut every_frame = renderer(quiet_builtin(), &uncached);
    let mut cached = renderer(quiet_builtin(), &options());
    for time_s in [5.0, 60.0] {
        let a = builtin_frame(&mut every_frame, time_s).image;
        let drawn = every_frame.stats();
        let b = builtin_frame(&mut cached, time_s).image;
        let stats = cached.stats();
        // The frame's own map holds the vehicles alone; the tiles, the rest.
        assert!(stats.shadow_tiles_drawn > 0, "{stats:?}");
        assert!(
            stats.shadow_triangles * 4 < drawn.shadow_triangles,
            "{stats:?} against {drawn:?}"
        );
        let (mean, beyond) = difference(&a, &b);
        assert!(
            mean < 0.1 && beyond < 0.005,
            "t = {time_s} s: mean difference {mean:.3}, {:.2} % beyond 8 levels",
            100.0 * beyond
        );
    }
}

/// A tile's texels depend on which tile it is alone, so a frame is the same bit for bit
/// whatever its renderer drew before (here: the first 30 s of the route, which fill the
/// cache and evict from it), partly or whole.
#[test]
fn a_frame_is_the_same_whatever_the_shadow_cache_held() {
    let time_s = 40.0;
    let mut fresh = renderer(quiet_builtin(), &options());
    let expected = builtin_frame(&mut fresh, time_s).image;
    let mut used = renderer(quiet_builtin(), &options());
    let mut drawn = 0;
    for k in 0..60 {
        builtin_frame(&mut used, 0.5 * f64::from(k));
        drawn += used.stats().shadow_tiles_drawn;
    }
    // The cache holds 16 tiles.
    assert!(drawn > 32, "{drawn} tiles drawn: the cache never evicted");
    let again = builtin_frame(&mut used, time_s).image;
    assert!(
        again == expected,
        "the frame depends on what the cache held"
    );
    // Drawn again, nothing new is drawn.
    builtin_frame(&mut used, time_s);
    assert_eq!(used.stats().shadow_tiles_drawn, 0);
}

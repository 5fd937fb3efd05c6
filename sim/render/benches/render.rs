//! Frames rendered and read back per second at 256×242, with shadows and the default
//! clutter, on the backend `WGPU_BACKEND` names (GL/llvmpipe by default): the default
//! options (512² shadow map) and, for comparison, a 1024² shadow map.
//!
//! Run: `cargo bench -p sim-render --bench render`. Criterion's "thrpt" is frames per second.
//! On a 2-core machine other processes halve the figure: check `uptime` first.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use sim_render::{builtin_description, builtin_poses, builtin_target, Scene};
use sim_render::{Backend, CameraRig, FrameInput, RenderOptions, Renderer};
use tracker::PixelRect;

fn render(c: &mut Criterion) {
    let scene = std::sync::Arc::new(
        Scene::build(builtin_description(builtin_target(), 1)).expect("built-in scene"),
    );
    let rig = CameraRig::default();
    let backend = Backend::choose(None).expect("backend");
    let mut group = c.benchmark_group("render");
    group.throughput(Throughput::Elements(1));
    for shadow_map_size in [512, 1024] {
        let options = RenderOptions {
            backend,
            shadow_map_size,
            ..RenderOptions::default()
        };
        let mut renderer = Renderer::new(scene.clone(), rig.clone(), &options).expect("renderer");
        eprintln!("adapter: {}", renderer.adapter_name());
        // Drive along the route at 15 Hz so culling, shadow fitting and noise change per frame.
        let mut frame_index = 0u64;
        group.bench_function(format!("frame_256x242_shadow{shadow_map_size}"), |b| {
            b.iter(|| {
                let time_s = (frame_index % 600) as f64 / 15.0;
                let (world_from_chase, world_from_lead) =
                    builtin_poses(scene.description(), scene.route(), &rig.mount, time_s);
                frame_index += 1;
                renderer
                    .render(&FrameInput::fixed_camera(
                        frame_index,
                        time_s,
                        world_from_chase,
                        world_from_lead,
                    ))
                    .expect("frame")
            })
        });
    }
    // Only the part the tracker reads, as `run` renders it: a 110 × 90 px window around
    // the target (what `nist-grounds`' tracker reads at 10 m).
    let options = RenderOptions {
        backend,
        ..RenderOptions::default()
    };
    let mut renderer = Renderer::new(scene.clone(), rig.clone(), &options).expect("renderer");
    let mut frame_index = 0u64;
    group.bench_function("frame_part_110x90", |b| {
        b.iter(|| {
            let time_s = (frame_index % 600) as f64 / 15.0;
            let (world_from_chase, world_from_lead) =
                builtin_poses(scene.description(), scene.route(), &rig.mount, time_s);
            frame_index += 1;
            let truth = renderer.ground_truth(&world_from_chase, &world_from_lead, 0.0);
            let (x, y) = (truth.c_x.round() as usize, truth.c_y.round() as usize);
            let h: usize = std::env::var("HALF")
                .map(|v| v.parse().unwrap())
                .unwrap_or(55);
            let part = PixelRect {
                x0: x.saturating_sub(h),
                y0: y.saturating_sub(h * 45 / 55),
                x1: (x + h).min(rig.width as usize),
                y1: (y + h * 45 / 55).min(rig.height as usize),
            };
            renderer
                .render_part(
                    &FrameInput::fixed_camera(
                        frame_index,
                        time_s,
                        world_from_chase,
                        world_from_lead,
                    ),
                    Some(part),
                )
                .expect("frame")
        })
    });
    group.finish();
    let mut renderer = Renderer::new(
        scene.clone(),
        rig.clone(),
        &RenderOptions {
            backend,
            ..RenderOptions::default()
        },
    )
    .expect("renderer");
    // What the bench's whole frames draw: the mean over its 600 poses.
    let mut sums = [0u64; 4];
    for frame_index in 0..600u64 {
        let time_s = frame_index as f64 / 15.0;
        let (world_from_chase, world_from_lead) =
            builtin_poses(scene.description(), scene.route(), &rig.mount, time_s);
        renderer
            .render(&FrameInput::fixed_camera(
                frame_index,
                time_s,
                world_from_chase,
                world_from_lead,
            ))
            .expect("frame");
        let stats = renderer.stats();
        for (sum, n) in sums.iter_mut().zip([
            stats.main_triangles,
            stats.shadow_triangles,
            stats.draw_calls,
            stats.shadow_tiles_drawn,
        ]) {
            *sum += u64::from(n);
        }
    }
    let [main, shadow, calls, tiles] = sums.map(|s| s as f64 / 600.0);
    eprintln!(
        "scene: {} triangles; a whole frame draws, on average over 600: {main:.0} triangles \
         from the camera, {shadow:.0} from the sun, {calls:.1} draw calls, {tiles:.2} shadow \
         tiles",
        scene.objects_indices().end / 3,
    );
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(6));
    targets = render
}
criterion_main!(benches);

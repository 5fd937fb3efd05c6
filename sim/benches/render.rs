//! Frames rendered and read back per second at 256×242, with shadows and the default
//! clutter, on the backend `WGPU_BACKEND` names (GL/llvmpipe by default).
//!
//! Run: `cargo bench -p sim --bench render`. Criterion's "thrpt" is frames per second.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use sim::camera::{Backend, CameraRig, FrameInput, RenderOptions, Renderer};
use sim::scene::{builtin_description, builtin_poses, builtin_target, Scene};

fn render(c: &mut Criterion) {
    let scene = Scene::build(builtin_description(builtin_target(), 1)).expect("built-in scene");
    let rig = CameraRig::default();
    let backend = Backend::choose(None).expect("backend");
    if let Ok(n) = std::env::var("CF_QUICK") {
        let n: u64 = n.parse().unwrap();
        let size: u32 = std::env::var("CF_SIZE")
            .map(|s| s.parse().unwrap())
            .unwrap_or(1024);
        let options = RenderOptions {
            backend,
            shadow_map_size: size,
            ..RenderOptions::default()
        };
        let mut renderer = Renderer::new(&scene, rig.clone(), &options).expect("renderer");
        let cpu = || {
            let s = std::fs::read_to_string("/proc/self/stat").unwrap();
            let f: Vec<&str> = s.rsplit(')').next().unwrap().split_whitespace().collect();
            (f[11].parse::<f64>().unwrap() + f[12].parse::<f64>().unwrap()) * 10.0
        };
        let mut go = |count: u64| {
            let (t0, c0) = (std::time::Instant::now(), cpu());
            for frame_index in 0..count {
                let time_s = (frame_index % 600) as f64 / 15.0;
                let (world_from_chase, world_from_lead) =
                    builtin_poses(scene.description(), scene.route(), &rig.mount, time_s);
                renderer
                    .render(&FrameInput {
                        frame_index,
                        time_s,
                        world_from_chase,
                        world_from_lead,
                    })
                    .unwrap();
            }
            (t0.elapsed().as_secs_f64(), cpu() - c0)
        };
        go(60);
        let (wall, cpu_ms) = go(n);
        eprintln!(
            "QUICK {size}: {:.1} frames/s wall, {:.2} cpu-ms/frame",
            n as f64 / wall,
            cpu_ms / n as f64
        );
        return;
    }
    let mut group = c.benchmark_group("render");
    group.throughput(Throughput::Elements(1));
    for shadow_map_size in [1024, 512] {
        let options = RenderOptions {
            backend,
            shadow_map_size,
            ..RenderOptions::default()
        };
        let mut renderer = Renderer::new(&scene, rig.clone(), &options).expect("renderer");
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
                    .render(&FrameInput {
                        frame_index,
                        time_s,
                        world_from_chase,
                        world_from_lead,
                    })
                    .expect("frame")
            })
        });
    }
    group.finish();
    let mut renderer = Renderer::new(
        &scene,
        rig.clone(),
        &RenderOptions {
            backend,
            ..RenderOptions::default()
        },
    )
    .expect("renderer");
    let (world_from_chase, world_from_lead) =
        builtin_poses(scene.description(), scene.route(), &rig.mount, 0.0);
    renderer
        .render(&FrameInput {
            frame_index: 0,
            time_s: 0.0,
            world_from_chase,
            world_from_lead,
        })
        .expect("frame");
    eprintln!(
        "scene: {} triangles; frame 0 drew {:?}",
        scene.mesh().indices.len() / 3,
        renderer.stats()
    );
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(6));
    targets = render
}
criterion_main!(benches);

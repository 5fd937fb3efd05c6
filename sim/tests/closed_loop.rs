//! The closed loop end to end: a shortened `nist-grounds` runs with the real renderer,
//! tracker, delay line, controllers and physics, and meets its following-distance and
//! tracking criteria; the same seed gives identical records twice; overlapping the physics
//! with rendering, or rendering two frames at once (the second in a worker process), gives
//! the same records as one thing at a time.
//! Run with `cargo test -p sim --release --test closed_loop`.

use sim_core::{ClosedLoop, FrameRecord, LoopOptions, Plan};
use sim_render::Backend;

fn run(overrides: &[&str]) -> Vec<FrameRecord> {
    run_with(overrides, true)
}

fn run_with(overrides: &[&str], pipelined: bool) -> Vec<FrameRecord> {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let plan = Plan::builtin(&overrides).unwrap();
    let mut l = ClosedLoop::new(plan, Backend::choose(None).unwrap(), false).unwrap();
    assert_eq!(l.set_pipelined(pipelined), pipelined);
    records_of(&mut l)
}

/// Runs `l` to its end: every frame's record.
fn records_of(l: &mut ClosedLoop) -> Vec<FrameRecord> {
    let mut records = Vec::new();
    while let Some(out) = l.step().unwrap() {
        records.push(out.record);
    }
    records
}

#[test]
fn shortened_nist_grounds_follows_and_tracks() {
    let records = run(&["duration_s=20"]);
    assert_eq!(records.len(), 300);
    let lost = records.iter().filter(|r| r.lost_truth).count();
    let gap_min = records.iter().map(|r| r.gap_m).fold(f64::MAX, f64::min);
    let gap_max = records.iter().map(|r| r.gap_m).fold(f64::MIN, f64::max);
    let dev = records
        .iter()
        .map(|r| r.lateral_deviation_m)
        .fold(0.0, f64::max);
    let range_err = records
        .iter()
        .map(|r| (r.est_range_m - r.true_range_m).abs())
        .fold(0.0, f64::max);
    let last = records.last().unwrap();
    eprintln!(
        "lost {lost} frames; gap {gap_min:.2}..{gap_max:.2} m; max lateral deviation {dev:.2} m; max range error {range_err:.2} m; distance {:.1} m",
        last.chase_distance_m
    );
    for r in records.iter().step_by(15) {
        eprintln!(
            "t={:5.1} gap={:5.2} true=({:6.1},{:6.1},{:.3}) est=({:6.1},{:6.1},{:.3}) {:?} v={:.1}/{:.1} dev={:.2} {}",
            r.t_s, r.gap_m, r.true_cx, r.true_cy, r.true_scale, r.est_cx, r.est_cy, r.est_scale, r.status, r.chase_speed_mps, r.lead_speed_mps, r.lateral_deviation_m, r.chase_mode
        );
    }
    assert_eq!(lost, 0, "tracking lost (ground truth) in {lost} frames");
    assert!(
        gap_min >= 5.0 && gap_max <= 15.0,
        "gap {gap_min:.2}..{gap_max:.2}"
    );
    assert!(dev < 1.0, "lateral deviation {dev:.2} m");
    assert!(!records.iter().any(|r| r.collision));
}

#[test]
fn the_same_scenario_and_seed_give_identical_records() {
    let a = run(&["duration_s=4", "environment.sensor.noise_sigma_grey=4"]);
    let b = run(&["duration_s=4", "environment.sensor.noise_sigma_grey=4"]);
    assert_eq!(a.len(), 60);
    assert_eq!(a, b);
    // And a different seed gives a different run (the check can fail).
    let c = run(&[
        "duration_s=4",
        "environment.sensor.noise_sigma_grey=4",
        "seed=99",
    ]);
    assert_ne!(a, c);
}

#[test]
fn overlapping_physics_with_rendering_changes_nothing() {
    // Jitter and drops exercise the delay line's stream; 40 ms of jitter still leaves at
    // least one frame of latency, so the loop can overlap.
    let set = [
        "duration_s=6",
        "loop.jitter_ms=40",
        "loop.drop_probability=0.1",
    ];
    let overlapped = run_with(&set, true);
    let sequential = run_with(&set, false);
    assert_eq!(overlapped.len(), 90);
    assert_eq!(overlapped, sequential);
}

#[test]
fn a_latency_under_one_frame_keeps_the_loop_sequential() {
    let overrides = ["duration_s=1".to_string(), "loop.latency_ms=50".to_string()];
    let plan = Plan::builtin(&overrides).unwrap();
    let mut l = ClosedLoop::new(plan, Backend::choose(None).unwrap(), false).unwrap();
    assert!(!l.pipelined());
    assert!(!l.set_pipelined(true));
    while l.step().unwrap().is_some() {}
    let timing = l.timing();
    assert_eq!(timing.frames, 15);
    assert!(!timing.pipelined);
    assert!(timing.render_s > 0.0 && timing.physics_s > 0.0 && timing.track_s > 0.0);
}

fn builtin_loop(overrides: &[&str]) -> ClosedLoop {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let plan = Plan::builtin(&overrides).unwrap();
    ClosedLoop::new(plan, Backend::choose(None).unwrap(), false).unwrap()
}

/// `carfollow render-worker`: it reads no scenario, the loop sends it the scene.
fn render_worker() -> std::process::Command {
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_carfollow"));
    c.arg("render-worker");
    c
}

#[test]
fn two_frames_in_flight_change_nothing() {
    let set = ["duration_s=5", "environment.sensor.noise_sigma_grey=4"];
    let mut l = builtin_loop(&set);
    assert!(l.add_render_worker(render_worker()).unwrap());
    assert_eq!(l.frames_in_flight(), 2);
    let mut two = Vec::new();
    while let Some(out) = l.step().unwrap() {
        two.push(out.record);
    }
    assert_eq!(two.len(), 75);
    assert_eq!(two, run_with(&set, false));
}

/// Every frame's record and whole image, on one renderer or with the second renderer on a
/// thread of this process (its own llvmpipe, on Mesa's software EGL device).
fn frames_with(set: &[&str], second_on_thread: bool) -> Vec<(FrameRecord, Vec<u8>)> {
    let overrides: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    let plan = Plan::builtin(&overrides).unwrap();
    let l = ClosedLoop::start(
        plan,
        LoopOptions {
            renderers: if second_on_thread { 2 } else { 1 },
            whole_frames: true,
            // No process to fall back on: the second renderer is the thread or nothing.
            ..LoopOptions::new(Backend::Gl)
        },
    );
    let mut l = l.unwrap();
    assert!(l.notes().is_empty(), "{:?}", l.notes());
    assert_eq!(l.frames_in_flight(), if second_on_thread { 2 } else { 1 });
    let mut frames = Vec::new();
    while let Some(out) = l.step().unwrap() {
        frames.push((out.record, out.image.into_raw()));
    }
    frames
}

#[test]
fn a_second_renderer_on_a_thread_draws_the_same_frames() {
    let set = ["duration_s=3", "environment.sensor.noise_sigma_grey=4"];
    let one = frames_with(&set, false);
    let two = frames_with(&set, true);
    assert_eq!(one.len(), 45);
    assert_eq!(two.len(), one.len());
    for (k, (a, b)) in one.iter().zip(&two).enumerate() {
        assert_eq!(a.0, b.0, "frame {k}'s record");
        assert!(a.1 == b.1, "frame {k}'s pixels differ");
    }
}

#[test]
fn the_builder_says_why_it_renders_one_frame_at_a_time() {
    // Two renderers asked for, but a latency under one frame: the loop cannot run ahead,
    // so it takes no second renderer and needs to say nothing.
    let set = ["duration_s=1".to_string(), "loop.latency_ms=50".to_string()];
    let options = || LoopOptions {
        renderers: 2,
        ..LoopOptions::new(Backend::choose(None).unwrap())
    };
    let l = ClosedLoop::start(Plan::builtin(&set).unwrap(), options()).unwrap();
    assert_eq!(l.frames_in_flight(), 1);
    assert!(l.notes().is_empty(), "{:?}", l.notes());
    // A worker process that is not a renderer: refused, said in a note, one renderer.
    let set = ["duration_s=1".to_string()];
    let mut l = ClosedLoop::start(
        Plan::builtin(&set).unwrap(),
        LoopOptions {
            backend: Backend::Gl,
            renderers: 2,
            worker_process: Some(std::process::Command::new("true")),
            ..options()
        },
    )
    .unwrap();
    if l.frames_in_flight() == 1 {
        assert_eq!(l.notes().len(), 1, "{:?}", l.notes());
        assert!(l.notes()[0].ends_with("rendering one frame at a time"));
    }
    assert_eq!(records_of(&mut l), run(&["duration_s=1"]));
}

/// A worker that says it built another scene than the one it was sent (it answers with a
/// fingerprint of its own and renders nothing).
fn a_worker_of_another_scene() -> std::process::Command {
    let mut c = std::process::Command::new("sh");
    c.args(["-c", "printf ABCDEFGH; exec cat >/dev/null"]);
    c
}

#[test]
fn a_render_worker_with_another_scene_is_refused() {
    let mut l = builtin_loop(&["duration_s=1"]);
    let err = l
        .add_render_worker(a_worker_of_another_scene())
        .unwrap_err()
        .to_string();
    assert!(err.contains("another scene"), "{err}");
    assert_eq!(l.frames_in_flight(), 1);
    // The first frame had started rendering before the worker was refused: the loop takes
    // its renderer back and runs on one, with one renderer's records.
    assert_eq!(records_of(&mut l), run(&["duration_s=1"]));
    // A loop that cannot overlap does not start one.
    let mut l = builtin_loop(&["duration_s=1", "loop.latency_ms=50"]);
    assert!(!l.add_render_worker(render_worker()).unwrap());
}

#[test]
fn a_loop_made_sequential_after_its_worker_was_added_runs_on_one_renderer() {
    let set = ["duration_s=1"];
    let mut l = builtin_loop(&set);
    assert!(l.add_render_worker(render_worker()).unwrap());
    // The first frame is on the render thread already: it comes back, and is rendered
    // again on the sequential path.
    assert!(!l.set_pipelined(false));
    assert_eq!(l.frames_in_flight(), 1);
    assert_eq!(records_of(&mut l), run_with(&set, false));
}

/// The records and the metered mean grey of each frame, with whole frames or not, and with
/// a render worker or not.
fn run_metered(set: &[&str], whole: bool, worker: bool) -> (Vec<FrameRecord>, Vec<f64>) {
    let mut l = builtin_loop(set);
    l.set_whole_frames(whole);
    if worker {
        assert!(l.add_render_worker(render_worker()).unwrap());
    }
    let window = sim_render::AutoGain::metering_window(256, 242);
    let (mut records, mut means) = (Vec::new(), Vec::new());
    while let Some(out) = l.step().unwrap() {
        let mut sum = 0u64;
        for y in window.y0..window.y1 {
            for x in window.x0..window.x1 {
                sum += u64::from(out.image.get_pixel(x as u32, y as u32)[0]);
            }
        }
        means.push(sum as f64 / (window.width() * window.height()) as f64);
        records.push(out.record);
    }
    (records, means)
}

#[test]
fn auto_gain_brightens_a_dark_scene_alike_with_and_without_whole_frames() {
    // A sensor at a fifth of its nominal gain sees the scene dark.
    let set = [
        "duration_s=4",
        "environment.sensor.gain=0.2",
        "environment.sensor.auto_gain={target_grey=110,time_constant_s=0.4}",
    ];
    let (whole, means) = run_metered(&set, true, false);
    assert_eq!(whole.len(), 60);
    eprintln!("metered means: {means:.1?}");
    assert!(means[0] < 40.0, "{}", means[0]);
    assert!(means[59] > 2.0 * means[0], "{} → {}", means[0], means[59]);
    assert!((means[59] - 110.0).abs() < 20.0, "{}", means[59]);
    // The first two frames are exposed before any metering; then it rises.
    assert_eq!(means[0], means[0].min(means[1]).min(means[5]));
    let (part, part_means) = run_metered(&set, false, false);
    assert_eq!(whole, part);
    assert_eq!(means, part_means);
    let (two, two_means) = run_metered(&set, false, true);
    assert_eq!(whole, two);
    assert_eq!(means, two_means);
    // Without the control the scene stays dark.
    let (_, dark) = run_metered(&set[..2], true, false);
    assert!(dark[59] < 40.0, "{}", dark[59]);
}

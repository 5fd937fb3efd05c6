//! `carfollow render`: one camera frame, of a scenario's closed-loop run or of the built-in scene, to a PNG.

use super::exit::incomplete;
use super::paths::png_path;
use anyhow::{bail, Context};
use clap::Args;
use sim_render::{builtin_description, builtin_poses, builtin_target, Scene};
use sim_render::{Backend, CameraRig, FrameInput, RenderOptions, Renderer};
use std::path::PathBuf;

/// Arguments of `carfollow render`.
#[derive(Args, Debug)]
#[command(
    after_help = super::exit::TOOL_HELP,
    about = "Render one camera frame (256×242 grey PNG) at time T",
    long_about = "Render one frame of what the chase vehicle's camera sees at time T, with sun \
                  shadows, clutter and sensor noise, and print the target's ground truth.\n\n\
                  With SCENARIO, the scenario runs through the closed loop up to T and that \
                  frame is written. Without it, the built-in scene is rendered (a rural road with bends and intersections, \
                  the NIST ten-segment target on a box truck 10 m ahead, both vehicles in the \
                  right lane at 11 m/s)."
)]
pub struct RenderArgs {
    /// Scenario file: the frame at --time of its closed-loop run (the loop runs up to it).
    /// Without one, the built-in scene.
    pub scenario: Option<PathBuf>,
    /// Simulation time of the frame, seconds (the nearest camera frame's, at 15 Hz).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub time: f64,
    /// Where to write the PNG.
    #[arg(long, default_value = "frame.png")]
    pub out: PathBuf,
    /// wgpu backend: gl (default; Mesa llvmpipe on a CPU), vulkan (lavapipe or a GPU) or
    /// primary. Overrides the WGPU_BACKEND environment variable.
    #[arg(long)]
    pub backend: Option<String>,
    /// Seed (clutter placement and sensor noise): the built-in scene's (default 1), or one
    /// that replaces the scenario's, as `--set seed=N` would.
    #[arg(long)]
    pub seed: Option<u64>,
    /// With SCENARIO: override a field by its dotted path, e.g. --set tracker.lambda=0.7
    /// (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// The built-in scene's seed when `--seed` is not given.
const BUILTIN_SEED: u64 = 1;

/// Frame period used to turn `--time` into a frame index: the camera's 15 Hz (paper
/// section 3), the loop's rate.
const FRAME_RATE_HZ: f64 = vehicle::CAMERA_HZ as f64;

/// Runs the subcommand.
pub fn run(args: RenderArgs) -> anyhow::Result<()> {
    if !(args.time.is_finite() && args.time >= 0.0) {
        bail!(
            "--time must be a finite number of seconds ≥ 0, got {}",
            args.time
        );
    }
    png_path("--out", &args.out)?;
    if let Some(path) = &args.scenario {
        return render_scenario(path, &args);
    }
    if let Some(set) = args.set.first() {
        bail!("--set {set}: overrides need a SCENARIO file; the built-in scene takes only --seed");
    }
    let backend = Backend::choose(args.backend.as_deref())?;
    let description = builtin_description(builtin_target(), args.seed.unwrap_or(BUILTIN_SEED));
    let scene =
        std::sync::Arc::new(Scene::build(description).context("building the built-in scene")?);
    let rig = CameraRig::default();
    let options = RenderOptions {
        backend,
        ..RenderOptions::default()
    };
    let mut renderer = Renderer::new(scene.clone(), rig.clone(), &options).map_err(incomplete)?;
    let (world_from_chase, world_from_lead) =
        builtin_poses(scene.description(), scene.route(), &rig.mount, args.time);
    let frame = renderer
        .render(&FrameInput::fixed_camera(
            (args.time * FRAME_RATE_HZ).round() as u64,
            args.time,
            world_from_chase,
            world_from_lead,
        ))
        .map_err(incomplete)?;
    frame
        .image
        .save(&args.out)
        .with_context(|| format!("writing {}", args.out.display()))
        .map_err(incomplete)?;
    let t = frame.truth;
    say!(
        "{}: t = {:.3} s on {}; target c = ({:.2}, {:.2}) px, scale {:.4}, camera-frame position ({:.3}, {:.3}, {:.3}) m{}",
        args.out.display(),
        args.time,
        renderer.adapter_name(),
        t.c_x,
        t.c_y,
        t.scale,
        t.target_cam_m[0],
        t.target_cam_m[1],
        t.target_cam_m[2],
        if t.in_view { "" } else { " (not wholly in view)" }
    );
    Ok(())
}

/// The frame at `args.time` of a scenario's closed-loop run.
fn render_scenario(path: &std::path::Path, args: &RenderArgs) -> anyhow::Result<()> {
    let mut overrides = args.set.clone();
    if let Some(seed) = args.seed {
        overrides.push(format!("seed={seed}"));
    }
    let plan = sim_core::Plan::load(path, &overrides)?;
    let scenario = plan.scenario().clone();
    // The frame nearest --time must be one of the run's.
    let frames = scenario.frames();
    let wanted = (args.time * FRAME_RATE_HZ).round() as u64;
    if wanted >= frames {
        bail!(
            "--time {} is past the last frame of `{}` (t = {:.3} s of its {} s)",
            args.time,
            scenario.name,
            frames.saturating_sub(1) as f64 / FRAME_RATE_HZ,
            scenario.duration_s
        );
    }
    // A run has frames only every 1/15 s: say which one stands for a time between them.
    let at = wanted as f64 / FRAME_RATE_HZ;
    if (at - args.time).abs() > 1e-9 {
        eprintln!(
            "note: --time {} s falls between the run's camera frames (15 Hz): rendering frame \
             {wanted}, t = {at:.3} s",
            args.time
        );
    }
    let backend = Backend::choose(args.backend.as_deref())?;
    let mut looped = sim_core::ClosedLoop::new(plan, backend, false).map_err(incomplete)?;
    loop {
        let out = looped.step().map_err(incomplete)?.with_context(|| {
            format!(
                "the run of `{}` ended before {} s",
                scenario.name, args.time
            )
        })?;
        if out.record.frame == wanted {
            out.image
                .save(&args.out)
                .with_context(|| format!("writing {}", args.out.display()))
                .map_err(incomplete)?;
            let r = out.record;
            let target = if scenario.has_lead {
                format!(
                    "target c = ({:.2}, {:.2}) px, scale {:.4}, range {:.2} m",
                    r.true_cx, r.true_cy, r.true_scale, r.true_range_m
                )
            } else {
                "no lead".to_string()
            };
            say!(
                "{}: `{}` at t = {:.3} s; {target}; tracker: {}",
                args.out.display(),
                scenario.name,
                r.t_s,
                r.status.as_str()
            );
            return Ok(());
        }
    }
}

//! `carfollow render-worker`: a second renderer for `carfollow run`, in its own process
//! (see `sim::render_worker`). Started by `run`, not by people.

use anyhow::Context;
use clap::Args;
use sim::camera::{Backend, FrameInput, Renderer};
use sim::closed_loop::{render_options, CameraSetup};
use sim::render_worker::{fingerprint, serve_frames};
use sim::scenario::Scenario;
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `carfollow render-worker`: the scenario as `run` was given it.
#[derive(Args, Debug)]
pub struct RenderWorkerArgs {
    /// The scenario file; none for the built-in nist-grounds.
    pub scenario: Option<PathBuf>,
    /// Overrides, as given to `run`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// wgpu backend.
    #[arg(long)]
    pub backend: Option<String>,
}

/// Builds the scenario's scene and serves frames on stdin and stdout until stdin ends.
pub fn run_render_worker(args: RenderWorkerArgs) -> anyhow::Result<ExitCode> {
    let scenario = match &args.scenario {
        Some(path) => Scenario::load(path, &args.set)?,
        None => Scenario::builtin(&args.set)?,
    };
    let backend = Backend::choose(args.backend.as_deref())?;
    let setup = CameraSetup::new(&scenario)?;
    let options = render_options(backend);
    let mut renderer = Renderer::new(&setup.scene, setup.rig.clone(), &options)?;
    warm_up(&mut renderer, &scenario, &setup)?;
    let print = fingerprint(setup.scene.description(), &setup.rig, &options);
    serve_frames(
        &mut renderer,
        print,
        std::io::stdin().lock(),
        std::io::stdout().lock(),
    )
    .context("cannot serve frames")?;
    Ok(ExitCode::SUCCESS)
}

/// Renders (and drops) a whole frame of the vehicles where the scenario starts them, before
/// the worker says it is ready: its shaders compile and the first shadow tiles draw now,
/// while the loop renders its own first frame, and not when the loop waits for the worker's
/// first frame. A frame's pixels never depend on what the renderer drew before it.
fn warm_up(
    renderer: &mut Renderer,
    scenario: &Scenario,
    setup: &CameraSetup,
) -> anyhow::Result<()> {
    let lateral = 0.5 * scenario.route.lane_width_m;
    let route = setup.scene.route();
    let world_from_chase = route.pose_at(scenario.chase_start_m, lateral);
    let world_from_lead = route.pose_at(scenario.lead_start_m, lateral) * setup.lead_from_scene;
    renderer
        .render(&FrameInput::fixed_camera(
            0,
            0.0,
            world_from_chase,
            world_from_lead,
        ))
        .context("cannot render a first frame")?;
    Ok(())
}

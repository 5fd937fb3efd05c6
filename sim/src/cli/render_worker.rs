//! `carfollow render-worker`: a second renderer for `carfollow run`, in its own process
//! (see `sim_core::ClosedLoop::start`). Started by `run`, not by people.

use anyhow::Context;
use clap::Args;
use sim_core::{fingerprint, render_options, serve_frames, Plan};
use sim_render::{Backend, Renderer};
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
    let plan = match &args.scenario {
        Some(path) => Plan::load(path, &args.set)?,
        None => Plan::builtin(&args.set)?,
    };
    let backend = Backend::choose(args.backend.as_deref())?;
    let options = render_options(backend);
    let (scene, rig) = (plan.scene(), plan.rig());
    let mut renderer = Renderer::new(scene.clone(), rig.clone(), &options)?;
    let print = fingerprint(scene.description(), rig, &options);
    serve_frames(
        &mut renderer,
        print,
        std::io::stdin().lock(),
        std::io::stdout().lock(),
    )
    .context("cannot serve frames")?;
    Ok(ExitCode::SUCCESS)
}

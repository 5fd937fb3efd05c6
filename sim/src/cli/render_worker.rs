//! `carfollow render-worker`: a second renderer for `carfollow run`, in its own process
//! (see `sim::render_worker`). Started by `run`, not by people.

use anyhow::Context;
use clap::Args;
use sim::camera::{Backend, Renderer};
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

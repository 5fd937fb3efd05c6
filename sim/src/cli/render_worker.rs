//! `carfollow render-worker`: a second renderer for `carfollow run`, in its own process
//! (see `sim_core::ClosedLoop::start`). Started by `run`, not by people: the loop sends it
//! the scene it planned, so it reads no scenario and plans nothing.

use anyhow::Context;
use clap::Args;
use sim_core::{fingerprint, receive_scene, render_options, serve_frames};
use sim_render::{Backend, Renderer, Scene};
use std::process::ExitCode;
use std::sync::Arc;

/// Arguments of `carfollow render-worker`.
#[derive(Args, Debug)]
pub struct RenderWorkerArgs {
    /// wgpu backend.
    #[arg(long)]
    pub backend: Option<String>,
}

/// Receives the loop's scene on stdin, builds it and serves frames on stdin and stdout
/// until stdin ends.
pub fn run_render_worker(args: RenderWorkerArgs) -> anyhow::Result<ExitCode> {
    let mut input = std::io::stdin().lock();
    let (description, rig) = receive_scene(&mut input).context("cannot read the loop's scene")?;
    let scene = Arc::new(Scene::build(description)?);
    let backend = Backend::choose(args.backend.as_deref())?;
    let options = render_options(backend);
    let mut renderer = Renderer::new(scene.clone(), rig.clone(), &options)?;
    let print = fingerprint(scene.description(), &rig, &options);
    serve_frames(&mut renderer, print, input, std::io::stdout().lock())
        .context("cannot serve frames")?;
    Ok(ExitCode::SUCCESS)
}

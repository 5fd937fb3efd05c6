//! `carfollow run`: scenarios through the closed loop, with their outputs and verdicts.

use anyhow::Context;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use sim::camera::Backend;
use sim::child::RASTER_THREADS_ENV;
use sim::closed_loop::{ClosedLoop, LoopTiming};
use sim::report::{write_junit, OutputOptions, RunOutputs, Summary};
use sim::scenario::Scenario;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

/// Arguments of `carfollow run`.
#[derive(Args, Debug)]
#[command(
    about = "Run scenarios through the closed loop (camera, tracker, delay line, controllers, physics)",
    long_about = "Run each SCENARIO.toml (with none, the built-in nist-grounds) headless and \
                  write frames.csv, summary.json, plots and junit.xml to renders/<scenario>/ \
                  (or to --out). Exit status: 0 when every scenario passed its [expect], 1 when \
                  one failed, 2 on bad input."
)]
pub struct RunArgs {
    /// Scenario files; none runs the built-in nist-grounds.
    pub scenarios: Vec<PathBuf>,
    /// Output folder (default renders/<scenario>; with several scenarios, DIR/<scenario>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Override a field by its dotted path, e.g. --set tracker.lambda=0.7 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Also write the camera view with the tracker's overlay (video.gif) and PNG stills.
    #[arg(long)]
    pub video: bool,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// wgpu backend: gl (default; Mesa llvmpipe), vulkan or primary. Overrides WGPU_BACKEND.
    #[arg(long)]
    pub backend: Option<String>,
    /// Camera frames rendered at once: 1, or 2 (the second in a worker process; the
    /// results are the same). Default: 2 on a machine with two cores or more.
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=2))]
    pub renderers: Option<u8>,
}

/// Runs the subcommand: exit status 0 when every scenario passed its `[expect]`, 1 when one
/// failed; bad input is an error (exit status 2).
pub fn run_run(args: RunArgs) -> anyhow::Result<ExitCode> {
    // Every scenario is validated before any runs: bad input never wastes a long run.
    let scenarios: Vec<Scenario> = if args.scenarios.is_empty() {
        vec![Scenario::builtin(&args.set)?]
    } else {
        args.scenarios
            .iter()
            .map(|p| Scenario::load(p, &args.set))
            .collect::<Result<_, _>>()?
    };
    let backend = Backend::choose(args.backend.as_deref())?;
    if renderers(&args) == 2 && std::env::var_os(RASTER_THREADS_ENV).is_none() {
        // With two renderers, one per core, llvmpipe's own rasteriser threads only get in
        // each other's way: each renders on its own thread (the worker inherits this).
        // Nothing has created a renderer or a thread yet.
        std::env::set_var(RASTER_THREADS_ENV, "0");
    }
    let root = args.out.clone().unwrap_or_else(|| PathBuf::from("renders"));
    let single_out = args.out.is_some() && scenarios.len() == 1;
    let mut summaries = Vec::new();
    for scenario in &scenarios {
        let dir = if single_out {
            root.clone()
        } else {
            root.join(&scenario.name)
        };
        let summary = run_one(scenario, backend, &dir, &args)?;
        println!("{}", verdict(&summary, &dir));
        summaries.push(summary);
    }
    if scenarios.len() > 1 {
        let path = write_junit(root.join("junit.xml"), &summaries)?;
        println!("{}: {} scenarios", path.display(), summaries.len());
    }
    let passed = summaries.iter().all(|s| s.passed);
    Ok(if passed {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// One line: the scenario, PASS or FAIL with its failures, and where the outputs are.
fn verdict(s: &Summary, dir: &Path) -> String {
    let head = format!(
        "{}: {} in {:.1} s ({:.1}× real time); gap {:.1}–{:.1} m, tracking lost {:.1} s; outputs in {}",
        s.scenario,
        if s.passed { "PASS" } else { "FAIL" },
        s.wall_s,
        s.realtime_factor.unwrap_or(0.0),
        s.gap_m.min,
        s.gap_m.max,
        // Adding 0.0 turns a −0.0 into 0.0 for display.
        s.tracking_lost_s + 0.0,
        dir.display()
    );
    if s.failures.is_empty() {
        head
    } else {
        format!("{head}\n  {}", s.failures.join("\n  "))
    }
}

/// Camera frames rendered at once (`--renderers`, default 2 with two cores or more).
fn renderers(args: &RunArgs) -> u8 {
    args.renderers.unwrap_or_else(|| {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        if cores >= 2 {
            2
        } else {
            1
        }
    })
}

fn run_one(
    scenario: &Scenario,
    backend: Backend,
    dir: &Path,
    args: &RunArgs,
) -> anyhow::Result<Summary> {
    let started = Instant::now();
    let mut looped = ClosedLoop::new(scenario, backend, args.video)?;
    if renderers(args) == 2 {
        let mut command = Command::new(
            std::env::current_exe().context("cannot find this program to start a renderer")?,
        );
        command.arg("render-worker");
        if let Some(path) = &scenario.path {
            command.arg(path);
        }
        for set in &args.set {
            command.arg("--set").arg(set);
        }
        command.arg("--backend").arg(backend.to_string());
        if let Err(e) = looped.add_render_worker(command) {
            eprintln!("warning: {e}; rendering one frame at a time");
        }
    }
    let frames = looped.frames();
    let mut outputs = RunOutputs::create(
        dir,
        OutputOptions {
            video: args.video,
            expected_frames: Some(frames),
            ..OutputOptions::default()
        },
    )
    .with_context(|| format!("{}: cannot write outputs", dir.display()))?;
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(frames)
    };
    bar.set_style(
        ProgressStyle::with_template("{prefix} [{bar:30}] {msg} ({elapsed_precise}, eta {eta})")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_prefix(scenario.name.clone());
    let mut outputs_s = 0.0;
    while let Some(out) = looped.step()? {
        let written = Instant::now();
        outputs.record(&out.record)?;
        if args.video {
            let img = sim::overlay::draw(&out.image, &out.track, &out.edges);
            outputs.frame_image(out.record.frame, &img)?;
        }
        bar.inc(1);
        if out.record.frame % 15 == 0 {
            let wall = started.elapsed().as_secs_f64();
            let fps = (out.record.frame + 1) as f64 / wall.max(1e-9);
            bar.set_message(format!(
                "t {:6.1}/{:.0} s, {:5.1} frames/s, {:4.1}× real time, gap {:5.2} m, {}",
                out.record.t_s,
                scenario.duration_s,
                fps,
                fps / 15.0,
                out.record.gap_m,
                out.record.status.as_str()
            ));
        }
        outputs_s += written.elapsed().as_secs_f64();
    }
    bar.finish_and_clear();
    let wall_s = started.elapsed().as_secs_f64();
    let timing = LoopTiming {
        outputs_s,
        ..looped.timing()
    };
    let summary = outputs.finish(
        &scenario.name,
        scenario.seed,
        &scenario.expect,
        wall_s,
        Some(timing),
    )?;
    write_junit(dir.join("junit.xml"), std::slice::from_ref(&summary))?;
    Ok(summary)
}

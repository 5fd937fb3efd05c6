//! `carfollow run`: scenarios through the closed loop, with their outputs and verdicts.

use super::exit::{self, incomplete, one_line};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use sim::{write_junit, JunitScenario, LiveOptions, Simulation, SimulationOptions, Summary};
use sim_core::{Plan, Scenario, RASTER_THREADS_ENV};
use sim_render::Backend;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::{Duration, Instant};

/// The default `--progress-every`, seconds: how often a run writes a progress line to
/// stderr when stderr is not a terminal (a CI or Slurm log, where the progress bar stays
/// hidden). Often enough to show it is alive; a 17-minute scenario (about 15 s of
/// wall-clock time) logs two or three lines.
const PROGRESS_EVERY_S: f64 = 5.0;

/// The default `--video-stride`: every third frame, 5 frames a second of simulated time,
/// still smooth at the vehicles' speeds and a third of the GIF (a 17-minute run: 5,100
/// frames rather than 15,300).
const DEFAULT_VIDEO_STRIDE: u32 = 3;

/// Arguments of `carfollow run`.
#[derive(Args, Debug)]
#[command(
    after_help = super::exit::HELP,
    about = "Run scenarios through the closed loop (camera, tracker, delay line, controllers, physics)",
    long_about = "Run each SCENARIO.toml (with none, the built-in nist-grounds) headless and \
                  write frames.csv, summary.json, plots and junit.xml to renders/<scenario>/ \
                  (or to --out). Every scenario is validated before any runs; a scenario that \
                  fails or cannot complete does not stop the others, and with several scenarios \
                  DIR/junit.xml holds them all. Exit status: 0 when everything ran and passed, 1 \
                  when a run completed but a criterion failed, 2 on bad input (found before \
                  anything runs), 3 when a run could not complete (renderer, worker, I/O)."
)]
pub struct RunArgs {
    /// Scenario files; none runs the built-in nist-grounds.
    pub scenarios: Vec<PathBuf>,
    /// Output folder (default renders/SCENARIO; with several scenarios, DIR/SCENARIO).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Override a field by its dotted path, e.g. --set tracker.lambda=0.7 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    #[command(flatten)]
    pub openscenario: super::import::OpenScenarioArgs,
    /// Also write the camera view with the tracker's overlay (video.gif) and PNG stills.
    #[arg(long)]
    pub video: bool,
    /// With --video, put every N-th camera frame into video.gif (1: all 15 a second; the
    /// GIF still plays in real time).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_VIDEO_STRIDE,
          value_parser = clap::value_parser!(u32).range(1..=150))]
    pub video_stride: u32,
    /// Off a terminal (CI, Slurm), write a progress line to stderr every SECONDS of
    /// wall-clock time (0: every frame).
    #[arg(long, value_name = "SECONDS", default_value_t = PROGRESS_EVERY_S,
          value_parser = progress_seconds)]
    pub progress_every: f64,
    /// No progress bar, and no progress lines off a terminal.
    #[arg(long)]
    pub quiet: bool,
    /// wgpu backend: gl (default; Mesa llvmpipe), vulkan or primary. Overrides WGPU_BACKEND.
    #[arg(long)]
    pub backend: Option<String>,
    /// Camera frames rendered at once: 1, or 2 (the second on a thread with a llvmpipe of
    /// its own, else in a worker process; the results are the same). Default: 2 on a
    /// machine with two cores or more.
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=2))]
    pub renderers: Option<u8>,
    /// Also record the run for Foxglove: run.mcap beside frames.csv (camera images with the
    /// tracker's overlay, transforms, the scene, tracker, controller and truth, events).
    #[arg(long)]
    pub mcap: bool,
    /// Record as --mcap, but keep run.mcap only when a criterion failed.
    #[arg(long, conflicts_with = "mcap")]
    pub mcap_failed: bool,
    /// Serve the run live over Foxglove's WebSocket protocol on 127.0.0.1 while it goes on.
    #[arg(long)]
    pub live: bool,
    /// The live view's port (0: any free port; the one chosen is printed).
    #[arg(long, value_name = "PORT", default_value_t = 8765, requires = "live")]
    pub live_port: u16,
    /// With --live, hold the run until a client has subscribed to a topic.
    #[arg(long, requires = "live")]
    pub live_wait: bool,
}

/// Runs the subcommand: exit status 0 when every scenario passed its `[expect]`, 1 when one
/// failed, 3 when one could not complete; bad input is an error (exit status 2) before
/// anything runs.
pub fn run_run(args: RunArgs) -> anyhow::Result<ExitCode> {
    // Every scenario is planned before any runs: bad input never wastes a long run.
    let plans: Vec<Plan> = if args.scenarios.is_empty() {
        vec![Plan::builtin(&args.set)?]
    } else {
        args.scenarios
            .iter()
            .map(|p| args.openscenario.plan(p, &args.set))
            .collect::<Result<_, _>>()?
    };
    let scenarios: Vec<Scenario> = plans.iter().map(|p| p.scenario().clone()).collect();
    // Each scenario writes to a folder named after it: two of one name would overwrite
    // each other's outputs.
    for (k, a) in scenarios.iter().enumerate() {
        if let Some(b) = scenarios[..k].iter().find(|b| b.name == a.name) {
            let file = |s: &Scenario| {
                s.path
                    .as_ref()
                    .map_or("the built-in scenario".into(), |p| p.display().to_string())
            };
            anyhow::bail!(
                "{} and {} are both named `{}`, so their outputs would share one folder: give \
                 one another `name`",
                file(b),
                file(a),
                a.name
            );
        }
    }
    let backend = Backend::choose(args.backend.as_deref())?;
    if rasterise_on_own_thread(&args) && std::env::var_os(RASTER_THREADS_ENV).is_none() {
        // Each renderer rasterises on its own thread (the worker inherits this). Nothing
        // has created a renderer or a thread yet.
        std::env::set_var(RASTER_THREADS_ENV, "0");
    }
    let root = args.out.clone().unwrap_or_else(|| PathBuf::from("renders"));
    let single_out = args.out.is_some() && scenarios.len() == 1;
    // Each scenario's outcome: its summary, or why it could not complete.
    let mut outcomes: Vec<(&Scenario, f64, Result<Summary, String>)> = Vec::new();
    for (scenario, plan) in scenarios.iter().zip(plans) {
        let dir = if single_out {
            root.clone()
        } else {
            root.join(&scenario.name)
        };
        let started = Instant::now();
        let outcome = run_one(plan, backend, &dir, &args).map_err(|e| one_line(&e));
        let wall_s = started.elapsed().as_secs_f64();
        match &outcome {
            Ok(summary) => say!("{}", verdict(summary, &dir)),
            Err(e) => eprintln!("error: {}: could not complete: {e}", scenario.name),
        }
        // The scenario's own junit.xml: a completed run's simulation wrote it; one that
        // could not complete says so in it.
        if outcome.is_err() && std::fs::create_dir_all(&dir).is_ok() {
            let entry = junit_entry(scenario, wall_s, &outcome);
            if let Err(e) = write_junit(dir.join("junit.xml"), &[entry]) {
                eprintln!("error: {e}");
            }
        }
        outcomes.push((scenario, wall_s, outcome));
    }
    if scenarios.len() > 1 {
        let entries: Vec<JunitScenario> = outcomes
            .iter()
            .map(|(s, wall_s, o)| junit_entry(s, *wall_s, o))
            .collect();
        let path = write_junit(root.join("junit.xml"), &entries).map_err(incomplete)?;
        say!("{}: {} scenarios", path.display(), entries.len());
    }
    let code = if outcomes.iter().any(|(_, _, o)| o.is_err()) {
        exit::INCOMPLETE
    } else if outcomes
        .iter()
        .all(|(_, _, o)| o.as_ref().is_ok_and(|s| s.passed))
    {
        exit::PASS
    } else {
        exit::FAILED
    };
    Ok(ExitCode::from(code))
}

/// `--progress-every`: finite seconds, 0 to a day.
pub(crate) fn progress_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if (0.0..=86_400.0).contains(&v) => Ok(v),
        _ => Err(format!(
            "{text:?} is not a number of seconds from 0 to 86400"
        )),
    }
}

/// A scenario's entry in `junit.xml`.
fn junit_entry<'a>(
    scenario: &'a Scenario,
    wall_s: f64,
    outcome: &'a Result<Summary, String>,
) -> JunitScenario<'a> {
    match outcome {
        Ok(summary) => JunitScenario::Ran(summary),
        Err(error) => JunitScenario::Incomplete {
            scenario: &scenario.name,
            seed: scenario.seed,
            wall_s,
            error,
        },
    }
}

/// One line: the scenario, PASS or FAIL with its failures, and where the outputs are.
fn verdict(s: &Summary, dir: &Path) -> String {
    let head = format!(
        "{}: {} in {:.1} s ({:.1}× real time); {}, tracking lost {:.1} s; outputs in {}",
        s.scenario,
        if s.passed { "PASS" } else { "FAIL" },
        s.wall_s,
        s.realtime_factor.unwrap_or(0.0),
        // A run without a lead has no gap to it: the traffic's figures say the rest.
        if s.gap_m.min.is_finite() {
            format!("gap {:.1}–{:.1} m", s.gap_m.min, s.gap_m.max)
        } else {
            "no lead".to_string()
        },
        // Adding 0.0 turns a −0.0 into 0.0 for display.
        s.tracking_lost_s + 0.0,
        dir.display()
    );
    // A tracker that started with nothing placed: when it found its target.
    let head = match s.acquisition {
        None => head,
        Some(a) => match (a.acquired_t_s, a.range_m) {
            (Some(t), Some(r)) => format!(
                "{head}\n  the tracker first held its target at {t:.2} s, {r:.1} m off \
                 (searching {:.1} s before)",
                a.not_acquired_s + 0.0
            ),
            _ => format!(
                "{head}\n  the tracker never held its target (searching {:.1} s)",
                a.not_acquired_s + 0.0
            ),
        },
    };
    // A collision is news even where no criterion asks about it (said once: not again
    // when the failed `no_collision` criterion says it).
    let said = s
        .criteria
        .iter()
        .any(|c| c.name == "no_collision" && !c.passed);
    let head = match s.collisions {
        n if n == 0 || said => head,
        1 => format!("{head}\n  the vehicles collided once"),
        n => format!("{head}\n  the vehicles collided {n} times"),
    };
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

/// Whether llvmpipe should rasterise on each renderer's own thread instead of its pool of
/// rasteriser threads. With two renderers, one per core, the pool's threads only get in each
/// other's way. With one renderer they cost more than they share out, except on whole
/// frames: `nist-grounds` with `--renderers 1` runs 1.27× faster on its own thread (6
/// alternating pairs, CPU time 1.77 s → 1.46 s), while with `--video` (whole frames) it runs
/// at 0.94 of the pool's speed (5 pairs).
fn rasterise_on_own_thread(args: &RunArgs) -> bool {
    let whole_frames = args.video || args.mcap || args.mcap_failed || args.live;
    renderers(args) == 2 || !whole_frames
}

fn run_one(plan: Plan, backend: Backend, dir: &Path, args: &RunArgs) -> anyhow::Result<Summary> {
    let scenario = plan.scenario().clone();
    // The scenario is planned: from here on, whatever stops the run is not bad input.
    // The second renderer's process, where it cannot be a thread of this one (see
    // `ClosedLoop::start`): `carfollow render-worker`, which the loop sends its scene.
    let worker_process = std::env::current_exe().ok().map(|exe| {
        let mut command = Command::new(exe);
        command.arg("render-worker");
        command.arg("--backend").arg(backend.to_string());
        command
    });
    let mut sim = Simulation::new(
        plan,
        SimulationOptions {
            renderers: renderers(args),
            worker_process,
            out: Some(dir.to_path_buf()),
            video: args.video,
            video_stride: args.video_stride,
            mcap: args.mcap,
            mcap_failed: args.mcap_failed,
            live: args.live.then_some(LiveOptions {
                port: args.live_port,
                wait_for_client: args.live_wait,
            }),
            ..SimulationOptions::new(backend)
        },
    )
    .map_err(incomplete)?;
    for warning in scenario.warnings() {
        eprintln!("warning: {}: {warning}", scenario.name);
    }
    for note in sim.notes() {
        eprintln!("warning: {note}");
    }
    let progress = Progress::new(&scenario, sim.looped().frames(), args);
    let started = Instant::now();
    let mut road_end_said = false;
    while let Some(out) = sim.step().map_err(incomplete)? {
        progress.frame(&out.record, started.elapsed().as_secs_f64());
        if let (false, Some(t)) = (road_end_said, sim.looped().lead_at_road_end_s()) {
            road_end_said = true;
            progress.say(&format!(
                "warning: {}: at t = {t:.1} s the lead reached the route's end, where it \
                 stops: the rest of the run follows a standing lead",
                scenario.name
            ));
        }
    }
    if let Some(end) = sim.looped().run_ended() {
        progress.say(&format!(
            "{}: at t = {:.2} s the event `{}` of `{}` ended the run (end_run)",
            scenario.name,
            end.step.seconds(),
            end.event,
            end.vehicle
        ));
    }
    progress.done();
    let (summary, recording) = sim.finish().map_err(incomplete)?;
    if let Some(path) = recording {
        say!("{}: recording", path.display());
    }
    Ok(summary)
}

/// A run's progress: a bar on a terminal; off one (a CI or Slurm log, where the bar hides
/// itself), a line every `--progress-every` seconds; nothing with `--quiet`.
struct Progress {
    bar: ProgressBar,
    log_every: Option<Duration>,
    next_log: std::cell::Cell<Instant>,
    name: String,
    duration_s: f64,
    frames: u64,
}

impl Progress {
    fn new(scenario: &Scenario, frames: u64, args: &RunArgs) -> Progress {
        let bar = if args.quiet {
            ProgressBar::hidden()
        } else {
            ProgressBar::new(frames)
        };
        bar.set_style(
            ProgressStyle::with_template(
                "{prefix} [{bar:30}] {msg} ({elapsed_precise}, eta {eta})",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        bar.set_prefix(scenario.name.clone());
        let every = Duration::from_secs_f64(args.progress_every);
        Progress {
            bar,
            log_every: (!args.quiet && !std::io::stderr().is_terminal()).then_some(every),
            next_log: std::cell::Cell::new(Instant::now() + every),
            name: scenario.name.clone(),
            duration_s: scenario.duration_s,
            frames,
        }
    }

    /// Writes `line` to stderr, above the bar on a terminal.
    fn say(&self, line: &str) {
        self.bar.suspend(|| eprintln!("{line}"));
    }

    /// After frame `r`, `wall_s` seconds into the run.
    fn frame(&self, r: &sim_core::FrameRecord, wall_s: f64) {
        self.bar.inc(1);
        // The gap to the lead, or without one to the vehicle in the path.
        let gap_m = if r.gap_m.is_finite() {
            r.gap_m
        } else {
            r.traffic.as_ref().map_or(f64::NAN, |t| t.path_gap_m)
        };
        let now = Instant::now();
        if let Some(every) = self.log_every.filter(|_| now >= self.next_log.get()) {
            self.next_log.set(now + every);
            eprintln!(
                "{}: t {:.1}/{:.0} s ({:.0} %), {:.1}× real time, gap {:.2} m, {}",
                self.name,
                r.t_s,
                self.duration_s,
                100.0 * (r.frame + 1) as f64 / self.frames.max(1) as f64,
                r.t_s / wall_s.max(1e-9),
                gap_m,
                r.status.as_str()
            );
        }
        if r.frame.is_multiple_of(15) {
            let fps = (r.frame + 1) as f64 / wall_s.max(1e-9);
            self.bar.set_message(format!(
                "t {:6.1}/{:.0} s, {:5.1} frames/s, {:4.1}× real time, gap {:5.2} m, {}",
                r.t_s,
                self.duration_s,
                fps,
                fps / 15.0,
                gap_m,
                r.status.as_str()
            ));
        }
    }

    fn done(&self) {
        self.bar.finish_and_clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Command {
        #[command(flatten)]
        run: RunArgs,
    }

    fn args(given: &[&str]) -> RunArgs {
        Command::parse_from(std::iter::once("run").chain(given.iter().copied())).run
    }

    #[test]
    fn renderers_rasterise_on_their_own_threads_unless_one_draws_whole_frames() {
        assert!(rasterise_on_own_thread(&args(&["--renderers", "2"])));
        assert!(rasterise_on_own_thread(&args(&[
            "--renderers",
            "2",
            "--video"
        ])));
        assert!(rasterise_on_own_thread(&args(&["--renderers", "1"])));
        for whole_frames in ["--video", "--mcap", "--mcap-failed", "--live"] {
            assert!(
                !rasterise_on_own_thread(&args(&["--renderers", "1", whole_frames])),
                "{whole_frames}"
            );
        }
    }
}

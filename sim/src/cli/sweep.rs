//! `carfollow sweep`: a grid of scenarios, seeds and parameter values on all cores (or one
//! shard of it), with its report; `carfollow sweep merge`: joins shards' results.

use anyhow::Context;
use clap::{Args, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use sim::{
    dedupe_sorted, merge_dirs, read_failed, read_rows, run_points, serve_points, write_failed,
    write_report, FailedPoint, Manifest, Point, ResultRow, ResultsWriter, Roles, Shard, Sweep,
    SweepError, MANIFEST_FILE, RESULTS_FILE,
};
use sim_render::Backend;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use super::exit::{self, incomplete};
use super::paths::same_path;

/// The default `--progress-every`, seconds: how often a sweep writes a progress line to
/// stderr off a terminal (CI, Slurm logs), where the bar stays hidden.
const PROGRESS_EVERY_S: f64 = 10.0;

/// The file listing the missing points after a merge.
const MISSING_FILE: &str = "missing.txt";

/// Arguments of `carfollow sweep`.
#[derive(Args, Debug)]
#[command(
    after_help = super::exit::SWEEP_HELP,
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true,
    about = "Run a sweep: scenarios × seeds × parameter axes, on all cores or one shard",
    long_about = "Run every point of SWEEP.toml (scenarios × seeds × axes) headless, on --jobs \
                  worker processes. Each finished point appends one JSON line to DIR/results.jsonl \
                  (with --shard I/N, DIR/results-shard-I-of-N.jsonl) at once, and DIR/sweep.json \
                  names the sweep and its grid; --resume skips the points already there, and \
                  refuses results of another sweep file or other overrides. Points that could \
                  not run are listed in DIR/failed.txt (failed-shard-I-of-N.txt). At the end, \
                  writes table.csv, sweep-<axis>.png and summary.md to DIR. Exit status: 0 \
                  when every point ran (whatever its [expect] verdict), 2 on bad input, 3 when \
                  a point could not run."
)]
pub struct SweepArgs {
    /// `merge`: join shards' results.
    #[command(subcommand)]
    pub action: Option<SweepAction>,
    /// The sweep file.
    #[arg(required = true)]
    pub sweep: Option<PathBuf>,
    /// Output folder (default renders/sweeps/<sweep file's stem>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Points run at once, each in its own worker process (default: the number of cores).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Run only the I-th of N round-robin slices of the grid; I is 0-based (0 <= I < N).
    #[arg(long, value_name = "I/N")]
    pub shard: Option<Shard>,
    /// Keep the results file and skip the points already in it.
    #[arg(long)]
    pub resume: bool,
    /// Override a field of every point, after the sweep file's `set` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// For .xosc scenarios: the entity carfollow drives as the chase (default: one named
    /// Ego, ego, hero or ego_vehicle).
    #[arg(long, value_name = "NAME")]
    pub ego: Option<String>,
    /// For .xosc scenarios: the entity the chase follows (default: the nearest vehicle
    /// ahead of the ego in its lane at t = 0, or none if none is or it starts beyond the
    /// 250 m the renderer draws); `none`: no lead, the chase cruising until it finds a
    /// vehicle in its path.
    #[arg(long, value_name = "NAME")]
    pub lead: Option<String>,
    /// No progress bar, and no progress lines off a terminal.
    #[arg(long)]
    pub quiet: bool,
    /// Off a terminal (CI, Slurm), write a progress line to stderr at most every SECONDS
    /// of wall-clock time, when a point finishes (0: at every point).
    #[arg(long, value_name = "SECONDS", default_value_t = PROGRESS_EVERY_S,
          value_parser = super::run::progress_seconds)]
    pub progress_every: f64,
    /// wgpu backend: gl (default; Mesa llvmpipe), vulkan or primary. Overrides WGPU_BACKEND.
    #[arg(long)]
    pub backend: Option<String>,
    /// Check the sweep file and plan every point (as before a run), say how many points
    /// there are (in the shard) and how long the check took, and stop: nothing is run or
    /// written. For a sweep about to go to a cluster.
    #[arg(long)]
    pub dry_run: bool,
    /// Record every point, and keep the recordings (for Foxglove and `carfollow track`) of
    /// the points whose criteria failed, in DIR/recordings/SCENARIO-seedSEED-ID.mcap.
    #[arg(long)]
    pub mcap_failed: bool,
}

/// The folder of `--mcap-failed`'s recordings in a sweep's output folder.
const RECORDINGS_DIR: &str = "recordings";

/// Arguments of `carfollow sweep-worker` (started by `carfollow sweep`, not by people).
#[derive(Args, Debug)]
pub struct SweepWorkerArgs {
    /// The sweep file.
    pub sweep: PathBuf,
    /// Overrides, as given to `carfollow sweep`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// The chase of .xosc scenarios, as given to `carfollow sweep`.
    #[arg(long, value_name = "NAME")]
    pub ego: Option<String>,
    /// The lead of .xosc scenarios, as given to `carfollow sweep`.
    #[arg(long, value_name = "NAME")]
    pub lead: Option<String>,
    /// wgpu backend.
    #[arg(long)]
    pub backend: Option<String>,
    /// Overlap each point's physics with its rendering (there is a spare core).
    #[arg(long)]
    pub overlap: bool,
    /// Record each point here, keeping the recordings of points that failed a criterion.
    #[arg(long, value_name = "DIR")]
    pub mcap_failed: Option<PathBuf>,
}

/// Runs a sweep worker: point requests on stdin, one JSON answer per line on stdout (see
/// `sim::serve_points`).
pub fn run_sweep_worker(args: SweepWorkerArgs) -> anyhow::Result<ExitCode> {
    // The sweep that started this worker checked every point: none is planned again here
    // but the one it runs.
    let roles = Roles {
        ego: args.ego.clone(),
        lead: args.lead.clone(),
    };
    let sweep = Sweep::load_checked(&args.sweep, &args.set, &roles)?;
    let backend = Backend::choose(args.backend.as_deref())?;
    serve_points(
        &sweep,
        backend,
        args.overlap,
        args.mcap_failed.as_deref(),
        std::io::stdin().lock(),
        std::io::stdout().lock(),
    )
    .context("cannot answer the sweep")?;
    Ok(ExitCode::SUCCESS)
}

/// `carfollow sweep`'s subcommands.
#[derive(Subcommand, Debug)]
pub enum SweepAction {
    /// Join the results of shards (or of interrupted runs): dedupe by point id, sort by grid
    /// order, and write results.jsonl and the report; list the grid's missing points in
    /// missing.txt (exit status 3 when there are any).
    Merge(MergeArgs),
}

/// Arguments of `carfollow sweep merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// Folders holding results*.jsonl files.
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Output folder (default: the first DIR).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Accepted for symmetry with `sweep`: merge draws no progress bar anyway.
    #[arg(long)]
    pub quiet: bool,
}

/// Runs the subcommand.
pub fn run_sweep(args: SweepArgs) -> anyhow::Result<ExitCode> {
    if let Some(SweepAction::Merge(m)) = args.action {
        return run_merge(m);
    }
    // Before anything is read or written.
    if args.jobs == Some(0) {
        anyhow::bail!("--jobs must be at least 1");
    }
    let file = args.sweep.clone().expect("clap requires the sweep file");
    let checked = std::time::Instant::now();
    let roles = Roles {
        ego: args.ego.clone(),
        lead: args.lead.clone(),
    };
    let sweep = Sweep::load_as(&file, &args.set, &roles)?;
    if args.dry_run {
        let shard = sweep.shard(args.shard).len();
        if let Some(d) = &sweep.distribution {
            return Ok(dry_run_distribution(&file, &sweep, d, args.shard, checked));
        }
        println!(
            "{}: valid: {} point{} ({} scenario{} × {} seed{} × {} combination{} of the axes){}; checked \
             in {:.2} s with {} plan{} (points that differ only in the tracker's settings or \
             [expect] plan alike)",
            file.display(),
            sweep.points.len(),
            plural(sweep.points.len()),
            sweep.scenarios.len(),
            plural(sweep.scenarios.len()),
            sweep.seeds.len(),
            plural(sweep.seeds.len()),
            sweep.points.len() / (sweep.scenarios.len() * sweep.seeds.len()),
            plural(sweep.points.len() / (sweep.scenarios.len() * sweep.seeds.len())),
            args.shard.map_or(String::new(), |s| format!(
                ", {shard} in shard {}/{}",
                s.index, s.count
            )),
            checked.elapsed().as_secs_f64(),
            sweep.plans,
            plural(sweep.plans),
        );
        return Ok(ExitCode::SUCCESS);
    }
    let backend = Backend::choose(args.backend.as_deref())?;
    let out = args.out.clone().unwrap_or_else(|| {
        let stem = file
            .file_stem()
            .map_or("sweep".into(), |s| s.to_string_lossy());
        Path::new("renders/sweeps").join(stem.as_ref())
    });
    let results = out.join(
        args.shard
            .map_or(RESULTS_FILE.to_string(), |s| s.file_name()),
    );
    let failed_file = out.join(args.shard.map_or("failed.txt".to_string(), |s| {
        format!("failed-shard-{}-of-{}.txt", s.index, s.count)
    }));

    let (done_rows, complete) = resumable(&file, &out, &results, &sweep, args.resume)?;
    std::fs::create_dir_all(&out)
        .with_context(|| format!("{}: cannot create", out.display()))
        .map_err(incomplete)?;
    Manifest::of(&sweep, &args.set).write(&out)?;
    let points = sweep.shard(args.shard);
    let todo: Vec<_> = points
        .iter()
        .copied()
        .filter(|p| !done_rows.iter().any(|r| r.id == p.id))
        .collect();
    let writer = ResultsWriter::open(&results, args.resume.then_some(complete))?;
    let jobs = args.jobs.unwrap_or_else(cores);
    if !args.quiet {
        eprintln!(
            "{}: {} points{}, {} already done, {} to run on {} job{}; results in {}",
            file.display(),
            points.len(),
            args.shard.map_or(String::new(), |s| format!(
                " in shard {}/{}",
                s.index, s.count
            )),
            points.len() - todo.len(),
            todo.len(),
            jobs,
            if jobs == 1 { "" } else { "s" },
            results.display()
        );
    }

    let errors = run_with_progress(&args, &file, &out, backend, &points, &todo, jobs, &writer)?;

    let failed_points = failed_points(&errors, &todo);
    write_failed(&failed_file, &failed_points).map_err(incomplete)?;

    let (rows, _) = read_rows(&results)?;
    let rows = dedupe_sorted(rows);
    if rows.is_empty() {
        say!("{}: no point finished; no report", results.display());
    } else {
        let written = write_report(&out, &rows).map_err(incomplete)?;
        say!(
            "{}: {} of {} points done; report: {}",
            results.display(),
            rows.len(),
            points.len(),
            written
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    if args.mcap_failed {
        let dir = out.join(RECORDINGS_DIR);
        let kept = std::fs::read_dir(&dir).map_or(0, |entries| {
            entries
                .filter_map(Result::ok)
                .filter(|e| e.path().extension().is_some_and(|x| x == "mcap"))
                .count()
        });
        let noun = if kept == 1 { "recording" } else { "recordings" };
        say!(
            "{}: {kept} {noun} of points whose criteria failed",
            dir.display()
        );
    }
    if errors.is_empty() {
        Ok(ExitCode::SUCCESS)
    } else {
        eprintln!(
            "error: {} of {} points could not run; listed in {}",
            errors.len(),
            points.len(),
            failed_file.display()
        );
        Ok(ExitCode::from(exit::INCOMPLETE))
    }
}

/// The rows already in `results` (and the length of their complete lines), when the
/// folder `out` may take this sweep's results: a new folder, or, with `resume`, one holding
/// this sweep's own (its manifest and every row of the same hash). Says why not otherwise.
fn resumable(
    file: &Path,
    out: &Path,
    results: &Path,
    sweep: &Sweep,
    resume: bool,
) -> anyhow::Result<(Vec<ResultRow>, u64)> {
    // A folder that cannot be made is an output that cannot be written (exit 3), said as
    // such rather than as results that cannot be read.
    let nearest = out
        .ancestors()
        .find(|a| !a.as_os_str().is_empty() && a.exists());
    if let Some(blocked) = nearest.filter(|a| !a.is_dir()) {
        return Err(incomplete(anyhow::anyhow!(
            "{}: cannot create the output folder: {} is not a folder",
            out.display(),
            blocked.display()
        )));
    }
    let (done_rows, complete) = read_rows(results)?;
    let exists = std::fs::metadata(results).is_ok_and(|m| m.len() > 0);
    if exists && !resume {
        anyhow::bail!(
            "{} already has results: pass --resume to continue it, or remove it",
            results.display()
        );
    }
    // The folder's results must be of this sweep: the same file and overrides.
    if let Some(row) = done_rows
        .iter()
        .find(|r| !r.sweep_hash.is_empty() && r.sweep_hash != sweep.hash)
    {
        anyhow::bail!(
            "{}: its rows are of another sweep (hash {}; now {}): the sweep file, a \
             scenario, target, road or catalog file it uses, or the overrides changed since; use another \
             --out, or remove the results",
            results.display(),
            row.sweep_hash,
            sweep.hash
        );
    }
    match Manifest::read(out)? {
        Some(m) if m.hash != sweep.hash => anyhow::bail!(
            "{}: the results in {} are of another sweep (hash {}; now {}): the sweep file, \
             a scenario or target file it uses, or the overrides changed since; use another \
             --out, or remove the folder",
            file.display(),
            out.display(),
            m.hash,
            sweep.hash
        ),
        None if exists => anyhow::bail!(
            "{}: cannot tell which sweep these results are of ({} is missing); use another \
             --out, or remove the results",
            results.display(),
            MANIFEST_FILE
        ),
        _ => {}
    }
    Ok((done_rows, complete))
}

/// Runs the points `todo` of `points` on `jobs` worker processes, appending their rows with
/// `writer`, with a progress bar on a terminal (or a line every `--progress-every` seconds
/// off one); the points that could not run, with why.
#[allow(clippy::too_many_arguments)]
fn run_with_progress(
    args: &SweepArgs,
    file: &Path,
    out: &Path,
    backend: Backend,
    points: &[&Point],
    todo: &[&Point],
    jobs: usize,
    writer: &ResultsWriter,
) -> anyhow::Result<Vec<SweepError>> {
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(points.len() as u64)
    };
    bar.set_style(
        ProgressStyle::with_template(
            "sweep [{bar:30}] {pos}/{len} {msg} ({elapsed_precise}, eta {eta})",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar.set_position((points.len() - todo.len()) as u64);
    let failed = AtomicUsize::new(0);
    let finished = AtomicUsize::new(points.len() - todo.len());
    let log_progress = !args.quiet && !std::io::stderr().is_terminal();
    let every = Duration::from_secs_f64(args.progress_every);
    let next_log = Mutex::new(Instant::now() + every);
    let exe = std::env::current_exe().context("cannot find this program to start workers")?;
    // Overlapping a point's physics with its rendering pays only with a core to spare.
    let overlap = jobs < cores();
    let spawn_worker = || {
        let mut command = Command::new(&exe);
        command.arg("sweep-worker").arg(file);
        for set in &args.set {
            command.arg("--set").arg(set);
        }
        for (flag, name) in [("--ego", &args.ego), ("--lead", &args.lead)] {
            if let Some(name) = name {
                command.arg(flag).arg(name);
            }
        }
        command.arg("--backend").arg(backend.to_string());
        if overlap {
            command.arg("--overlap");
        }
        if args.mcap_failed {
            command.arg("--mcap-failed").arg(out.join(RECORDINGS_DIR));
        }
        command
    };
    let errors = run_points(todo, jobs, &spawn_worker, writer, |r| {
        match r {
            Ok(row) => bar.set_message(format!(
                "{}: lost {:.1} s",
                row.point,
                row.figure("/tracking_lost_s").unwrap_or(f64::NAN) + 0.0
            )),
            Err(e) => {
                failed.fetch_add(1, Ordering::Relaxed);
                // Said once: on the bar's terminal, or straight to stderr without one.
                if bar.is_hidden() {
                    eprintln!("error: {e}");
                } else {
                    bar.println(format!("error: {e}"));
                }
            }
        }
        bar.inc(1);
        let n = finished.fetch_add(1, Ordering::Relaxed) + 1;
        if log_progress {
            let mut next = next_log.lock().unwrap_or_else(|e| e.into_inner());
            if Instant::now() >= *next {
                *next = Instant::now() + every;
                eprintln!(
                    "sweep: {n}/{} points done, {} could not run",
                    points.len(),
                    failed.load(Ordering::Relaxed)
                );
            }
        }
    })
    .map_err(incomplete)?;
    bar.finish_and_clear();
    Ok(errors)
}

/// The points of `todo` that `errors` say could not run, for `failed.txt`.
fn failed_points(errors: &[SweepError], todo: &[&Point]) -> Vec<FailedPoint> {
    errors
        .iter()
        .map(|e| {
            let (point, error) = match e {
                SweepError::Run { point, message } => (point.clone(), message.clone()),
                other => (String::new(), other.to_string()),
            };
            let p = todo.iter().find(|p| p.describe() == point);
            FailedPoint {
                index: p.map_or(usize::MAX, |p| p.index),
                id: p.map_or(String::new(), |p| p.id.clone()),
                point,
                error,
            }
        })
        .collect()
}

/// The machine's cores (1 if it cannot tell).
fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

fn run_merge(args: MergeArgs) -> anyhow::Result<ExitCode> {
    let rows = merge_dirs(&args.dirs)?;
    let mut manifests = Vec::new();
    for dir in &args.dirs {
        if let Some(m) = Manifest::read(dir)? {
            manifests.push(m);
        }
    }
    let dirs = args
        .dirs
        .iter()
        .map(|d| d.display().to_string())
        .collect::<Vec<_>>()
        .join(", ");
    if rows.is_empty() && manifests.is_empty() {
        anyhow::bail!(
            "{dirs}: no sweep results to merge (no results*.jsonl rows, no {MANIFEST_FILE})"
        );
    }
    let mut hashes: Vec<&str> = rows
        .iter()
        .map(|r| r.sweep_hash.as_str())
        .chain(manifests.iter().map(|m| m.hash.as_str()))
        .filter(|h| !h.is_empty())
        .collect();
    hashes.sort_unstable();
    hashes.dedup();
    if hashes.len() > 1 {
        anyhow::bail!(
            "{dirs}: the folders hold results of different sweeps (hashes {})",
            hashes.join(", ")
        );
    }
    let out = args.out.unwrap_or_else(|| args.dirs[0].clone());
    // Another folder's results would be overwritten: merge into a new folder, or into one
    // of those merged (whose rows are then among the merged).
    if out.is_dir() && !args.dirs.iter().any(|d| same_path(d, &out)) {
        let holds_results = out.join(MANIFEST_FILE).exists()
            || std::fs::read_dir(&out)?.flatten().any(|e| {
                let name = e.file_name().to_string_lossy().to_string();
                name.starts_with("results") && name.ends_with(".jsonl")
            });
        if holds_results {
            anyhow::bail!(
                "--out {}: already holds sweep results; merge into a new folder, or list it \
                 among the folders to merge",
                out.display()
            );
        }
    }
    std::fs::create_dir_all(&out)
        .with_context(|| format!("{}: cannot create", out.display()))
        .map_err(incomplete)?;
    let results = out.join(RESULTS_FILE);
    let writer = ResultsWriter::open(&results, None)?;
    for row in &rows {
        writer.append(row)?;
    }
    let report = if rows.is_empty() {
        "none (no point finished)".to_string()
    } else {
        write_report(&out, &rows)?
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let Some(manifest) = manifests.first() else {
        say!(
            "{}: {} points merged from {} folders; report: {report}",
            results.display(),
            rows.len(),
            args.dirs.len(),
        );
        eprintln!("warning: no {MANIFEST_FILE} in {dirs}: the grid is unknown, so missing points cannot be listed");
        return Ok(ExitCode::SUCCESS);
    };
    manifest.write(&out)?;
    // The grid's points that no folder has a row of, with why when a run said so.
    let mut failed = Vec::new();
    for dir in &args.dirs {
        failed.extend(read_failed(dir)?);
    }
    let missing: Vec<FailedPoint> = manifest
        .points
        .iter()
        .filter(|p| !rows.iter().any(|r| r.id == p.id))
        .map(|p| FailedPoint {
            index: p.index,
            id: p.id.clone(),
            point: p.point.clone(),
            error: failed
                .iter()
                .find(|f| f.id == p.id)
                .map_or("not run".into(), |f| format!("failed: {}", f.error)),
        })
        .collect();
    let missing_file = out.join(MISSING_FILE);
    write_failed(&missing_file, &missing)?;
    say!(
        "{}: {} of {} points merged from {} folders; report: {report}",
        results.display(),
        rows.len(),
        manifest.points.len(),
        args.dirs.len(),
    );
    if missing.is_empty() {
        return Ok(ExitCode::SUCCESS);
    }
    let n_failed = missing
        .iter()
        .filter(|m| m.error.starts_with("failed"))
        .count();
    let shown: Vec<String> = missing.iter().take(5).map(|m| m.point.clone()).collect();
    eprintln!(
        "error: the sweep is incomplete: {} of {} points missing ({} failed, {} not run): {}{}; all listed in {}",
        missing.len(),
        manifest.points.len(),
        n_failed,
        missing.len() - n_failed,
        shown.join(", "),
        if missing.len() > shown.len() { ", ..." } else { "" },
        missing_file.display()
    );
    Ok(ExitCode::from(exit::INCOMPLETE))
}

/// `--dry-run` of a parameter distribution: its points listed, one a line, after the
/// line a sweep file's dry run says.
fn dry_run_distribution(
    file: &Path,
    sweep: &Sweep,
    d: &sim_core::openscenario::Distribution,
    shard: Option<Shard>,
    checked: Instant,
) -> ExitCode {
    let points = sweep.shard(shard);
    let drawn = d
        .random_seed
        .map_or(String::new(), |s| format!(", drawn with randomSeed {s}"));
    println!(
        "{}: valid: {} point{} ({} run{} of {}'s parameters{drawn}, seed {}){}; checked in \
         {:.2} s with {} plan{}",
        file.display(),
        sweep.points.len(),
        plural(sweep.points.len()),
        d.runs.len(),
        plural(d.runs.len()),
        d.scenario.display(),
        sweep.seeds[0],
        shard.map_or(String::new(), |s| format!(
            ", {} in shard {}/{}",
            points.len(),
            s.index,
            s.count
        )),
        checked.elapsed().as_secs_f64(),
        sweep.plans,
        plural(sweep.plans),
    );
    for p in points {
        println!("{} {}", p.id, p.describe());
    }
    ExitCode::SUCCESS
}

/// "s" for a count other than 1.
fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

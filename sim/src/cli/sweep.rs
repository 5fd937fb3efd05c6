//! `carfollow sweep`: a grid of scenarios, seeds and parameter values on all cores (or one
//! shard of it), with its report; `carfollow sweep merge`: joins shards' results.

use anyhow::Context;
use clap::{Args, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use sim::camera::Backend;
use sim::sweep::{
    dedupe_sorted, merge_dirs, read_rows, run_points, serve_points, write_report, ResultsWriter,
    Shard, Sweep, RESULTS_FILE,
};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Arguments of `carfollow sweep`.
#[derive(Args, Debug)]
#[command(
    after_help = super::exit::HELP,
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true,
    about = "Run a sweep: scenarios × seeds × parameter axes, on all cores or one shard",
    long_about = "Run every point of SWEEP.toml (scenarios × seeds × axes) headless, on --jobs \
                  worker processes. Each finished point appends one JSON line to DIR/results.jsonl \
                  (with --shard I/N, DIR/results-shard-I-of-N.jsonl) at once; --resume skips \
                  the points already there. At the end, writes table.csv, sweep-<axis>.png and \
                  summary.md to DIR. Exit status: 0 when every point ran (whatever its \
                  [expect] verdict), 1 when a point could not run, 2 on bad input."
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
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// wgpu backend: gl (default; Mesa llvmpipe), vulkan or primary. Overrides WGPU_BACKEND.
    #[arg(long)]
    pub backend: Option<String>,
}

/// Arguments of `carfollow sweep-worker` (started by `carfollow sweep`, not by people).
#[derive(Args, Debug)]
pub struct SweepWorkerArgs {
    /// The sweep file.
    pub sweep: PathBuf,
    /// Overrides, as given to `carfollow sweep`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// wgpu backend.
    #[arg(long)]
    pub backend: Option<String>,
    /// Overlap each point's physics with its rendering (there is a spare core).
    #[arg(long)]
    pub overlap: bool,
}

/// Runs a sweep worker: point requests on stdin, one JSON answer per line on stdout (see
/// `sim::sweep::serve_points`).
pub fn run_sweep_worker(args: SweepWorkerArgs) -> anyhow::Result<ExitCode> {
    let sweep = Sweep::load(&args.sweep, &args.set)?;
    let backend = Backend::choose(args.backend.as_deref())?;
    serve_points(
        &sweep,
        backend,
        args.overlap,
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
    /// order, and write results.jsonl and the report.
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
}

/// Runs the subcommand.
pub fn run_sweep(args: SweepArgs) -> anyhow::Result<ExitCode> {
    if let Some(SweepAction::Merge(m)) = args.action {
        return run_merge(m);
    }
    let file = args.sweep.clone().expect("clap requires the sweep file");
    let sweep = Sweep::load(&file, &args.set)?;
    let backend = Backend::choose(args.backend.as_deref())?;
    let out = args.out.clone().unwrap_or_else(|| {
        let stem = file
            .file_stem()
            .map_or("sweep".into(), |s| s.to_string_lossy());
        Path::new("renders/sweeps").join(stem.as_ref())
    });
    std::fs::create_dir_all(&out).with_context(|| format!("{}: cannot create", out.display()))?;
    let results = out.join(
        args.shard
            .map_or(RESULTS_FILE.to_string(), |s| s.file_name()),
    );

    let (done_rows, complete) = read_rows(&results)?;
    let exists = std::fs::metadata(&results).is_ok_and(|m| m.len() > 0);
    if exists && !args.resume {
        anyhow::bail!(
            "{} already has results: pass --resume to continue it, or remove it",
            results.display()
        );
    }
    let points = sweep.shard(args.shard);
    let todo: Vec<_> = points
        .iter()
        .copied()
        .filter(|p| !done_rows.iter().any(|r| r.id == p.id))
        .collect();
    let writer = ResultsWriter::open(&results, args.resume.then_some(complete))?;
    let jobs = args.jobs.unwrap_or_else(cores);
    if jobs == 0 {
        anyhow::bail!("--jobs must be at least 1");
    }
    if !args.quiet {
        eprintln!(
            "{}: {} points{}, {} already done, {} to run on {} jobs; results in {}",
            file.display(),
            points.len(),
            args.shard.map_or(String::new(), |s| format!(
                " in shard {}/{}",
                s.index, s.count
            )),
            points.len() - todo.len(),
            todo.len(),
            jobs,
            results.display()
        );
    }

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
    let exe = std::env::current_exe().context("cannot find this program to start workers")?;
    // Overlapping a point's physics with its rendering pays only with a core to spare.
    let overlap = jobs < cores();
    let spawn_worker = || {
        let mut command = Command::new(&exe);
        command.arg("sweep-worker").arg(&file);
        for set in &args.set {
            command.arg("--set").arg(set);
        }
        command.arg("--backend").arg(backend.to_string());
        if overlap {
            command.arg("--overlap");
        }
        command
    };
    let errors = run_points(&todo, jobs, &spawn_worker, &writer, |r| {
        match r {
            Ok(row) => bar.set_message(format!(
                "{}: lost {:.1} s",
                row.point,
                row.figure("/tracking_lost_s").unwrap_or(f64::NAN) + 0.0
            )),
            Err(e) => {
                failed.fetch_add(1, Ordering::Relaxed);
                bar.println(format!("error: {e}"));
            }
        }
        bar.inc(1);
    })?;
    bar.finish_and_clear();

    let (rows, _) = read_rows(&results)?;
    let rows = dedupe_sorted(rows);
    let written = write_report(&out, &rows)?;
    println!(
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
    for e in &errors {
        eprintln!("error: {e}");
    }
    Ok(if errors.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// The machine's cores (1 if it cannot tell).
fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

fn run_merge(args: MergeArgs) -> anyhow::Result<ExitCode> {
    let rows = merge_dirs(&args.dirs)?;
    let out = args.out.unwrap_or_else(|| args.dirs[0].clone());
    std::fs::create_dir_all(&out).with_context(|| format!("{}: cannot create", out.display()))?;
    let results = out.join(RESULTS_FILE);
    let writer = ResultsWriter::open(&results, None)?;
    for row in &rows {
        writer.append(row)?;
    }
    let written = write_report(&out, &rows)?;
    println!(
        "{}: {} points merged from {} folders; report: {}",
        results.display(),
        rows.len(),
        args.dirs.len(),
        written
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(ExitCode::SUCCESS)
}

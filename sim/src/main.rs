//! `carfollow`: the car-following simulator's command line.
use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// `println!` for the command line's report on stdout, which goes on when stdout is gone:
/// `carfollow run | head -1` keeps running and writing its outputs after `head` has left,
/// instead of panicking on the closed pipe.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        // A reader that went away (a closed pipe) is not the run's failure.
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

mod cli {
    pub mod check;
    pub mod exit;
    pub mod export;
    pub mod import;
    pub mod paths;
    pub mod render;
    pub mod render_worker;
    pub mod run;
    pub mod sweep;
    pub mod synth;
    pub mod target;
    pub mod track;
}

#[derive(Parser)]
#[command(
    name = "carfollow",
    version,
    about = "Closed-loop car-following simulator",
    after_help = cli::exit::HELP
)]
struct Cli {
    #[command(subcommand)]
    command: Commands,
}

#[derive(Subcommand)]
enum Commands {
    /// Run scenarios through the closed loop (default: the built-in nist-grounds).
    Run(cli::run::RunArgs),
    /// Run a sweep (scenarios × seeds × parameter axes) on all cores, or merge shards.
    Sweep(cli::sweep::SweepArgs),
    /// Validate scenario files without running them.
    Check(cli::check::CheckArgs),
    /// Write an OpenSCENARIO file (.xosc) as a carfollow scenario file.
    Import(cli::import::ImportArgs),
    /// Write a scenario as OpenSCENARIO (.xosc) on an OpenDRIVE road (.xodr).
    Export(cli::export::ExportArgs),
    /// Render one camera frame at time T, of a scenario's run or of the built-in scene.
    Render(cli::render::RenderArgs),
    /// Run the tracker on a folder of recorded frames.
    Track(cli::track::TrackArgs),
    /// Check a target model file and draw it.
    Target(cli::target::TargetArgs),
    /// Write a synthetic frame sequence of a target, with its ground truth.
    Synth(cli::synth::SynthArgs),
    /// Print the scenario format's JSON Schema (for editors that check TOML against one).
    #[command(
        after_help = "Writes scenarios/carfollow-scenario.schema.json's text to stdout. Exit \
                      status: 0."
    )]
    Schema,
    /// Print the command-line reference as Markdown (the book's `reference/cli.md`).
    #[command(hide = true)]
    CliReference,
    /// A sweep's worker process (started by `carfollow sweep`).
    #[command(hide = true)]
    SweepWorker(cli::sweep::SweepWorkerArgs),
    /// `run`'s second renderer (started by `carfollow run`).
    #[command(hide = true)]
    RenderWorker(cli::render_worker::RenderWorkerArgs),
}

fn main() -> ExitCode {
    release_large_blocks();
    let cli = Cli::parse();
    let result = match cli.command {
        Commands::Run(args) => cli::run::run_run(args),
        Commands::Sweep(args) => cli::sweep::run_sweep(args),
        Commands::Check(args) => cli::check::run_check(args),
        Commands::Import(args) => cli::import::run_import(args).map(|()| ExitCode::SUCCESS),
        Commands::Export(args) => cli::export::run_export(args).map(|()| ExitCode::SUCCESS),
        Commands::Render(args) => cli::render::run(args).map(|()| ExitCode::SUCCESS),
        Commands::Track(args) => cli::track::run_track(args).map(|()| ExitCode::SUCCESS),
        Commands::Target(args) => cli::target::run_target(args).map(|()| ExitCode::SUCCESS),
        Commands::Synth(args) => cli::synth::run_synth(args).map(|()| ExitCode::SUCCESS),
        Commands::CliReference => {
            say!("{}", cli_reference().trim_end());
            Ok(ExitCode::SUCCESS)
        }
        Commands::Schema => {
            say!("{}", sim_core::scenario_schema_json().trim_end());
            Ok(ExitCode::SUCCESS)
        }
        Commands::SweepWorker(args) => cli::sweep::run_sweep_worker(args),
        Commands::RenderWorker(args) => cli::render_worker::run_render_worker(args),
    };
    match result {
        Ok(code) => code,
        Err(error) => {
            eprintln!("error: {}", cli::exit::one_line(&error));
            cli::exit::code_of(&error)
        }
    }
}

/// The command-line reference of `docs/src/reference/cli.md`, from the clap definitions:
/// every visible command with its arguments, options and their help.
fn cli_reference() -> String {
    let options = clap_markdown::MarkdownOptions::new()
        .title("Command-line reference".to_string())
        .show_footer(false);
    clap_markdown::help_markdown_custom::<Cli>(&options)
}

/// Makes the allocator take blocks of 256 KiB and more straight from the system (glibc's
/// `M_MMAP_THRESHOLD`), so that freeing one gives its memory back. Left to itself, glibc
/// raises that threshold once such a block is freed, and the scene's groups of districts,
/// built and let go as a long route goes by, then leave the heap in pieces that are never
/// given back: a 30-minute run's peak was 12 % over a 90-second run's, and is 8 % with
/// this (`/usr/bin/time -f %M`, `run --renderers 1` and 2). Workers run this too.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn release_large_blocks() {
    // SAFETY: mallopt sets an allocator parameter, before any other thread is started.
    unsafe { libc::mallopt(libc::M_MMAP_THRESHOLD, 256 * 1024) };
}

/// Elsewhere the allocator is left as it is.
#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn release_large_blocks() {}

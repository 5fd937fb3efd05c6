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
    /// Render one camera frame at time T, of a scenario's run or of the built-in scene.
    Render(cli::render::RenderArgs),
    /// Run the tracker on a folder of recorded frames.
    Track(cli::track::TrackArgs),
    /// Check a target model file and draw it.
    Target(cli::target::TargetArgs),
    /// Write a synthetic frame sequence of a target, with its ground truth.
    Synth(cli::synth::SynthArgs),
    /// A sweep's worker process (started by `carfollow sweep`).
    #[command(hide = true)]
    SweepWorker(cli::sweep::SweepWorkerArgs),
    /// `run`'s second renderer (started by `carfollow run`).
    #[command(hide = true)]
    RenderWorker(cli::render_worker::RenderWorkerArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Commands::Run(args) => cli::run::run_run(args),
        Commands::Sweep(args) => cli::sweep::run_sweep(args),
        Commands::Check(args) => cli::check::run_check(args).map(|()| ExitCode::SUCCESS),
        Commands::Render(args) => cli::render::run(args).map(|()| ExitCode::SUCCESS),
        Commands::Track(args) => cli::track::run_track(args).map(|()| ExitCode::SUCCESS),
        Commands::Target(args) => cli::target::run_target(args).map(|()| ExitCode::SUCCESS),
        Commands::Synth(args) => cli::synth::run_synth(args).map(|()| ExitCode::SUCCESS),
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

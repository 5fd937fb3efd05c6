//! `carfollow`: the car-following simulator's command line.
use clap::{Parser, Subcommand};
use std::process::ExitCode;

mod cli {
    pub mod render;
    pub mod synth;
    pub mod target;
    pub mod track;
}

#[derive(Parser)]
#[command(
    name = "carfollow",
    version,
    about = "Closed-loop car-following simulator"
)]
struct Cli {
    #[command(subcommand)]
    command: Commands,
}

#[derive(Subcommand)]
enum Commands {
    /// Render one camera frame at time T (built-in scene until scenario files exist).
    Render(cli::render::RenderArgs),
    /// Run the tracker on a folder of recorded frames.
    Track(cli::track::TrackArgs),
    /// Check a target model file and draw it.
    Target(cli::target::TargetArgs),
    /// Write a synthetic frame sequence of a target, with its ground truth.
    Synth(cli::synth::SynthArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Commands::Render(args) => cli::render::run(args),
        Commands::Track(args) => cli::track::run_track(args),
        Commands::Target(args) => cli::target::run_target(args),
        Commands::Synth(args) => cli::synth::run_synth(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::from(2)
        }
    }
}

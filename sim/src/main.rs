//! `carfollow`: the car-following simulator's command line.
use clap::{Parser, Subcommand};
use std::process::ExitCode;

mod cli {
    pub mod render;
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
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Commands::Render(args) => cli::render::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::from(2)
        }
    }
}

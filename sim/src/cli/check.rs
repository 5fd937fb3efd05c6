//! `carfollow check`: validate scenario files without running them.

use clap::Args;
use sim::scenario::Scenario;
use std::path::PathBuf;

/// Arguments of `carfollow check`.
#[derive(Args, Debug)]
#[command(after_help = super::exit::HELP, about = "Validate scenario files (and their target files) without running them")]
pub struct CheckArgs {
    /// Scenario files.
    #[arg(required = true)]
    pub scenarios: Vec<PathBuf>,
    /// Override a field by its dotted path, e.g. --set tracker.lambda=0.7 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// Runs the subcommand: every file is checked, every error printed (one line each).
pub fn run_check(args: CheckArgs) -> anyhow::Result<()> {
    let mut bad = 0;
    for path in &args.scenarios {
        match Scenario::load(path, &args.set) {
            Ok(s) => say!(
                "{}: ok: `{}`, {} s, seed {}, target `{}`",
                path.display(),
                s.name,
                s.duration_s,
                s.seed,
                s.target.name()
            ),
            Err(e) => {
                eprintln!("error: {e}");
                bad += 1;
            }
        }
    }
    if bad > 0 {
        anyhow::bail!(
            "{bad} of {} scenario files are invalid",
            args.scenarios.len()
        );
    }
    Ok(())
}

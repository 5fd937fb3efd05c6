//! `carfollow check`: validate scenario files without running them.

use clap::Args;
use sim_core::openscenario::OscError;
use sim_core::{Plan, Scenario, ScenarioError};
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `carfollow check`.
#[derive(Args, Debug)]
#[command(after_help = super::exit::HELP, about = "Validate scenario files (and their target files) without running them")]
pub struct CheckArgs {
    /// Scenario files (none: the built-in nist-grounds, which `run` runs without files).
    pub scenarios: Vec<PathBuf>,
    /// Override a field by its dotted path, e.g. --set tracker.lambda=0.7 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    #[command(flatten)]
    pub openscenario: super::import::OpenScenarioArgs,
}

/// Runs the subcommand: every file is checked, every error printed (one line each), and,
/// of several files, how many are invalid; exit status 2 when any is. Without files, the
/// built-in scenario with the overrides: what `run` would run. A file checks when its run
/// can be planned (see [`Plan`]): `run` plans it alike.
pub fn run_check(args: CheckArgs) -> anyhow::Result<ExitCode> {
    let ok = |what: &str, s: &Scenario| {
        for warning in s.warnings() {
            eprintln!("warning: {what}: {warning}");
        }
        say!(
            "{what}: ok: `{}`, {} s, seed {}, target `{}`",
            s.name,
            s.duration_s,
            s.seed,
            s.target.name()
        )
    };
    if args.scenarios.is_empty() {
        // One error, said once by `main` (exit 2), as `run` says it.
        let plan = Plan::builtin(&args.set)?;
        ok("the built-in scenario", plan.scenario());
        return Ok(ExitCode::SUCCESS);
    }
    let mut bad = 0;
    for path in &args.scenarios {
        match args.openscenario.plan(path, &args.set) {
            Ok(plan) => ok(&path.display().to_string(), plan.scenario()),
            // A `--set` that cannot apply is the command's error, not the file's: said once
            // (by `main`), with no count of invalid files.
            Err(e)
                if matches!(
                    e.downcast_ref(),
                    Some(
                        ScenarioError::Override { .. }
                            | ScenarioError::OpenScenario(OscError::Param { .. })
                    )
                ) =>
            {
                return Err(e)
            }
            Err(e) => {
                eprintln!("error: {}", super::exit::one_line(&e));
                if is_sweep_file(path) {
                    eprintln!(
                        "note: {} is a sweep file: check it, and every point of it, with \
                         `carfollow sweep {} --dry-run`",
                        path.display(),
                        path.display()
                    );
                }
                bad += 1;
            }
        }
    }
    let files = args.scenarios.len();
    match bad {
        0 => Ok(ExitCode::SUCCESS),
        // One file's error is said once, above.
        _ if files == 1 => Ok(ExitCode::from(super::exit::BAD_INPUT)),
        _ => anyhow::bail!("{bad} of {files} scenario files are invalid"),
    }
}

/// Whether `path` holds a sweep file (`scenarios` and `seeds` at the top level) rather than
/// a scenario.
fn is_sweep_file(path: &std::path::Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|text| text.parse::<toml::Table>().ok())
        .is_some_and(|t| t.contains_key("scenarios") && t.contains_key("seeds"))
}

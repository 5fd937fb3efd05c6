//! Exit statuses, the same for every subcommand, and how an error is said once.
//!
//! - 0: everything ran and passed;
//! - 1: a run completed but a criterion of its `[expect]` failed;
//! - 2: bad input (arguments, scenario, target or sweep files, `--set`), found before
//!   anything runs;
//! - 3: a run that could not complete (the renderer, a worker process, writing outputs), or
//!   a sweep with points missing.

use std::process::ExitCode;
use thiserror::Error;

/// Everything ran and passed.
pub const PASS: u8 = 0;
/// A run completed, and a criterion failed.
pub const FAILED: u8 = 1;
/// Bad input.
pub const BAD_INPUT: u8 = 2;
/// A run that could not complete.
pub const INCOMPLETE: u8 = 3;

/// The exit statuses as `--help` shows them.
pub const HELP: &str = "Exit status: 0 when everything ran and passed, 1 when a run completed \
                        but a criterion failed, 2 on bad input (found before anything runs), 3 \
                        when a run could not complete (renderer, worker, I/O) or a sweep has \
                        points missing.";

/// The exit statuses of `sweep`, whose points' failed criteria are results, not failures
/// of the sweep.
pub const SWEEP_HELP: &str = "Exit status: 0 when every point ran (whether or not its criteria \
                              passed: they are results of the sweep), 2 on bad input (found \
                              before anything runs), 3 when a point could not run or a merge \
                              has points missing.";

/// The exit statuses of the tools that run no scenario (`render`, `track`, `target`,
/// `synth`) as `--help` shows them.
pub const TOOL_HELP: &str = "Exit status: 0 when it ran, 2 on bad input (arguments, scenario, \
                             target or image files, found before anything is written or, for \
                             frames, as they are read, keeping what was written), 3 when an \
                             output could not be written.";

/// An error that stopped a run part-way (renderer, worker process, I/O): exit status 3,
/// where other errors are bad input (2).
#[derive(Debug, Error)]
#[error(transparent)]
pub struct Incomplete(#[from] pub anyhow::Error);

/// Wraps an error as [`Incomplete`].
pub fn incomplete(e: impl Into<anyhow::Error>) -> anyhow::Error {
    anyhow::Error::new(Incomplete(e.into()))
}

/// The exit code for an error.
pub fn code_of(error: &anyhow::Error) -> ExitCode {
    if error.downcast_ref::<Incomplete>().is_some() {
        ExitCode::from(INCOMPLETE)
    } else {
        ExitCode::from(BAD_INPUT)
    }
}

/// An error and its causes on one line, each said once: a cause whose text its error's
/// message already quotes (`cannot read: No such file (os error 2)`) is not repeated.
pub fn one_line(error: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in error.chain() {
        let text = cause.to_string();
        if text.is_empty() || line.contains(&text) {
            continue;
        }
        if !line.is_empty() {
            line.push_str(": ");
        }
        line.push_str(&text);
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;
    use anyhow::Context;

    #[test]
    fn a_cause_already_quoted_is_said_once() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let e = anyhow::Error::new(io).context("x.toml: cannot read scenario: no such file");
        assert_eq!(one_line(&e), "x.toml: cannot read scenario: no such file");
        let e: anyhow::Result<()> = Err(anyhow::anyhow!("inner")).context("outer");
        assert_eq!(one_line(&e.unwrap_err()), "outer: inner");
    }

    #[test]
    fn incomplete_runs_exit_3_and_bad_input_2() {
        let e = incomplete(anyhow::anyhow!("renderer lost"));
        assert_eq!(
            format!("{:?}", code_of(&e)),
            format!("{:?}", ExitCode::from(3))
        );
        assert_eq!(one_line(&e), "renderer lost");
        let e = anyhow::anyhow!("bad");
        assert_eq!(
            format!("{:?}", code_of(&e)),
            format!("{:?}", ExitCode::from(2))
        );
    }
}

//! A worker process spoken to over its stdin and stdout: the sweep's point workers and the
//! run's second renderer.

use std::io::BufReader;
use std::process::{ChildStdin, ChildStdout, Command, Stdio};

/// The environment variable that sets llvmpipe's rasteriser threads.
pub const RASTER_THREADS_ENV: &str = "LP_NUM_THREADS";

/// A running worker process. Dropping it closes its input, so it exits when its queue ends,
/// and waits for it.
pub struct Child {
    child: std::process::Child,
    stdin: Option<ChildStdin>,
    stdout: BufReader<ChildStdout>,
}

impl Child {
    /// Starts `command` with piped stdin and stdout (its stderr is ours). The worker
    /// renders on its own thread (`LP_NUM_THREADS=0`) unless our environment sets that:
    /// the parallelism is the workers', one per core.
    pub fn spawn(command: &mut Command) -> std::io::Result<Child> {
        if std::env::var_os(RASTER_THREADS_ENV).is_none() {
            command.env(RASTER_THREADS_ENV, "0");
        }
        let mut child = command
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()?;
        let (Some(stdin), Some(stdout)) = (child.stdin.take(), child.stdout.take()) else {
            let _ = child.kill();
            return Err(std::io::Error::other("the worker has no stdin or stdout"));
        };
        Ok(Child {
            child,
            stdin: Some(stdin),
            stdout: BufReader::new(stdout),
        })
    }

    /// Its input.
    pub fn stdin(&mut self) -> std::io::Result<&mut ChildStdin> {
        self.stdin
            .as_mut()
            .ok_or_else(|| std::io::Error::other("its input is closed"))
    }

    /// Its output.
    pub fn stdout(&mut self) -> &mut BufReader<ChildStdout> {
        &mut self.stdout
    }

    /// Closes its input and waits for it; returns how it ended.
    pub fn finish(mut self) -> String {
        self.close_and_wait()
    }

    fn close_and_wait(&mut self) -> String {
        drop(self.stdin.take());
        match self.child.wait() {
            Ok(status) => status.to_string(),
            Err(e) => e.to_string(),
        }
    }
}

impl Drop for Child {
    fn drop(&mut self) {
        self.close_and_wait();
    }
}

//! Why a run could not start or go on.

use crate::plugin::PluginError;
use sim_render::RenderError;
use thiserror::Error;

/// A run that could not start or go on.
#[derive(Debug, Error)]
pub enum LoopError {
    /// The scenario cannot be set up (vehicles, route, tracker).
    #[error("scenario `{scenario}`: {message}")]
    Setup {
        /// Scenario name.
        scenario: String,
        /// What is wrong.
        message: String,
    },
    /// The renderer failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The second renderer (a thread with a llvmpipe of its own, or a worker process)
    /// failed.
    #[error("the second renderer: {0}")]
    Worker(String),
    /// A plug-in tracker or controller failed, which ends the run.
    #[error("the {what}{}: {error}", at(*frame, *t_s))]
    Plugin {
        /// `tracker` or `controller`.
        what: &'static str,
        /// The camera frame it failed at (`None` before the first).
        frame: Option<u64>,
        /// The time it failed at, seconds.
        t_s: Option<f64>,
        /// What it said.
        error: PluginError,
    },
}

/// A plug-in's failure placed at frame `frame`, when it has no place yet.
pub(super) fn at_frame(e: LoopError, frame: u64) -> LoopError {
    match e {
        LoopError::Plugin {
            what,
            frame: None,
            error,
            ..
        } => LoopError::Plugin {
            what,
            frame: Some(frame),
            t_s: Some(frame as f64 / f64::from(vehicle::CAMERA_HZ)),
            error,
        },
        other => other,
    }
}

/// " at frame k (t = s s)", or " before the first frame".
fn at(frame: Option<u64>, t_s: Option<f64>) -> String {
    match (frame, t_s) {
        (Some(k), Some(t)) => format!(" failed at frame {k} (t = {t:.3} s)"),
        (Some(k), None) => format!(" failed at frame {k}"),
        _ => " failed before the first frame".into(),
    }
}

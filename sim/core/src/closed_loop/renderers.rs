//! The loop's renderers: this process's own, and, for speed, a second one that renders
//! frame k + 1 while frame k finishes: a thread of this process with a llvmpipe of its own
//! (on the GL backend), or else a worker process (`carfollow render-worker`). Results are
//! the same bit for bit with one renderer or two.

use super::error::LoopError;
use super::ClosedLoop;
use crate::closed_loop::capture::renders_ahead;
use crate::plan::Plan;
use crate::plugin::{ControllerChoice, TrackerChoice};
use crate::render_worker::{RemoteRenderer, StartedWorker};
use sim_render::Backend;

/// How a closed loop renders, for [`ClosedLoop::start`].
#[derive(Debug)]
pub struct LoopOptions {
    /// The graphics backend.
    pub backend: Backend,
    /// Camera frames rendered at once: 1, or 2 (the second renderer renders frame k + 1
    /// while frame k finishes; only where the scenario's latency lets the loop run ahead).
    pub renderers: u8,
    /// Each frame's output carries its edge points' fates (the overlay, recordings).
    pub diagnostics: bool,
    /// Render every frame whole (for whoever looks at the images: the video, recordings),
    /// not only the part the tracker reads (see [`ClosedLoop::set_whole_frames`]).
    pub whole_frames: bool,
    /// How to start a render worker process (`carfollow render-worker`, which is sent the
    /// plan's scene) where the second renderer cannot be a thread of this process;
    /// `None` renders one frame at a time there instead.
    pub worker_process: Option<std::process::Command>,
    /// The tracker: the built-in, as the scenario sets it up, or a plug-in.
    pub tracker: TrackerChoice,
    /// The controller: the built-in, as the scenario sets it up, or a plug-in.
    pub controller: ControllerChoice,
}

impl LoopOptions {
    /// One renderer on `backend`, only the part of each frame the tracker reads, no
    /// diagnostics.
    pub fn new(backend: Backend) -> LoopOptions {
        LoopOptions {
            backend,
            renderers: 1,
            diagnostics: false,
            whole_frames: false,
            worker_process: None,
            tracker: TrackerChoice::Builtin,
            controller: ControllerChoice::Builtin,
        }
    }
}

impl ClosedLoop {
    /// The loop of `plan` with its renderers as `options` asks. The second renderer starts
    /// first, so that it sets up while this process's does: on a thread of this process
    /// with a llvmpipe of its own (Mesa's software EGL device), or, where that cannot be
    /// had (another backend, no such device), in a worker process. A second renderer that
    /// cannot be had is not an error: the loop renders one frame at a time and says why
    /// in [`ClosedLoop::notes`].
    pub fn start(plan: Plan, options: LoopOptions) -> Result<ClosedLoop, LoopError> {
        let LoopOptions {
            backend,
            renderers,
            diagnostics,
            whole_frames,
            mut worker_process,
            tracker,
            controller,
        } = options;
        // Two plug-ins may share state: then nothing overlaps (see `ClosedLoop::with`).
        let both = matches!(tracker, TrackerChoice::Plugin(_))
            && matches!(controller, ControllerChoice::Plugin(_));
        let two = renderers >= 2 && !both && renders_ahead(&plan.delay);
        let on_thread = backend == Backend::Gl;
        let second = match (two, on_thread, &worker_process) {
            (false, _, _) => None,
            (true, true, _) => Some(RemoteRenderer::spawn_thread(
                plan.scene.clone(),
                plan.rig.clone(),
                backend,
            )),
            (true, false, Some(_)) => worker_process
                .take()
                .map(|command| RemoteRenderer::spawn(command, &plan.scene, &plan.rig)),
            (true, false, None) => Some(Err(format!(
                "no render worker process to start on {backend}"
            ))),
        };
        let mut looped = ClosedLoop::with(plan, backend, diagnostics, tracker, controller)?;
        looped.set_whole_frames(whole_frames);
        if let Some(second) = second {
            let mut added = second
                .map_err(LoopError::Worker)
                .and_then(|w| looped.add_started_render_worker(w));
            if on_thread && added.is_err() {
                // No second llvmpipe here: a worker process instead, when there is one.
                if let Some(command) = worker_process {
                    added = looped.add_render_worker(command);
                }
            }
            if let Err(e) = added {
                looped
                    .notes
                    .push(format!("{e}; rendering one frame at a time"));
            }
        }
        Ok(looped)
    }

    /// Starts a second renderer in a worker process (`command`: `carfollow render-worker`,
    /// which is sent this loop's scene), so that two camera frames render at once: frame
    /// k + 1 in one renderer while frame k finishes in the other. Results are identical to
    /// one renderer's (the worker's scene has this one's fingerprint), so this
    /// only changes the speed. Possible only when the loop can overlap at all (see
    /// [`ClosedLoop::set_pipelined`]) and before the first step; returns whether two frames
    /// are now in flight.
    pub fn add_render_worker(&mut self, command: std::process::Command) -> Result<bool, LoopError> {
        if !self.schedule.pipelined || self.frame > 0 {
            return Ok(false);
        }
        let started = RemoteRenderer::spawn(command, &self.recorder.scene, &self.eye.rig)
            .map_err(LoopError::Worker)?;
        self.add_started_render_worker(started)
    }

    /// [`ClosedLoop::add_render_worker`] with a worker already started (before this loop
    /// set up, so that both set up at once: see [`ClosedLoop::renders_ahead`]). A worker
    /// this loop cannot use is dropped, which ends it.
    ///
    /// The first frame starts rendering on this process's render thread before the worker
    /// is waited for, so that it renders (its shaders compiling, its first shadow tiles
    /// drawing) while the worker finishes setting up. Should the worker fail, the loop
    /// takes its renderer back and renders that frame again on one renderer's path: a
    /// capture changes nothing, and a frame's pixels never depend on what its renderer drew
    /// before.
    pub fn add_started_render_worker(&mut self, worker: StartedWorker) -> Result<bool, LoopError> {
        self.schedule
            .add_second(worker, &self.drive, &self.eye, self.frame)
    }

    /// Renders this loop's frames on a renderer of Mesa's software EGL device (a llvmpipe
    /// of its own, on a thread of its own) in place of this process's renderer, which
    /// renders on wgpu's display: llvmpipe renders the frames of one display one at a time,
    /// so loops of one process that split between the two render two frames at once. The
    /// frames are the same bit for bit. Only for a loop on GL (`backend`, the one it
    /// started on), before the first step, and with one frame in flight; returns whether it
    /// now does, or why it cannot.
    pub fn render_on_software_device(&mut self, backend: Backend) -> Result<bool, LoopError> {
        let s = &mut self.schedule;
        let busy = s.remote.is_some() || s.solo.is_some() || !s.in_flight.is_empty();
        if backend != Backend::Gl || self.frame > 0 || busy {
            return Ok(false);
        }
        let scene = self.recorder.scene.clone();
        let started = RemoteRenderer::spawn_thread(scene, self.eye.rig.clone(), backend)
            .map_err(LoopError::Worker)?;
        let solo = started
            .ready(s.fingerprint, &s.adapter_name, &self.eye.rig)
            .map_err(LoopError::Worker)?;
        s.solo = Some(solo);
        Ok(true)
    }
}

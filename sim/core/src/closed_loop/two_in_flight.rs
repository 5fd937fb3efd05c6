//! Two frames in flight: even frames render on this process's render thread, odd ones in
//! the second renderer, and each renderer starts its next frame as soon as that frame can
//! be captured (see [`ClosedLoop::add_render_worker`]).

use super::capture::{timed, Captured, InFlight, HERE};
use super::drive::Driven;
use super::tracking::{TrackFailure, Tracked};
use super::{ClosedLoop, LoopError};
use crate::render_thread::RenderThread;
use sim_render::{Frame, RenderError};
use std::time::Duration;

impl ClosedLoop {
    /// Starts rendering the frame of the world as it is now: even frames on this process's
    /// render thread, odd ones in the render worker, both in the background.
    pub(super) fn submit(&mut self) -> Result<InFlight, LoopError> {
        let captured = self.capture();
        let needed = self.parts.needed(
            captured.input.frame_index,
            &captured.world_from_camera.rotation,
        );
        let here = captured.input.frame_index.is_multiple_of(2);
        if here {
            let thread = match &mut self.render_thread {
                Some(thread) => thread,
                None => self
                    .render_thread
                    .insert(RenderThread::start().map_err(|e| {
                        LoopError::Worker(format!("cannot start the render thread: {e}"))
                    })?),
            };
            let renderer = self.renderer.take().expect(HERE);
            thread.render(renderer, captured.input.clone(), needed);
        } else {
            let remote = self.remote.as_mut().expect("two frames in flight");
            remote
                .submit(&captured.input, needed)
                .map_err(LoopError::Worker)?;
        }
        Ok(InFlight { captured, here })
    }

    /// One frame with two in flight (see [`ClosedLoop::add_render_worker`]). Frames
    /// alternate: even ones render on this process's render thread, odd ones in the worker,
    /// and each renderer starts its next frame as soon as that frame can be captured:
    /// - frame k is tracked (waiting for its render first), then, when frame k + 1 is still
    ///   to come, the physics to k + 2 runs (it needs estimates up to frame k alone: see
    ///   `set_pipelined`) and frame k + 2 goes to frame k's renderer, all before this step
    ///   returns frame k's outputs;
    /// - frame k's renderer is the worker: the physics to k + 2's steps before the estimate
    ///   of frame k can fall due run while frame k comes back, and after frame k + 2 is
    ///   submitted, those of the physics to k + 3 before frame k + 1's estimate can.
    ///
    /// With diagnostics on (a recording reads the chase controller after each frame) nothing
    /// runs ahead: the physics to k + 1 runs in step k, and frame k + 1 goes to its renderer
    /// then, before frame k is tracked.
    ///
    /// Should frame k's tracking need more of the frame, its own renderer renders it (the
    /// worker, or this process's, which is back from its thread by then). Each frame is
    /// metered for the automatic gain control as soon as it is tracked, before any later
    /// frame is captured. The order of all this is one renderer's, so the results are too.
    pub(super) fn step_two_in_flight(
        &mut self,
        spent: &mut [Duration; 3],
    ) -> Result<(Captured, Frame, Tracked, Driven), LoopError> {
        let [render_t, track_t, physics_t] = spent;
        if self.in_flight.is_empty() {
            let first = self.submit()?;
            self.in_flight.push_back(first);
        }
        let pending = self.in_flight.pop_front().expect("a frame in flight");
        let k = pending.captured.input.frame_index;
        let more = k + 1 < self.frames;
        // The physics runs ahead of the outputs (not with diagnostics: the recording takes
        // the chase controller as it stands after each frame).
        let ahead = more && !self.diagnostics;
        let t_s = pending.captured.input.time_s;
        let ego = self.ego_motion(&pending.captured);
        let (diagnostics, pan) = (self.diagnostics, pending.captured.pan_reading_rad);
        let input = &pending.captured.input;
        let driven = match self.advanced.take() {
            Some(advanced) => advanced,
            None => timed(physics_t, || self.drive.advance_frame()),
        };
        if more && self.in_flight.is_empty() {
            // Nothing ran ahead (diagnostics, or the first frame): frame k + 1 now.
            let next = self.submit()?;
            self.in_flight.push_back(next);
        }
        let (frame, (tracked, again)) = if pending.here {
            let thread = self
                .render_thread
                .as_mut()
                .expect("a frame on the render thread");
            let rendered = thread.wait();
            *render_t += rendered.spent;
            let renderer = self.renderer.insert(rendered.renderer);
            let mut frame = rendered.frame?;
            let render = |part| renderer.render_part(input, part);
            let seen = timed(track_t, || {
                self.tracking
                    .track::<RenderError>(&mut frame, render, t_s, ego, diagnostics, pan)
            })?;
            (frame, seen)
        } else {
            if ahead {
                let due = self.drive.earliest_due(k);
                timed(physics_t, || self.drive.advance_before(due));
            }
            let remote = self.remote.as_mut().expect("two frames in flight");
            let mut frame = timed(render_t, || remote.receive()).map_err(LoopError::Worker)?;
            let render = |part| {
                remote.submit(input, part)?;
                remote.receive()
            };
            let seen = timed(track_t, || {
                self.tracking
                    .track::<String>(&mut frame, render, t_s, ego, diagnostics, pan)
            })
            .map_err(|f| match f {
                TrackFailure::Render(e) => LoopError::Worker(e),
                TrackFailure::Plugin(e) => LoopError::from(TrackFailure::<RenderError>::Plugin(e)),
            })?;
            (frame, seen)
        };
        self.tracked(&pending.captured, &tracked, again);
        self.auto_gain.observe(k, input.auto_gain, &frame.image);
        if ahead {
            // The physics to k + 2, and frame k + 2 to the renderer frame k came from.
            let advanced = timed(physics_t, || self.drive.advance_frame());
            self.advanced = Some(advanced);
            if k + 2 < self.frames {
                let next = self.submit()?;
                self.in_flight.push_back(next);
                if !pending.here {
                    // The physics to k + 3 needs frame k + 1 tracked only from the step its
                    // estimate can fall due: the steps before run now, while frame k + 1
                    // finishes rendering here.
                    let due = self.drive.earliest_due(k + 1);
                    timed(physics_t, || self.drive.advance_before(due));
                }
            }
        }
        Ok((pending.captured, frame, tracked, driven))
    }
}

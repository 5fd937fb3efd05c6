//! Two frames in flight: even frames render on this process's render thread, odd ones in
//! the second renderer, and each renderer starts its next frame as soon as that frame can
//! be captured (see `ClosedLoop::add_render_worker`).

use super::capture::{timed, InFlight};
use super::drive::Drive;
use super::error::LoopError;
use super::eye::Eye;
use super::schedule::{Schedule, Shot, Spent};

impl Schedule {
    /// Starts rendering the frame of the world as it is now: even frames on this process's
    /// render thread, odd ones in the second renderer, both in the background.
    pub(super) fn submit(&mut self, drive: &Drive, eye: &Eye) -> Result<InFlight, LoopError> {
        let captured = eye.capture(drive);
        let part = eye.needed_ahead(&captured);
        let here = captured.input.frame_index.is_multiple_of(2);
        if here {
            self.render_here(&captured, part)?;
        } else {
            let remote = self.remote.as_mut().expect("two frames in flight");
            remote
                .submit(&captured.input, part)
                .map_err(LoopError::Worker)?;
        }
        Ok(InFlight { captured, here })
    }

    /// One frame with two in flight. Frames alternate: even ones render on this process's
    /// render thread, odd ones in the second renderer, and each renderer starts its next
    /// frame as soon as that frame can be captured:
    /// - frame k is tracked (waiting for its render first), then, when frame k + 1 is still
    ///   to come, the physics to k + 2 runs (it needs estimates up to frame k alone: see
    ///   `ClosedLoop::set_pipelined`) and frame k + 2 goes to frame k's renderer, all before
    ///   this step returns frame k's outputs;
    /// - frame k's renderer is the second: the physics to k + 2's steps before the
    ///   estimate of frame k can fall due run while frame k comes back, and after frame
    ///   k + 2 is submitted, those of the physics to k + 3 before frame k + 1's estimate can.
    ///
    /// With diagnostics on (a recording reads the chase controller after each frame) nothing
    /// runs ahead: the physics to k + 1 runs in step k, and frame k + 1 goes to its renderer
    /// then, before frame k is tracked.
    ///
    /// Should frame k's tracking need more of the frame, its own renderer renders it (the
    /// second, or this process's, which is back from its thread by then). Each frame is
    /// metered for the automatic gain control as soon as it is tracked, before any later
    /// frame is captured. The order of all this is one renderer's, so the results are too.
    pub(super) fn two_in_flight(
        &mut self,
        drive: &mut Drive,
        eye: &mut Eye,
        spent: &mut Spent,
    ) -> Result<Shot, LoopError> {
        let [render_t, track_t, physics_t] = spent;
        if self.in_flight.is_empty() {
            let first = self.submit(drive, eye)?;
            self.in_flight.push_back(first);
        }
        let pending = self.in_flight.pop_front().expect("a frame in flight");
        let (captured, here) = (pending.captured, pending.here);
        let k = captured.input.frame_index;
        let more = k + 1 < self.frames;
        // The physics runs ahead of the outputs (not with diagnostics: the recording takes
        // the chase controller as it stands after each frame).
        let ahead = more && !eye.diagnostics;
        let driven = match self.advanced.take() {
            Some(advanced) => advanced,
            None => timed(physics_t, || drive.advance_frame()),
        };
        if more && self.in_flight.is_empty() {
            // Nothing ran ahead (diagnostics, or the first frame): frame k + 1 now.
            let next = self.submit(drive, eye)?;
            self.in_flight.push_back(next);
        }
        let input = &captured.input;
        let (frame, tracked) = if here {
            let thread = self
                .render_thread
                .as_mut()
                .expect("a frame on the render thread");
            let rendered = thread.wait();
            *render_t += rendered.spent;
            let renderer = self.renderer.insert(rendered.renderer);
            let render = |part| renderer.render_part(input, part);
            eye.see(&captured, rendered.frame, render, track_t)?
        } else {
            if ahead {
                let due = drive.earliest_due(k);
                timed(physics_t, || drive.advance_before(due));
            }
            let remote = self.remote.as_mut().expect("two frames in flight");
            let rendered = timed(render_t, || remote.receive()).map_err(LoopError::Worker);
            let render = |part| {
                remote
                    .submit(input, part)
                    .and_then(|()| remote.receive())
                    .map_err(LoopError::Worker)
            };
            eye.see(&captured, rendered, render, track_t)?
        };
        eye.deliver(drive, &captured, &tracked);
        eye.meter(&captured, &frame);
        if ahead {
            // The physics to k + 2, and frame k + 2 to the renderer frame k came from.
            let advanced = timed(physics_t, || drive.advance_frame());
            self.advanced = Some(advanced);
            if k + 2 < self.frames {
                let next = self.submit(drive, eye)?;
                self.in_flight.push_back(next);
                if !here {
                    // The physics to k + 3 needs frame k + 1 tracked only from the step its
                    // estimate can fall due: the steps before run now, while frame k + 1
                    // finishes rendering here.
                    let due = drive.earliest_due(k + 1);
                    timed(physics_t, || drive.advance_before(due));
                }
            }
        }
        Ok(Shot {
            captured,
            frame,
            tracked,
            driven,
        })
    }
}

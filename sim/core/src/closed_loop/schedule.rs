//! How the loop's frames are scheduled: the renderers and the frames in flight.
//!
//! For its results a frame is always the same five steps in the same order: capture (1),
//! render (2), track (3), delay (4) and drive (5); [`Schedule::one_after_another`] runs
//! them just so. The schedule only chooses what runs beside what:
//! - one after another, on this thread;
//! - pipelined: 5 on a second thread while 2 and 3 run here, possible because no estimate
//!   reaches the controller sooner than a frame after its capture (see
//!   `ClosedLoop::set_pipelined`);
//! - prefetched: 2 started on this process's render thread before the step that takes it,
//!   so that it renders while the caller does something else;
//! - two in flight (`two_in_flight`): frame k + 1 renders in a second renderer while frame
//!   k renders and is tracked in this one.
//!
//! Every one gives the same results, bit for bit.

use super::capture::{timed, Captured, InFlight, HERE};
use super::drive::{Drive, Driven};
use super::error::LoopError;
use super::eye::Eye;
use super::tracking::Tracked;
use crate::render_thread::RenderThread;
use crate::render_worker::{RemoteRenderer, StartedWorker};
use sim_render::{Frame, Renderer};
use std::collections::VecDeque;
use std::time::Duration;

/// One frame as the schedule ran it.
pub(super) struct Shot {
    pub(super) captured: Captured,
    pub(super) frame: Frame,
    pub(super) tracked: Tracked,
    pub(super) driven: Driven,
}

/// Where each step's wall-clock time went: rendering, tracking, physics.
pub(super) type Spent = [Duration; 3];

/// The renderers and the frames in flight.
pub(super) struct Schedule {
    /// The scenario's frames.
    pub(super) frames: u64,
    /// Whether the physics to the next frame runs on a second thread while this frame is
    /// rendered and tracked (see [`Schedule::set_pipelined`]).
    pub(super) pipelined: bool,
    /// Whether it may: anything may run beside the tracker (not with two plug-ins, which
    /// may share state), and the delay line lets the physics run ahead.
    pub(super) can_overlap: bool,
    /// This process's renderer: `None` while it renders a frame on `render_thread`.
    pub(super) renderer: Option<Box<Renderer>>,
    /// The renderer's adapter.
    pub(super) adapter_name: String,
    /// The scene's fingerprint, which a second renderer must match.
    pub(super) fingerprint: u64,
    /// The thread this process's frames render on when they render in the background.
    pub(super) render_thread: Option<RenderThread>,
    /// The second renderer, when two frames are in flight.
    pub(super) remote: Option<RemoteRenderer>,
    /// The renderer every frame renders on in place of `renderer`, when it is one of Mesa's
    /// software EGL device on a thread of its own (see
    /// `ClosedLoop::render_on_software_device`).
    pub(super) solo: Option<RemoteRenderer>,
    /// Frames submitted and not yet tracked, in order.
    pub(super) in_flight: VecDeque<InFlight>,
    /// What the physics to the frame after the first in flight left, when an earlier step
    /// has run it already (two in flight).
    pub(super) advanced: Option<Driven>,
}

impl Schedule {
    /// Runs the next frame: 1 to 5, in the order this schedule keeps.
    pub(super) fn run(
        &mut self,
        drive: &mut Drive,
        eye: &mut Eye,
        spent: &mut Spent,
    ) -> Result<Shot, LoopError> {
        if self.solo.is_some() {
            self.on_solo(drive, eye, spent)
        } else if self.remote.is_some() {
            self.two_in_flight(drive, eye, spent)
        } else if !self.in_flight.is_empty() {
            self.prefetched(drive, eye, spent)
        } else if self.pipelined {
            self.pipelined(drive, eye, spent)
        } else {
            self.one_after_another(drive, eye, spent)
        }
    }

    /// The frame, one thing at a time.
    fn one_after_another(
        &mut self,
        drive: &mut Drive,
        eye: &mut Eye,
        spent: &mut Spent,
    ) -> Result<Shot, LoopError> {
        let [render_t, track_t, physics_t] = spent;
        // 1. The capture: the world now, and the camera's input for it.
        let captured = eye.capture(drive);
        // 2. The render, of the part of the frame the tracker will read.
        let part = eye.needed(&captured);
        let renderer = self.renderer.as_deref_mut().expect(HERE);
        let input = &captured.input;
        let rendered = timed(render_t, || renderer.render_part(input, part));
        // 3. The tracker, on the image alone (rendering more, should it read beyond).
        let render = |part| renderer.render_part(input, part);
        let (frame, tracked) = eye.see(&captured, rendered, render, track_t)?;
        // 4. The estimate into the delay line.
        eye.deliver(drive, &captured, &tracked);
        // 5. The controllers and the physics, to the next frame.
        let driven = timed(physics_t, || drive.advance_frame());
        eye.meter(&captured, &frame);
        Ok(Shot {
            captured,
            frame,
            tracked,
            driven,
        })
    }

    /// The frame with 5 on a second thread while 2 and 3 run on this one: 5 needs no
    /// estimate from this frame (see [`Schedule::set_pipelined`]); 4 waits for both.
    fn pipelined(
        &mut self,
        drive: &mut Drive,
        eye: &mut Eye,
        spent: &mut Spent,
    ) -> Result<Shot, LoopError> {
        let [render_t, track_t, physics_t] = spent;
        let captured = eye.capture(drive);
        let part = eye.needed(&captured);
        let renderer = self.renderer.as_deref_mut().expect(HERE);
        let input = &captured.input;
        let (seen, driven) = std::thread::scope(|scope| {
            let physics = scope.spawn(|| timed(physics_t, || drive.advance_frame()));
            let rendered = timed(render_t, || renderer.render_part(input, part));
            let render = |part| renderer.render_part(input, part);
            let seen = eye.see(&captured, rendered, render, track_t);
            (seen, joined(physics))
        });
        let (frame, tracked) = seen?;
        eye.deliver(drive, &captured, &tracked);
        eye.meter(&captured, &frame);
        Ok(Shot {
            captured,
            frame,
            tracked,
            driven,
        })
    }

    /// Starts rendering the next frame (`frame`) now, on this process's render thread; the
    /// next step takes it (see `ClosedLoop::prefetch`).
    pub(super) fn prefetch(
        &mut self,
        drive: &Drive,
        eye: &Eye,
        frame: u64,
    ) -> Result<(), LoopError> {
        if self.remote.is_some() || frame >= self.frames || !self.in_flight.is_empty() {
            return Ok(());
        }
        let captured = eye.capture(drive);
        let part = eye.needed(&captured);
        let here = match self.solo.as_mut() {
            Some(solo) => {
                solo.submit(&captured.input, part)
                    .map_err(LoopError::Worker)?;
                false
            }
            None => {
                self.render_here(&captured, part)?;
                true
            }
        };
        self.in_flight.push_back(InFlight { captured, here });
        Ok(())
    }

    /// The frame on the software device's renderer (`solo`), one thing at a time, the
    /// render started by [`Schedule::prefetch`] when it was.
    fn on_solo(
        &mut self,
        drive: &mut Drive,
        eye: &mut Eye,
        spent: &mut Spent,
    ) -> Result<Shot, LoopError> {
        let [render_t, track_t, physics_t] = spent;
        let solo = self.solo.as_mut().expect("a software device's renderer");
        let captured = match self.in_flight.pop_front() {
            Some(prefetched) => prefetched.captured,
            None => {
                let captured = eye.capture(drive);
                let part = eye.needed(&captured);
                solo.submit(&captured.input, part)
                    .map_err(LoopError::Worker)?;
                captured
            }
        };
        let input = &captured.input;
        let rendered = timed(render_t, || solo.receive()).map_err(LoopError::Worker);
        let render = |part| {
            solo.submit(input, part)
                .and_then(|()| solo.receive())
                .map_err(LoopError::Worker)
        };
        let (frame, tracked) = eye.see(&captured, rendered, render, track_t)?;
        eye.deliver(drive, &captured, &tracked);
        let driven = timed(physics_t, || drive.advance_frame());
        eye.meter(&captured, &frame);
        Ok(Shot {
            captured,
            frame,
            tracked,
            driven,
        })
    }

    /// A frame [`Schedule::prefetch`] started: waits for it and tracks it while the
    /// physics runs to the next frame (pipelined) or after (not).
    fn prefetched(
        &mut self,
        drive: &mut Drive,
        eye: &mut Eye,
        spent: &mut Spent,
    ) -> Result<Shot, LoopError> {
        let captured = self
            .in_flight
            .pop_front()
            .expect("a prefetched frame")
            .captured;
        let pipelined = self.pipelined;
        let thread = self.render_thread.as_mut().expect("the prefetch's thread");
        let renderer_slot = &mut self.renderer;
        let [render_t, track_t, physics_t] = spent;
        let input = &captured.input;
        let mut driven = None;
        let seen = std::thread::scope(|scope| {
            let physics =
                pipelined.then(|| scope.spawn(|| timed(physics_t, || drive.advance_frame())));
            let rendered = thread.wait();
            *render_t += rendered.spent;
            let renderer = renderer_slot.insert(rendered.renderer);
            let render = |part| renderer.render_part(input, part);
            let seen = eye.see(&captured, rendered.frame, render, track_t);
            driven = physics.map(joined);
            seen
        });
        let (frame, tracked) = seen?;
        eye.deliver(drive, &captured, &tracked);
        let driven = match driven {
            Some(driven) => driven,
            None => timed(physics_t, || drive.advance_frame()),
        };
        eye.meter(&captured, &frame);
        Ok(Shot {
            captured,
            frame,
            tracked,
            driven,
        })
    }

    /// Renders the frame of `captured` (`part` of it) on this process's render thread, in
    /// the background, starting the thread the first time.
    pub(super) fn render_here(
        &mut self,
        captured: &Captured,
        part: Option<tracker::PixelRect>,
    ) -> Result<(), LoopError> {
        if self.render_thread.is_none() {
            let thread = RenderThread::start()
                .map_err(|e| LoopError::Worker(format!("cannot start the render thread: {e}")))?;
            self.render_thread = Some(thread);
        }
        let renderer = self.renderer.take().expect(HERE);
        let thread = self.render_thread.as_mut().expect("started");
        thread.render(renderer, captured.input.clone(), part);
        Ok(())
    }

    /// Asks for the physics to the next frame to run beside each frame's rendering and
    /// tracking, or not; see `ClosedLoop::set_pipelined`. Returns whether it now does.
    pub(super) fn set_pipelined(&mut self, on: bool) -> bool {
        if !on && self.remote.is_some() {
            self.take_back_first_frame();
            if !self.in_flight.is_empty() {
                // A frame is rendering in the second renderer: too late to change.
                return self.pipelined;
            }
            // Two frames in flight overlap by nature.
            self.remote = None;
        }
        self.pipelined = on && self.can_overlap;
        self.pipelined
    }

    /// Takes a second renderer already started, when the loop can use it (pipelined, and
    /// before frame `frame` = 0 has run): see `ClosedLoop::add_started_render_worker`.
    pub(super) fn add_second(
        &mut self,
        worker: StartedWorker,
        drive: &Drive,
        eye: &Eye,
        frame: u64,
    ) -> Result<bool, LoopError> {
        if !self.pipelined || frame > 0 {
            return Ok(false);
        }
        if self.in_flight.is_empty() {
            let first = self.submit(drive, eye)?;
            self.in_flight.push_back(first);
        }
        match worker.ready(self.fingerprint, &self.adapter_name, &eye.rig) {
            Ok(remote) => {
                self.remote = Some(remote);
                Ok(true)
            }
            Err(e) => {
                self.take_back_first_frame();
                Err(LoopError::Worker(e))
            }
        }
    }

    /// Before the first step: drops the first frame from the render thread, if it is on
    /// it, and takes its renderer back, for one renderer's path to render it again.
    fn take_back_first_frame(&mut self) {
        let first = |f: &InFlight| f.here && f.captured.input.frame_index == 0;
        if self.in_flight.len() == 1 && first(&self.in_flight[0]) {
            self.in_flight.clear();
            let thread = self
                .render_thread
                .as_mut()
                .expect("the first frame's thread");
            self.renderer = Some(thread.wait().renderer);
        }
    }

    /// How many camera frames render at once: 2 with a second renderer, else 1.
    pub(super) fn frames_in_flight(&self) -> usize {
        if self.remote.is_some() {
            2
        } else {
            1
        }
    }
}

/// The physics thread's result, its panic passed on.
fn joined(physics: std::thread::ScopedJoinHandle<'_, Driven>) -> Driven {
    match physics.join() {
        Ok(driven) => driven,
        Err(panic) => std::panic::resume_unwind(panic),
    }
}

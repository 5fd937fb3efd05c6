//! One camera frame of the loop: the camera renders, the tracker tracks, the estimate goes
//! into the delay line, and the controllers and the physics run to the next frame; on one
//! thread, or with the physics on a second while this one renders and tracks (pipelined),
//! or with two frames in flight (see `two_in_flight`).

use super::capture::{timed, Captured, InFlight, HERE};
use super::drive::Driven;
use super::tracking::{TrackFailure, Tracked, Tracking};
use super::{ClosedLoop, FrameOutput, FramePoses, LoopError};
use crate::render_thread::RenderThread;
use sim_render::{Frame, RenderError, Renderer};
use std::time::{Duration, Instant};
use tracker::EgoMotion;

impl<E: Into<LoopError>> From<TrackFailure<E>> for LoopError {
    fn from(f: TrackFailure<E>) -> LoopError {
        match f {
            TrackFailure::Render(e) => e.into(),
            TrackFailure::Plugin(e) => LoopError::Plugin {
                what: "tracker",
                frame: None,
                t_s: None,
                error: e,
            },
        }
    }
}

impl ClosedLoop {
    /// Runs one camera frame and the physics up to the next one. `None` when the scenario's
    /// duration is over.
    pub fn step(&mut self) -> Result<Option<FrameOutput>, LoopError> {
        if self.frame >= self.frames {
            return Ok(None);
        }
        let step_started = Instant::now();
        let mut spent = [Duration::ZERO; 3];
        // 1. The camera; 2. the tracker, on the image only; 3. the delay line; 4. the
        // controllers and the physics to the next frame.
        let stepped = if self.remote.is_some() {
            self.step_two_in_flight(&mut spent)
        } else if !self.in_flight.is_empty() {
            self.step_prefetched(&mut spent)
        } else if self.pipelined {
            self.step_pipelined(&mut spent)
        } else {
            self.step_sequential(&mut spent)
        };
        let (captured, frame, tracked, driven) = stepped.map_err(|e| self.at_frame(e))?;
        if let Some((step, error)) = self.drive.take_failure() {
            // The frame whose physics the step belongs to (it may run ahead of this one).
            return Err(LoopError::Plugin {
                what: "controller",
                frame: Some(step.0 / u64::from(vehicle::STEPS_PER_FRAME)),
                t_s: Some(step.seconds()),
                error,
            });
        }
        debug_assert_eq!(captured.input.frame_index, self.frame);
        if self.remote.is_none() {
            // (With two in flight the step has metered the frame already.)
            self.auto_gain
                .observe(self.frame, captured.input.auto_gain, &frame.image);
        }
        let record = self.record(&captured, &frame, &tracked, driven);
        let poses = FramePoses {
            world_from_chase: captured.input.world_from_chase,
            world_from_lead: captured.input.world_from_lead,
            world_from_camera: captured.world_from_camera,
        };
        self.frame += 1;
        let [render_t, track_t, physics_t] = spent;
        self.timing.frames += 1;
        self.timing.render_s += render_t.as_secs_f64();
        self.timing.track_s += track_t.as_secs_f64();
        self.timing.physics_s += physics_t.as_secs_f64();
        self.timing.step_s += step_started.elapsed().as_secs_f64();
        Ok(Some(FrameOutput {
            record,
            image: frame.image,
            estimate: tracked.estimate,
            track: tracked.out,
            edges: tracked.edges,
            poses,
            ego: self.last_ego,
        }))
    }

    /// A plug-in's failure placed at this frame.
    fn at_frame(&self, e: LoopError) -> LoopError {
        match e {
            LoopError::Plugin {
                what,
                frame: None,
                error,
                ..
            } => LoopError::Plugin {
                what,
                frame: Some(self.frame),
                t_s: Some(self.frame as f64 / f64::from(vehicle::CAMERA_HZ)),
                error,
            },
            other => other,
        }
    }

    /// 4 needs no estimate from this frame (see `set_pipelined`), so it runs on a second
    /// thread while this one renders and tracks; 3 waits for both.
    fn step_pipelined(
        &mut self,
        spent: &mut [Duration; 3],
    ) -> Result<(Captured, Frame, Tracked, Driven), LoopError> {
        let captured = self.capture();
        let ego = self.ego_motion(&captured);
        let needed = self.needed(&captured);
        let (renderer, tracking, drive) = (
            self.renderer.as_deref_mut().expect(HERE),
            &mut self.tracking,
            &mut self.drive,
        );
        let diagnostics = self.diagnostics;
        let [render_t, track_t, physics_t] = spent;
        let (seen, driven) = std::thread::scope(|scope| {
            let physics = scope.spawn(|| timed(physics_t, || drive.advance_frame()));
            let rendered = timed(render_t, || renderer.render_part(&captured.input, needed));
            let seen = track_rendered(
                tracking,
                renderer,
                &captured,
                rendered,
                track_t,
                ego,
                diagnostics,
            );
            let driven = match physics.join() {
                Ok(driven) => driven,
                Err(panic) => std::panic::resume_unwind(panic),
            };
            (seen, driven)
        });
        let (frame, tracked, again) = seen?;
        self.tracked(&captured, &tracked, again);
        Ok((captured, frame, tracked, driven))
    }

    /// Starts rendering the next frame now, on this process's render thread, so that it
    /// renders while the caller does something else (a Gymnasium agent choosing its
    /// action); the next [`ClosedLoop::step`] takes it. Only with one renderer, and it changes
    /// nothing of the results: the frame is the one the step would render.
    pub fn prefetch(&mut self) -> Result<(), LoopError> {
        if self.remote.is_some() || self.frame >= self.frames || !self.in_flight.is_empty() {
            return Ok(());
        }
        let captured = self.capture();
        let needed = self.needed(&captured);
        let thread = match &mut self.render_thread {
            Some(thread) => thread,
            None => {
                self.render_thread
                    .insert(RenderThread::start().map_err(|e| {
                        LoopError::Worker(format!("cannot start the render thread: {e}"))
                    })?)
            }
        };
        let renderer = self.renderer.take().expect(HERE);
        thread.render(renderer, captured.input.clone(), needed);
        self.in_flight.push_back(InFlight {
            captured,
            here: true,
        });
        Ok(())
    }

    /// A frame [`ClosedLoop::prefetch`] started: waits for it and tracks it while the
    /// physics runs to the next frame (pipelined) or after (not).
    fn step_prefetched(
        &mut self,
        spent: &mut [Duration; 3],
    ) -> Result<(Captured, Frame, Tracked, Driven), LoopError> {
        let pending = self.in_flight.pop_front().expect("a prefetched frame");
        let captured = pending.captured;
        let ego = self.ego_motion(&captured);
        let (diagnostics, pipelined) = (self.diagnostics, self.pipelined);
        let thread = self.render_thread.as_mut().expect("the prefetch's thread");
        let (tracking, drive, renderer_slot) =
            (&mut self.tracking, &mut self.drive, &mut self.renderer);
        let [render_t, track_t, physics_t] = spent;
        let mut driven = None;
        let seen = std::thread::scope(|scope| {
            let physics =
                pipelined.then(|| scope.spawn(|| timed(physics_t, || drive.advance_frame())));
            let rendered = thread.wait();
            *render_t += rendered.spent;
            let renderer = renderer_slot.insert(rendered.renderer);
            let seen = track_rendered(
                tracking,
                renderer,
                &captured,
                rendered.frame,
                track_t,
                ego,
                diagnostics,
            );
            if let Some(physics) = physics {
                driven = Some(match physics.join() {
                    Ok(driven) => driven,
                    Err(panic) => std::panic::resume_unwind(panic),
                });
            }
            seen
        });
        let (frame, tracked, again) = seen?;
        self.tracked(&captured, &tracked, again);
        let driven = match driven {
            Some(driven) => driven,
            None => timed(physics_t, || self.drive.advance_frame()),
        };
        Ok((captured, frame, tracked, driven))
    }

    /// One thing at a time: render, track, then the physics.
    fn step_sequential(
        &mut self,
        spent: &mut [Duration; 3],
    ) -> Result<(Captured, Frame, Tracked, Driven), LoopError> {
        let captured = self.capture();
        let ego = self.ego_motion(&captured);
        let needed = self.needed(&captured);
        let [render_t, track_t, physics_t] = spent;
        let renderer = self.renderer.as_deref_mut().expect(HERE);
        let rendered = timed(render_t, || renderer.render_part(&captured.input, needed));
        let (frame, tracked, again) = track_rendered(
            &mut self.tracking,
            renderer,
            &captured,
            rendered,
            track_t,
            ego,
            self.diagnostics,
        )?;
        self.tracked(&captured, &tracked, again);
        let driven = timed(physics_t, || self.drive.advance_frame());
        Ok((captured, frame, tracked, driven))
    }
}

/// Tracks a frame this process rendered (`rendered`), rendering again the parts the tracker
/// asks for: the frame, what the tracker made of it, and whether it asked.
fn track_rendered(
    tracking: &mut Tracking,
    renderer: &mut Renderer,
    captured: &Captured,
    rendered: Result<Frame, RenderError>,
    track_t: &mut Duration,
    ego: Option<EgoMotion>,
    diagnostics: bool,
) -> Result<(Frame, Tracked, bool), LoopError> {
    let mut frame = rendered?;
    let input = &captured.input;
    let render = |part| renderer.render_part(input, part);
    let (tracked, again) = timed(track_t, || {
        tracking.track::<RenderError>(
            &mut frame,
            render,
            input.time_s,
            ego,
            diagnostics,
            captured.pan_reading_rad,
        )
    })?;
    Ok((frame, tracked, again))
}

//! This process's renderer on a thread of its own, so that a frame can go on rendering
//! across the loop's steps.
//!
//! With two frames in flight (see `ClosedLoop::add_render_worker`), the loop hands its
//! renderer to this thread with the next frame it renders here as soon as that frame can be
//! captured (the frame two before it tracked, the physics at its capture), and only then
//! returns the outputs of the frame it has just tracked: nothing the loop does for its
//! caller waits in front of a render. The renderer itself travels with each job and comes
//! back with the frame, so it is never shared: while it is away, the loop cannot use it.

use sim_render::{Frame, FrameInput, RenderError, Renderer};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};
use tracker::PixelRect;

/// A frame to render, and the renderer to render it with.
struct Job {
    renderer: Box<Renderer>,
    input: FrameInput,
    part: Option<PixelRect>,
}

/// A rendered frame (or why not), the renderer back, and the time the render took.
pub(crate) struct Rendered {
    pub(crate) renderer: Box<Renderer>,
    pub(crate) frame: Result<Frame, RenderError>,
    pub(crate) spent: Duration,
}

/// The thread, with a job at a time.
pub(crate) struct RenderThread {
    jobs: Option<Sender<Job>>,
    done: Receiver<Rendered>,
    thread: Option<JoinHandle<()>>,
}

impl RenderThread {
    /// Starts the thread.
    pub(crate) fn start() -> std::io::Result<RenderThread> {
        let (jobs, queued) = channel::<Job>();
        let (finished, done) = channel::<Rendered>();
        let thread = std::thread::Builder::new()
            .name("render".into())
            .spawn(move || {
                for Job {
                    mut renderer,
                    input,
                    part,
                } in queued
                {
                    let started = Instant::now();
                    let frame = renderer.render_part(&input, part);
                    let rendered = Rendered {
                        renderer,
                        frame,
                        spent: started.elapsed(),
                    };
                    if finished.send(rendered).is_err() {
                        // Nobody waits for it any more: the loop is gone.
                        break;
                    }
                }
            })?;
        Ok(RenderThread {
            jobs: Some(jobs),
            done,
            thread: Some(thread),
        })
    }

    /// Renders the part `part` of the frame `input` (all of it for `None`) with `renderer`,
    /// in the background; [`RenderThread::wait`] gives the frame and the renderer back.
    pub(crate) fn render(
        &mut self,
        renderer: Box<Renderer>,
        input: FrameInput,
        part: Option<PixelRect>,
    ) {
        let job = Job {
            renderer,
            input,
            part,
        };
        let sent = self
            .jobs
            .as_ref()
            .is_some_and(|jobs| jobs.send(job).is_ok());
        if !sent {
            // The thread has ended: only a panic ends it while jobs can be sent.
            self.rethrow();
        }
    }

    /// Waits for the frame of the last [`RenderThread::render`].
    pub(crate) fn wait(&mut self) -> Rendered {
        match self.done.recv() {
            Ok(rendered) => rendered,
            Err(_) => self.rethrow(),
        }
    }

    /// Carries the thread's panic on to this one, as a scoped thread's join would.
    fn rethrow(&mut self) -> ! {
        self.jobs = None;
        match self.thread.take().map(JoinHandle::join) {
            Some(Err(panic)) => std::panic::resume_unwind(panic),
            _ => panic!("the render thread stopped without a panic"),
        }
    }
}

impl Drop for RenderThread {
    fn drop(&mut self) {
        // Closing the queue ends the thread once its job (if any) is done.
        self.jobs = None;
        if let Some(thread) = self.thread.take() {
            // A panic there was either carried on already or is moot while dropping.
            let _ = thread.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sim_render::{builtin_description, builtin_poses, builtin_target, Scene};
    use sim_render::{Backend, CameraRig, RenderOptions};

    /// Frames rendered on the thread are those rendered here, frame after frame (whole and
    /// in part, so the renderer's state carries from one to the next), and the renderer
    /// comes back with each.
    #[test]
    fn frames_on_the_thread_are_the_frames_rendered_here() {
        let scene = std::sync::Arc::new(
            Scene::build(builtin_description(builtin_target(), 3)).expect("scene"),
        );
        let options = RenderOptions {
            backend: Backend::choose(None).expect("backend"),
            ..RenderOptions::default()
        };
        let rig = CameraRig::default();
        let mut here = Renderer::new(scene.clone(), rig.clone(), &options).expect("renderer");
        let mut away =
            Box::new(Renderer::new(scene.clone(), rig.clone(), &options).expect("renderer"));
        let mut thread = RenderThread::start().expect("thread");
        let part = PixelRect {
            x0: 90,
            y0: 80,
            x1: 170,
            y1: 150,
        };
        for (k, part) in [(30, None), (31, Some(part)), (32, Some(part)), (33, None)] {
            let time_s = k as f64 / 15.0;
            let (chase, lead) =
                builtin_poses(scene.description(), scene.route(), &rig.mount, time_s);
            let input = FrameInput::fixed_camera(k, time_s, chase, lead);
            thread.render(away, input.clone(), part);
            let rendered = thread.wait();
            away = rendered.renderer;
            let frame = rendered.frame.expect("frame on the thread");
            assert!(rendered.spent > Duration::ZERO);
            assert_eq!(
                frame,
                here.render_part(&input, part).expect("frame here"),
                "frame {k}"
            );
        }
    }
}

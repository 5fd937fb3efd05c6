//! A second renderer, so that the closed loop renders two camera frames at once: on a
//! thread of the loop's process, or in a worker process of its own.
//!
//! **Why a llvmpipe of its own.** Mesa's llvmpipe rasterises every GL context of one EGL
//! display on one rasteriser shared by them, so a second renderer on wgpu's display would
//! only take turns with the first. On the GL backend the second renderer is a thread with an
//! OpenGL context on Mesa's software EGL device, a display (and a llvmpipe) of its own
//! ([`RemoteRenderer::spawn_thread`]; see `camera::software_device`). Where that cannot be
//! had (another backend, an EGL without that device, or a loop whose own renderer is not
//! llvmpipe, whose frames a llvmpipe's would not match), it is a worker process
//! ([`RemoteRenderer::spawn`], `carfollow render-worker`), which renders alongside as well.
//! The thread is the faster: its frames come and go over channels, not pipes
//! (`nist-grounds` ran 1.06× as fast, 8 alternating pairs), and the run is one process. What
//! it gives up is isolation: a crash inside the driver on the thread ends the run (its
//! `frames.csv` rows are flushed as they are written), where a worker process's crash ended
//! only the worker, and the run with a one-line error.
//!
//! **Why two frames can be in flight.** The physics from frame k to k + 1 needs only the
//! estimates of frames up to k − 1 (none arrives sooner than one frame after its capture:
//! see [`crate::closed_loop::ClosedLoop::set_pipelined`]), so frame k + 1's poses are known
//! before frame k has been tracked, and both frames can be rendering at once. The worker
//! builds the loop's scene with the same code and driver, so its frames are the frames the
//! loop's own renderer would have made: the results do not change.
//!
//! **The protocol**, over the worker's stdin and stdout, all numbers little-endian:
//! - the loop first sends the plan's scene description and camera rig ([`send_scene`]: a
//!   `u64` byte count, then the two as TOML, whose numbers round-trip exactly), so the
//!   worker plans nothing: it builds the scene it is given;
//! - the worker then writes that scene's fingerprint ([`fingerprint`]), a `u64`, which the
//!   loop checks against its own;
//! - each request is 44 `u64`-sized fields: the frame index (`u64`), the time, then each of
//!   the chase's and the lead's poses as translation x, y, z and rotation quaternion i, j,
//!   k, w (`f64`, exact bits, so the worker renders exactly the loop's poses), the camera's
//!   pan and the automatic gain (`f64`), then the part of the frame to render, x0, y0, x1,
//!   y1 (`u64`, see [`Renderer::render_part`]), then for an interlaced camera's earlier
//!   field a flag (`u64`, 1 when there is one), its time, the two poses and the pan, as
//!   above, then how many actor poses the frame and its earlier field have (`u64` each, at
//!   most [`ObjectSlot::MAX_ACTORS`]), the chase's speed (`f64`, for the rain's streaks) and
//!   the braking flags (`u64`, a bit per vehicle, for the brake lamps), the lead's speed
//!   (`f64`, for its spray); then those poses, the frame's and then the earlier field's,
//!   seven `f64` each as above, then the frame's actors' speeds (`f64` each, for their
//!   spray);
//! - each answer is the ground truth: c_x, c_y, scale, the target centre in the camera
//!   frame x, y, z (`f64`), and in view (one byte, 0 or 1), then the frame's exact pixels
//!   x0, y0, x1, y1 (`u64`), then the image's rows y0 to y1 (width bytes each; the rows
//!   outside hold no exact pixel and are not sent).
//!
//! The thread takes the same requests as values over a channel, and answers with the frame.
//!
//! The worker exits when its input ends, and the thread when its queue does, so neither
//! outlives the loop. Either may be started before the loop sets up, so that the two set
//! up side by side.

use crate::child::Child;
use crate::plan::render_options;
use image::GrayImage;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use sim_render::{
    Backend, CameraRig, Field, Frame, FrameInput, GroundTruth, RenderOptions, Renderer,
    SoftwareContext,
};
use sim_render::{Braking, ObjectSlot, Scene, SceneDescription};
use std::io::{BufReader, BufWriter, Read, Write};
use std::process::Command;
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::Arc;
use std::thread::JoinHandle;
use tracker::PixelRect;

/// Bytes of one request before its actors' poses.
const REQUEST_BYTES: usize = 44 * 8;
/// Bytes of one pose in a request.
const POSE_BYTES: usize = 7 * 8;
/// Bytes of the ground truth and the exact pixels before the image's rows.
const TRUTH_BYTES: usize = 6 * 8 + 1 + 4 * 8;

/// A fingerprint of everything that decides a frame's pixels: the scene description, the
/// rig and the render options (FNV-1a over their exact debug forms, which print every
/// number's shortest round-trip digits).
pub fn fingerprint(
    description: &SceneDescription,
    rig: &CameraRig,
    options: &RenderOptions,
) -> u64 {
    vehicle::fnv1a64(format!("{description:?}{rig:?}{options:?}").as_bytes())
}

fn put_pose(out: &mut Vec<u8>, pose: &Isometry3<f64>) {
    let t = pose.translation.vector;
    let q = pose.rotation.quaternion().coords;
    for v in [t.x, t.y, t.z, q.x, q.y, q.z, q.w] {
        out.extend_from_slice(&v.to_le_bytes());
    }
}

fn get_f64(bytes: &[u8], field: usize) -> f64 {
    let mut b = [0u8; 8];
    b.copy_from_slice(&bytes[field * 8..field * 8 + 8]);
    f64::from_le_bytes(b)
}

fn get_pose(bytes: &[u8], first: usize) -> Isometry3<f64> {
    let f = |i| get_f64(bytes, first + i);
    Isometry3::from_parts(
        Translation3::new(f(0), f(1), f(2)),
        // The loop's own unit quaternion, bit for bit: no renormalisation.
        UnitQuaternion::new_unchecked(Quaternion::new(f(6), f(3), f(4), f(5))),
    )
}

fn get_u64(bytes: &[u8], field: usize) -> u64 {
    let mut b = [0u8; 8];
    b.copy_from_slice(&bytes[field * 8..field * 8 + 8]);
    u64::from_le_bytes(b)
}

fn put_rect(out: &mut Vec<u8>, r: PixelRect) {
    for v in [r.x0, r.y0, r.x1, r.y1] {
        out.extend_from_slice(&(v as u64).to_le_bytes());
    }
}

fn get_rect(bytes: &[u8], first: usize) -> PixelRect {
    let f = |i| get_u64(bytes, first + i) as usize;
    PixelRect {
        x0: f(0),
        y0: f(1),
        x1: f(2),
        y1: f(3),
    }
}

fn encode_request(input: &FrameInput, part: PixelRect) -> Vec<u8> {
    let mut out = Vec::with_capacity(REQUEST_BYTES);
    out.extend_from_slice(&input.frame_index.to_le_bytes());
    out.extend_from_slice(&input.time_s.to_le_bytes());
    put_pose(&mut out, &input.world_from_chase);
    put_pose(&mut out, &input.world_from_lead);
    out.extend_from_slice(&input.camera_pan_rad.to_le_bytes());
    out.extend_from_slice(&input.auto_gain.to_le_bytes());
    put_rect(&mut out, part);
    let own = input.field();
    let field = input.earlier_field.as_ref().unwrap_or(&own);
    out.extend_from_slice(&u64::from(input.earlier_field.is_some()).to_le_bytes());
    out.extend_from_slice(&field.time_s.to_le_bytes());
    put_pose(&mut out, &field.world_from_chase);
    put_pose(&mut out, &field.world_from_lead);
    out.extend_from_slice(&field.camera_pan_rad.to_le_bytes());
    let earlier_actors = input
        .earlier_field
        .as_ref()
        .map_or(&[][..], |f| &f.world_from_actors[..]);
    for count in [input.world_from_actors.len(), earlier_actors.len()] {
        out.extend_from_slice(&(count as u64).to_le_bytes());
    }
    out.extend_from_slice(&input.chase_speed_mps.to_le_bytes());
    out.extend_from_slice(&input.braking.0.to_le_bytes());
    out.extend_from_slice(&input.lead_speed_mps.to_le_bytes());
    for pose in input.world_from_actors.iter().chain(earlier_actors) {
        put_pose(&mut out, pose);
    }
    for k in 0..input.world_from_actors.len() {
        let speed = input.actor_speeds_mps.get(k).copied().unwrap_or(0.0);
        out.extend_from_slice(&speed.to_le_bytes());
    }
    out
}

/// How many actor poses follow a request's first [`REQUEST_BYTES`] `bytes`: the frame's
/// and its earlier field's. More than a scene can have is not a request of the loop's.
fn actor_counts(bytes: &[u8; REQUEST_BYTES]) -> std::io::Result<[usize; 2]> {
    let counts = [get_u64(bytes, 39), get_u64(bytes, 40)];
    if counts
        .iter()
        .any(|&n| n > u64::from(ObjectSlot::MAX_ACTORS))
    {
        return Err(std::io::Error::other(format!(
            "a request with {counts:?} actor poses: not the loop's"
        )));
    }
    Ok(counts.map(|n| n as usize))
}

/// The request of first bytes `bytes` and actor poses `poses` (as many as
/// [`actor_counts`] says).
fn decode_request(bytes: &[u8; REQUEST_BYTES], poses: &[u8]) -> (FrameInput, PixelRect) {
    let [own, earlier] = actor_counts(bytes).unwrap_or([0, 0]);
    let actors = |first: usize, n: usize| -> Vec<Isometry3<f64>> {
        (first..first + n).map(|k| get_pose(poses, 7 * k)).collect()
    };
    let input = FrameInput {
        frame_index: get_u64(bytes, 0),
        time_s: get_f64(bytes, 1),
        world_from_chase: get_pose(bytes, 2),
        world_from_lead: get_pose(bytes, 9),
        world_from_actors: actors(0, own),
        camera_pan_rad: get_f64(bytes, 16),
        auto_gain: get_f64(bytes, 17),
        braking: Braking(get_u64(bytes, 42)),
        earlier_field: (get_u64(bytes, 22) != 0).then(|| Field {
            time_s: get_f64(bytes, 23),
            world_from_chase: get_pose(bytes, 24),
            world_from_lead: get_pose(bytes, 31),
            world_from_actors: actors(own, earlier),
            camera_pan_rad: get_f64(bytes, 38),
        }),
        chase_speed_mps: get_f64(bytes, 41),
        lead_speed_mps: get_f64(bytes, 43),
        actor_speeds_mps: (0..own)
            .map(|k| get_f64(poses, 7 * (own + earlier) + k))
            .collect(),
    };
    (input, get_rect(bytes, 18))
}

/// The scene a render worker builds, on the wire: the plan's camera rig and scene
/// description.
#[derive(serde::Serialize)]
struct SceneOut<'a> {
    rig: &'a CameraRig,
    description: &'a SceneDescription,
}

/// [`SceneOut`], received.
#[derive(serde::Deserialize)]
struct SceneIn {
    rig: CameraRig,
    description: SceneDescription,
}

/// The loop's side, first: sends the scene `description` and camera `rig` to a render
/// worker on `output` (a `u64` byte count, then TOML: its numbers round-trip exactly).
pub fn send_scene(
    output: &mut impl Write,
    description: &SceneDescription,
    rig: &CameraRig,
) -> std::io::Result<()> {
    let text = toml::to_string(&SceneOut { rig, description }).map_err(std::io::Error::other)?;
    output.write_all(&(text.len() as u64).to_le_bytes())?;
    output.write_all(text.as_bytes())?;
    output.flush()
}

/// The worker's side, first: the scene description and camera rig [`send_scene`] sent.
pub fn receive_scene(input: &mut impl Read) -> std::io::Result<(SceneDescription, CameraRig)> {
    let mut count = [0u8; 8];
    input.read_exact(&mut count)?;
    let count = u64::from_le_bytes(count);
    // A scene's description is some kilobytes; a count beyond this is not one.
    if count > 1 << 30 {
        return Err(std::io::Error::other(format!(
            "a scene of {count} bytes: not the loop's"
        )));
    }
    let mut text = vec![0u8; count as usize];
    input.read_exact(&mut text)?;
    let text = String::from_utf8(text).map_err(std::io::Error::other)?;
    let scene: SceneIn = toml::from_str(&text).map_err(std::io::Error::other)?;
    Ok((scene.description, scene.rig))
}

/// The worker's side: renders each request from `input` with `renderer` and writes the
/// answer to `output`, until `input` ends.
pub fn serve_frames(
    renderer: &mut Renderer,
    fingerprint: u64,
    input: impl Read,
    output: impl Write,
) -> std::io::Result<()> {
    let mut input = BufReader::new(input);
    let mut output = BufWriter::new(output);
    output.write_all(&fingerprint.to_le_bytes())?;
    output.flush()?;
    let mut request = [0u8; REQUEST_BYTES];
    let mut poses = Vec::new();
    loop {
        match input.read_exact(&mut request) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => return Ok(()),
            Err(e) => return Err(e),
        }
        let [own, earlier] = actor_counts(&request)?;
        poses.resize((own + earlier) * POSE_BYTES + own * 8, 0);
        input.read_exact(&mut poses)?;
        let (frame_input, part) = decode_request(&request, &poses);
        let frame = renderer
            .render_part(&frame_input, Some(part))
            .map_err(std::io::Error::other)?;
        let t = frame.truth;
        let [x, y, z] = t.target_cam_m;
        for v in [t.c_x, t.c_y, t.scale, x, y, z] {
            output.write_all(&v.to_le_bytes())?;
        }
        // 1: wholly in view, 2: partly, 0: out.
        output.write_all(&[u8::from(t.in_view) + 2 * u8::from(t.partly_in_view)])?;
        let mut exact = Vec::with_capacity(32);
        put_rect(&mut exact, frame.exact);
        output.write_all(&exact)?;
        let width = frame.image.width() as usize;
        output.write_all(&frame.image.as_raw()[frame.exact.y0 * width..frame.exact.y1 * width])?;
        output.flush()?;
    }
}

/// The loop's side: the second renderer, in a worker process or on a thread of this
/// process (dropping it ends either).
pub struct RemoteRenderer {
    link: Link,
    width: u32,
    height: u32,
}

/// A second renderer started and perhaps still setting up: [`StartedWorker::ready`] waits
/// for it. Dropping it ends it.
pub struct StartedWorker {
    link: Link,
}

/// How the second renderer is reached: a worker process over its stdin and stdout, or a
/// thread of this process over channels (see [`RemoteRenderer::spawn_thread`]).
enum Link {
    Process(Child),
    Thread(ThreadLink),
}

/// The second renderer on a thread of this process, on a llvmpipe of its own (Mesa's
/// software EGL device: see `camera::software_device`).
struct ThreadLink {
    jobs: Option<Sender<(FrameInput, PixelRect)>>,
    done: Receiver<Result<Frame, String>>,
    /// The renderer's fingerprint and its adapter, once it is set up.
    hello: Receiver<Result<(u64, String), String>>,
    /// Its adapter, once [`StartedWorker::ready`] has it.
    adapter: Option<String>,
    thread: Option<JoinHandle<()>>,
}

impl Drop for ThreadLink {
    fn drop(&mut self) {
        // Its queue ends, so the thread ends, dropping its renderer on its own thread.
        self.jobs = None;
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

impl RemoteRenderer {
    /// Starts `command` (a render worker: `carfollow render-worker`) and sends it `scene`
    /// and `rig` to render, without waiting for it to set up ([`StartedWorker::ready`]
    /// does, and checks that it built the scene of the same fingerprint).
    pub fn spawn(
        mut command: Command,
        scene: &Scene,
        rig: &CameraRig,
    ) -> Result<StartedWorker, String> {
        let mut child = Child::spawn(&mut command).map_err(|e| format!("cannot start it: {e}"))?;
        child
            .stdin()
            .and_then(|stdin| send_scene(stdin, scene.description(), rig))
            .map_err(|e| format!("cannot send it the scene: {e}"))?;
        Ok(StartedWorker {
            link: Link::Process(child),
        })
    }

    /// Starts the second renderer on a thread of this process instead of a worker process,
    /// without waiting for it to set up: it builds `scenario`'s scene itself, as a worker
    /// does, on a llvmpipe of its own (an OpenGL context on Mesa's software EGL device), so
    /// that it renders alongside this process's renderer. [`StartedWorker::ready`] says
    /// whether it could (not on another backend, nor without that device).
    pub fn spawn_thread(
        scene: Arc<Scene>,
        rig: CameraRig,
        backend: Backend,
    ) -> Result<StartedWorker, String> {
        let (jobs, queued) = channel::<(FrameInput, PixelRect)>();
        let (finished, done) = channel();
        let (greet, hello) = channel();
        let thread = std::thread::Builder::new()
            .name("render 2".into())
            .spawn(move || {
                if backend != Backend::Gl {
                    let _ = greet.send(Err(format!("a thread renders on gl only, not {backend}")));
                    return;
                }
                let context = match SoftwareContext::open() {
                    Ok(context) => context,
                    Err(e) => {
                        let _ = greet.send(Err(format!("no second llvmpipe in this process: {e}")));
                        return;
                    }
                };
                let options = render_options(backend);
                let opened =
                    Renderer::on_current_gl(scene.clone(), rig.clone(), &options, &|name| {
                        context.proc_address(name)
                    })
                    .map_err(|e| e.to_string())
                    .map(|renderer| {
                        let print = fingerprint(scene.description(), &rig, &options);
                        let adapter = renderer.adapter_name().to_string();
                        (renderer, (print, adapter))
                    });
                let mut renderer = match opened {
                    Ok((renderer, hello)) => {
                        let _ = greet.send(Ok(hello));
                        renderer
                    }
                    Err(e) => {
                        let _ = greet.send(Err(e));
                        return;
                    }
                };
                for (input, part) in queued {
                    let frame = renderer
                        .render_part(&input, Some(part))
                        .map_err(|e| e.to_string());
                    if finished.send(frame).is_err() {
                        break;
                    }
                }
                // The renderer goes before the context it needs.
                drop(renderer);
                drop(context);
            })
            .map_err(|e| format!("cannot start its thread: {e}"))?;
        Ok(StartedWorker {
            link: Link::Thread(ThreadLink {
                jobs: Some(jobs),
                done,
                hello,
                adapter: None,
                thread: Some(thread),
            }),
        })
    }
}

impl StartedWorker {
    /// Waits for the second renderer to set up, and checks that it renders the scene of
    /// `expected` fingerprint at `rig`'s size, and, on a thread (always llvmpipe), on the
    /// loop's adapter `adapter`: a loop on another GL driver (a GPU) would get frames of two
    /// drivers. A worker process chooses its adapter as the loop does.
    pub fn ready(
        self,
        expected: u64,
        adapter: &str,
        rig: &CameraRig,
    ) -> Result<RemoteRenderer, String> {
        let mut link = self.link;
        let got = match &mut link {
            Link::Process(child) => {
                let mut hello = [0u8; 8];
                child
                    .stdout()
                    .read_exact(&mut hello)
                    .map_err(|e| format!("it did not start: {e}"))?;
                u64::from_le_bytes(hello)
            }
            Link::Thread(thread) => {
                let (print, its) = thread
                    .hello
                    .recv()
                    .map_err(|_| "its thread stopped".to_string())??;
                if its != adapter {
                    return Err(format!("it renders on {its}, the loop on {adapter}"));
                }
                thread.adapter = Some(its);
                print
            }
        };
        if got != expected {
            return Err(format!(
                "it built another scene (fingerprint {got:016x}, expected {expected:016x})"
            ));
        }
        Ok(RemoteRenderer {
            link,
            width: rig.width,
            height: rig.height,
        })
    }
}

impl RemoteRenderer {
    /// The adapter the second renderer renders on, when it is a thread of this process
    /// (always Mesa's llvmpipe); `None` for a worker process, which chooses its adapter as
    /// the loop does.
    pub fn adapter_name(&self) -> Option<&str> {
        match &self.link {
            Link::Process(_) => None,
            Link::Thread(thread) => thread.adapter.as_deref(),
        }
    }

    /// Sends a frame to render, only the part `needed` of it if given (see
    /// [`Renderer::render_part`]); its answer comes from [`RemoteRenderer::receive`].
    pub fn submit(&mut self, input: &FrameInput, needed: Option<PixelRect>) -> Result<(), String> {
        let part = needed.unwrap_or(PixelRect::whole(self.width as usize, self.height as usize));
        match &mut self.link {
            Link::Process(child) => child
                .stdin()
                .and_then(|stdin| {
                    stdin.write_all(&encode_request(input, part))?;
                    stdin.flush()
                })
                .map_err(|e| format!("cannot send a frame: {e}")),
            Link::Thread(thread) => thread
                .jobs
                .as_ref()
                .and_then(|jobs| jobs.send((input.clone(), part)).ok())
                .ok_or_else(|| "cannot send a frame: its thread stopped".to_string()),
        }
    }

    /// Waits for the frame submitted first and not yet received.
    pub fn receive(&mut self) -> Result<Frame, String> {
        let child = match &mut self.link {
            Link::Process(child) => child,
            Link::Thread(thread) => {
                return thread
                    .done
                    .recv()
                    .map_err(|_| "no frame came back: its thread stopped".to_string())?;
            }
        };
        let mut truth = [0u8; TRUTH_BYTES];
        let stdout = child.stdout();
        stdout
            .read_exact(&mut truth)
            .map_err(|e| format!("no frame came back: {e}"))?;
        let exact = get_rect(&truth[49..], 0);
        let (width, height) = (self.width as usize, self.height as usize);
        if exact.x0 > exact.x1 || exact.y0 > exact.y1 || exact.x1 > width || exact.y1 > height {
            return Err(format!(
                "the frame came back with exact pixels {exact:?} outside {width} × {height}"
            ));
        }
        let mut pixels = vec![0u8; width * height];
        stdout
            .read_exact(&mut pixels[exact.y0 * width..exact.y1 * width])
            .map_err(|e| format!("no frame came back: {e}"))?;
        let image = GrayImage::from_raw(self.width, self.height, pixels)
            .expect("the buffer holds width × height bytes");
        let f = |i| get_f64(&truth, i);
        Ok(Frame {
            image,
            truth: GroundTruth {
                c_x: f(0),
                c_y: f(1),
                scale: f(2),
                target_cam_m: [f(3), f(4), f(5)],
                in_view: truth[48] == 1,
                partly_in_view: truth[48] == 2,
            },
            exact,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two second renderers on threads share the software device's one display (they take
    /// turns), draw the frames a renderer on wgpu's display draws, and one's end leaves the
    /// other working.
    #[test]
    fn second_renderers_on_threads_draw_the_frames_drawn_here() {
        use sim_render::builtin_poses;
        let plan = crate::Plan::builtin(&["seed=4".to_string()]).expect("plan");
        let (scene, rig) = (plan.scene().clone(), plan.rig().clone());
        let options = render_options(Backend::Gl);
        let print = fingerprint(scene.description(), &rig, &options);
        let mut here = Renderer::new(scene.clone(), rig.clone(), &options).expect("here");
        let adapter = here.adapter_name().to_string();
        let start = || {
            RemoteRenderer::spawn_thread(scene.clone(), rig.clone(), Backend::Gl)
                .and_then(|started| started.ready(print, &adapter, &rig))
                .expect("a second renderer on a thread")
        };
        let (mut one, mut two) = (start(), start());
        assert_eq!(one.adapter_name(), two.adapter_name());
        let part = PixelRect {
            x0: 90,
            y0: 80,
            x1: 170,
            y1: 150,
        };
        let input = |k: u64| {
            let time_s = k as f64 / 15.0;
            let (chase, lead) =
                builtin_poses(scene.description(), scene.route(), &rig.mount, time_s);
            FrameInput::fixed_camera(k, time_s, chase, lead)
        };
        for (k, part) in [(20, None), (21, Some(part)), (22, Some(part))] {
            let input = input(k);
            // Both in flight at once, on their two threads.
            one.submit(&input, part).expect("sent");
            two.submit(&input, part).expect("sent");
            let expected = here.render_part(&input, part).expect("frame here");
            assert_eq!(one.receive().expect("frame"), expected, "frame {k}, first");
            assert_eq!(two.receive().expect("frame"), expected, "frame {k}, second");
        }
        drop(one);
        let input = input(23);
        two.submit(&input, None).expect("sent");
        assert_eq!(
            two.receive().expect("frame after the other ended"),
            here.render(&input).expect("frame here")
        );
    }

    #[test]
    fn requests_round_trip_bit_for_bit() {
        let pose = |a: f64, t: [f64; 3]| {
            Isometry3::from_parts(
                Translation3::new(t[0], t[1], t[2]),
                UnitQuaternion::from_euler_angles(0.01 * a, a, -0.3 * a),
            )
        };
        let actors = |n: usize, a: f64| -> Vec<Isometry3<f64>> {
            (0..n)
                .map(|k| pose(a + k as f64 / 3.0, [k as f64 + 0.1, 0.0, -7.0 / 3.0]))
                .collect()
        };
        let part = PixelRect {
            x0: 3,
            y0: 40,
            x1: 250,
            y1: 241,
        };
        // Without actors, with the earlier field's, and with a progressive frame's.
        for (own, earlier, interlaced) in [(0, 0, true), (3, 3, true), (2, 0, false)] {
            let input = FrameInput {
                frame_index: 123_456_789,
                time_s: 8.2 + 1.0 / 3.0,
                world_from_chase: pose(0.7, [1.0 / 3.0, 0.2, -1e5]),
                world_from_lead: pose(-2.9, [std::f64::consts::PI, 1e-9, 7.0]),
                world_from_actors: actors(own, 0.2),
                camera_pan_rad: -0.3 - 1e-12,
                auto_gain: 1.0 / 3.0,
                braking: Braking(0b1011),
                earlier_field: interlaced.then(|| Field {
                    time_s: 8.2 + 1.0 / 7.0,
                    world_from_chase: pose(0.69, [1.0 / 7.0, 0.21, -1e5 + 0.1]),
                    world_from_lead: pose(-2.8, [3.0, 2e-9, 7.1]),
                    world_from_actors: actors(earlier, -0.4),
                    camera_pan_rad: -0.29,
                }),
                chase_speed_mps: 17.0 + 1.0 / 3.0,
                lead_speed_mps: 25.0 - 1.0 / 3.0,
                actor_speeds_mps: (0..own).map(|k| 20.0 + k as f64 / 7.0).collect(),
            };
            let encoded = encode_request(&input, part);
            let bytes: [u8; REQUEST_BYTES] = encoded[..REQUEST_BYTES].try_into().unwrap();
            let poses = &encoded[REQUEST_BYTES..];
            let [n, m] = actor_counts(&bytes).unwrap();
            assert_eq!((n, m), (own, earlier));
            assert_eq!(poses.len(), (n + m) * POSE_BYTES + n * 8);
            let (back, back_part) = decode_request(&bytes, poses);
            assert_eq!(back, input);
            assert_eq!(back_part, part);
            assert_eq!(
                back.world_from_lead.rotation.quaternion().coords,
                input.world_from_lead.rotation.quaternion().coords
            );
        }
    }

    /// A request of more actor poses than a scene can have is refused, not read.
    #[test]
    fn a_request_of_too_many_actors_is_an_error() {
        let mut input =
            FrameInput::fixed_camera(0, 0.0, Isometry3::identity(), Isometry3::identity());
        input.world_from_actors = vec![Isometry3::identity(); ObjectSlot::MAX_ACTORS as usize + 1];
        let encoded = encode_request(&input, PixelRect::whole(4, 4));
        let bytes: [u8; REQUEST_BYTES] = encoded[..REQUEST_BYTES].try_into().unwrap();
        assert!(actor_counts(&bytes).is_err());
    }

    #[test]
    fn a_second_renderer_on_a_thread_is_gl_only() {
        let plan = crate::Plan::builtin(&["duration_s=1".to_string()]).expect("plan");
        let started =
            RemoteRenderer::spawn_thread(plan.scene().clone(), plan.rig().clone(), Backend::Vulkan)
                .expect("the thread starts");
        let err = started
            .ready(0, "llvmpipe", plan.rig())
            .err()
            .expect("refused");
        assert!(err.contains("gl only"), "{err}");
    }
}

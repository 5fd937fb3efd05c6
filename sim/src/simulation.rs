//! A scenario's run as a value: a [`Simulation`] built from a plan, stepped one camera frame
//! at a time, exposing each frame (its image, truth, estimate and record), and finished with
//! the usual outputs: `frames.csv` (streamed), `summary.json`, the plots, `junit.xml`, and,
//! when asked, the video and a recording. `carfollow run` is a simulation run to its end;
//! the Python package steps one.

use crate::overlay::draw_frame_overlay;
use crate::recording::{
    LiveOptions, RecordError, Recorder, RecorderOptions, ReplaySetup, MCAP_FILE,
};
use crate::report::{
    write_junit, EndedBy, JunitScenario, OutputOptions, ReportError, RunOutputs, Summary,
};
use sim_core::{
    ClosedLoop, ControllerChoice, FrameOutput, FrameRecord, LoopError, LoopOptions, LoopTiming,
    Plan, Scenario, TrackerChoice,
};
use sim_render::Backend;
use std::path::{Path, PathBuf};
use std::time::Instant;
use thiserror::Error;

/// Why a simulation could not go on (never bad input: that is refused before, as a
/// [`sim_core::ScenarioError`]).
#[derive(Debug, Error)]
pub enum RunError {
    /// The loop: the renderer, a worker, a plug-in.
    #[error(transparent)]
    Loop(#[from] LoopError),
    /// Writing an output.
    #[error(transparent)]
    Report(#[from] ReportError),
    /// The recording.
    #[error(transparent)]
    Record(#[from] RecordError),
    /// Something else on the way, said in a line.
    #[error("{0}")]
    Other(String),
}

/// How a simulation runs and what it writes.
#[derive(Debug)]
pub struct SimulationOptions {
    /// The graphics backend.
    pub backend: Backend,
    /// Camera frames rendered at once, 1 or 2 (see [`LoopOptions::renderers`]).
    pub renderers: u8,
    /// How to start a render worker process where the second renderer cannot be a thread.
    pub worker_process: Option<std::process::Command>,
    /// The tracker.
    pub tracker: TrackerChoice,
    /// The controller.
    pub controller: ControllerChoice,
    /// Where the outputs go as the run goes (`None`: kept, for [`Simulation::write_outputs`]).
    pub out: Option<PathBuf>,
    /// `video.gif` and the stills, every `video_stride`-th frame.
    pub video: bool,
    /// See `video`.
    pub video_stride: u32,
    /// Record the run to `out/run.mcap` (needs `out`).
    pub mcap: bool,
    /// Record, but keep the recording only when a criterion failed.
    pub mcap_failed: bool,
    /// Serve the run live to Foxglove.
    pub live: Option<LiveOptions>,
    /// Render every frame whole even when nothing looks at the images (they are then
    /// whole in each [`FrameOutput`]).
    pub whole_frames: bool,
}

impl SimulationOptions {
    /// One renderer on `backend`, the built-ins, nothing written.
    pub fn new(backend: Backend) -> SimulationOptions {
        SimulationOptions {
            backend,
            renderers: 1,
            worker_process: None,
            tracker: TrackerChoice::Builtin,
            controller: ControllerChoice::Builtin,
            out: None,
            video: false,
            video_stride: 1,
            mcap: false,
            mcap_failed: false,
            live: None,
            whole_frames: false,
        }
    }
}

/// A scenario's run, one camera frame at a time.
pub struct Simulation {
    scenario: Scenario,
    looped: ClosedLoop,
    /// The outputs being written, once there is a folder for them.
    outputs: Option<RunOutputs>,
    /// Every record, while nothing streams them (for [`Simulation::write_outputs`]).
    kept: Vec<FrameRecord>,
    recorder: Option<Recorder>,
    keep_failed_only: bool,
    video: (bool, u32),
    started: Instant,
    outputs_s: f64,
    last: Option<FrameOutput>,
    /// The target's size in the image at scale 1, pixels (for a plug-in's overlay).
    target_size_px: [f64; 2],
    /// The run stopped with an error: nothing more steps.
    failed: bool,
}

impl Simulation {
    /// The simulation of `plan`, set up as `options` says. The second renderer, when asked
    /// for and possible, starts first (see [`ClosedLoop::start`]); one that cannot be had
    /// is said in [`Simulation::notes`].
    pub fn new(plan: Plan, options: SimulationOptions) -> Result<Simulation, RunError> {
        let started = Instant::now();
        let scenario = plan.scenario().clone();
        let record = options.mcap || options.mcap_failed || options.live.is_some();
        let looked_at = options.video || record || options.whole_frames;
        let looped = ClosedLoop::start(
            plan,
            LoopOptions {
                backend: options.backend,
                renderers: options.renderers,
                // The overlay of the video and the recording needs the edges' fates.
                diagnostics: options.video || record,
                // Only what looks at the frames needs them whole.
                whole_frames: looked_at,
                worker_process: options.worker_process,
                tracker: options.tracker,
                controller: options.controller,
            },
        )?;
        let target_size_px = {
            let ([fx, fy], [w, h]) = (scenario.camera.focal_px(), scenario.target.size_m());
            let range = scenario.target.nominal_range_m();
            [w * fx / range, h * fy / range]
        };
        let mut sim = Simulation {
            scenario,
            looped,
            outputs: None,
            kept: Vec::new(),
            recorder: None,
            keep_failed_only: options.mcap_failed,
            video: (options.video, options.video_stride),
            started,
            outputs_s: 0.0,
            last: None,
            target_size_px,
            failed: false,
        };
        let mcap = (options.mcap || options.mcap_failed)
            .then(|| options.out.as_ref().map(|d| d.join(MCAP_FILE)))
            .flatten();
        if let Some(dir) = &options.out {
            std::fs::create_dir_all(dir).map_err(ReportError::io(dir))?;
            // A recording of an earlier run must not pass for this one's.
            let old = dir.join(MCAP_FILE);
            if old.is_file() {
                std::fs::remove_file(&old).map_err(|e| {
                    RunError::Other(format!("{}: cannot remove: {e}", old.display()))
                })?;
            }
        }
        // The recording first: a run whose other outputs cannot be written still leaves a
        // readable recording (closed when `sim` drops).
        if mcap.is_some() || options.live.is_some() {
            let setup = ReplaySetup::of(&sim.scenario, &sim.looped).map_err(RunError::Other)?;
            let recorder_options = RecorderOptions {
                mcap,
                live: options.live,
            };
            sim.recorder = Some(Recorder::start(&setup, &recorder_options)?);
        }
        if let Some(dir) = &options.out {
            sim.write_to(dir)?;
        }
        Ok(sim)
    }

    /// Sends the outputs to `dir` from now on: `frames.csv` with the frames run so far, and
    /// the rest as they come.
    pub fn write_to(&mut self, dir: &Path) -> Result<(), RunError> {
        let mut outputs = self.outputs_in(dir)?;
        for r in self.kept.drain(..) {
            outputs.record(&r)?;
        }
        self.outputs = Some(outputs);
        Ok(())
    }

    fn outputs_in(&self, dir: &Path) -> Result<RunOutputs, RunError> {
        let s = &self.scenario;
        let (video, video_stride) = self.video;
        let mut outputs = RunOutputs::create(
            dir,
            OutputOptions {
                video,
                video_stride,
                expected_frames: Some(self.looped.frames()),
                features: s.target.segments().len(),
                traffic: s.has_traffic(),
                ..OutputOptions::default()
            },
            &s.expect,
        )?;
        outputs.set_provenance(s.resolved_json(), s.overrides.clone());
        outputs.set_components(self.looped.tracker_name(), self.looped.controller_name());
        Ok(outputs)
    }

    /// Runs one camera frame (and the physics to the next); `None` once the run is over.
    pub fn step(&mut self) -> Result<Option<&FrameOutput>, RunError> {
        if self.failed {
            return Ok(None);
        }
        let out = match self.looped.step() {
            Ok(Some(out)) => out,
            Ok(None) => return Ok(None),
            Err(e) => {
                self.failed = true;
                return Err(e.into());
            }
        };
        let written = Instant::now();
        if let Some(r) = &mut self.recorder {
            r.frame(&out, self.looped.chase());
        }
        match &mut self.outputs {
            Some(outputs) => {
                outputs.record(&out.record)?;
                if self.video.0 {
                    let img = draw_frame_overlay(&out, self.target_size_px);
                    outputs.frame_image(out.record.frame, &img)?;
                }
            }
            None => self.kept.push(out.record.clone()),
        }
        self.outputs_s += written.elapsed().as_secs_f64();
        self.last = Some(out);
        Ok(self.last.as_ref())
    }

    /// Renders every frame whole, or only the part the tracker reads (see
    /// [`ClosedLoop::set_whole_frames`]); a run writing video keeps whole frames.
    pub fn set_whole_frames(&mut self, on: bool) {
        self.looped.set_whole_frames(on || self.video.0);
    }

    /// Whether the run is over (its duration run, ended by an event's `end_run`, or
    /// stopped by an error).
    pub fn done(&self) -> bool {
        self.failed
            || self.looped.frame() >= self.looped.frames()
            || self.looped.run_ended().is_some()
    }

    /// The last frame run.
    pub fn last(&self) -> Option<&FrameOutput> {
        self.last.as_ref()
    }

    /// The scenario.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// The loop (its names, timing, the built-in controller).
    pub fn looped(&self) -> &ClosedLoop {
        &self.looped
    }

    /// What the set-up has to say that is not an error.
    pub fn notes(&self) -> &[String] {
        self.looped.notes()
    }

    /// Wall-clock seconds since the simulation was made.
    pub fn wall_s(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// Where the time went.
    pub fn timing(&self) -> LoopTiming {
        LoopTiming {
            outputs_s: self.outputs_s,
            ..self.looped.timing()
        }
    }

    /// Ends the run where it stands: the summary, and with a folder for outputs,
    /// `summary.json`, the plots, the video's end, `junit.xml` and the recording (kept or
    /// not, as asked). Returns the summary and the recording's path, when one was kept.
    pub fn finish(mut self) -> Result<(Summary, Option<PathBuf>), RunError> {
        let wall_s = self.wall_s();
        let timing = Some(self.timing());
        let s = &self.scenario;
        let ended_by = self.ended_by();
        let summary = match self.outputs.take() {
            Some(mut outputs) => {
                outputs.set_ended_by(ended_by);
                // The loop (its renderers, the scene, the physics) goes first, so that the
                // plots are drawn in the memory it held, not on top of it.
                drop(self.looped);
                let dir = outputs.dir().to_path_buf();
                let summary = outputs.finish(&s.name, s.seed, wall_s, timing)?;
                write_junit(dir.join("junit.xml"), &[JunitScenario::Ran(&summary)])?;
                summary
            }
            None => self.summary_of_kept(wall_s, timing),
        };
        let mut recording = None;
        if let Some(r) = self.recorder.take() {
            let failed_only = self.keep_failed_only;
            recording = r.finish(Some(&summary), |s| {
                !failed_only || s.is_some_and(|s| !s.passed)
            })?;
        }
        Ok((summary, recording))
    }

    /// Writes the usual outputs of the frames kept so far into `dir` (`frames.csv`,
    /// `summary.json`, the plots, `junit.xml`; no video: its images are gone), and returns
    /// the summary. Only for a simulation that was not writing its outputs already.
    pub fn write_outputs(&self, dir: &Path) -> Result<Summary, RunError> {
        if let Some(outputs) = &self.outputs {
            return Err(RunError::Other(format!(
                "the outputs are being written to {} already",
                outputs.dir().display()
            )));
        }
        let s = &self.scenario;
        let mut outputs = self.outputs_in(dir)?;
        for r in &self.kept {
            outputs.record(r)?;
        }
        outputs.set_ended_by(self.ended_by());
        let summary = outputs.finish(&s.name, s.seed, self.wall_s(), Some(self.timing()))?;
        write_junit(dir.join("junit.xml"), &[JunitScenario::Ran(&summary)])?;
        Ok(summary)
    }

    /// The event that ended the run before its duration, if one has.
    fn ended_by(&self) -> Option<EndedBy> {
        self.looped.run_ended().map(EndedBy::of)
    }

    /// The summary of the frames kept, written nowhere.
    fn summary_of_kept(&self, wall_s: f64, timing: Option<LoopTiming>) -> Summary {
        let s = &self.scenario;
        let mut summary = Summary::compute(&s.name, s.seed, &self.kept, &s.expect, wall_s);
        summary.timing = timing;
        summary.resolved_scenario = Some(s.resolved_json());
        summary.overrides = s.overrides.clone();
        summary.ended_by = self.ended_by();
        summary.tracker = Some(self.looped.tracker_name());
        summary.controller = Some(self.looped.controller_name());
        summary
    }
}

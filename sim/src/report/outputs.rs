//! [`RunOutputs`]: the one thing the closed loop talks to. It streams `frames.csv` and the
//! video while the run goes and keeps no record: the summary is built as the records come
//! ([`SummaryBuilder`]), and the plots keep what they draw of each frame (88 bytes) up to
//! 2.9 MB, merging frames beyond that ([`PlotTrace`]; none with plots off). At the end it
//! writes `summary.json` and the plots.
//!
//! Files in the output directory:
//! - `frames.csv` (see [`FramesCsv`]), `summary.json` (see [`Summary`]), the plots of
//!   [`PLOT_FILES`](super::PLOT_FILES);
//! - with video on: `video.gif` (see [`VideoWriter`]) and PNG stills `still_first.png`,
//!   `still_25pct.png`, `still_50pct.png`, `still_75pct.png` (these three when the expected
//!   frame count is given), `still_first_lost.png` (the first frame judged lost by ground truth
//!   that has an image, if any) and `still_last.png`.
//!
//! `junit.xml` covers all the scenarios of one invocation, so the caller writes it with
//! [`write_junit`](super::write_junit) once every run has finished.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use image::RgbImage;

use super::plots::PlotTrace;
use super::EndedBy;
use super::{write_plots, FramesCsv, ReportError, Summary, SummaryBuilder, VideoWriter};
use sim_core::LoopTiming;
use sim_core::{Expect, FrameRecord};

/// What a run writes besides `frames.csv` and `summary.json`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OutputOptions {
    /// Write `video.gif` and the stills from [`RunOutputs::frame_image`].
    pub video: bool,
    /// Put every `video_stride`-th frame into the GIF (1: all). Stills use every frame given.
    pub video_stride: u32,
    /// Frames the run is expected to record (duration × 15 Hz); with it, stills at 25, 50 and
    /// 75 % are written.
    pub expected_frames: Option<u64>,
    /// Draw the PNG plots at the end.
    pub plots: bool,
    /// Segments of the target model: `frames.csv` has a σ² column for each.
    pub features: usize,
    /// The scenario has traffic (other vehicles, or events): `frames.csv` ends with the
    /// traffic's columns ([`super::TRAFFIC_COLUMNS`]).
    pub traffic: bool,
}

impl Default for OutputOptions {
    fn default() -> Self {
        OutputOptions {
            video: false,
            video_stride: 1,
            expected_frames: None,
            plots: true,
            features: 0,
            traffic: false,
        }
    }
}

/// The outputs of one scenario's run, written into one directory.
#[derive(Debug)]
pub struct RunOutputs {
    dir: PathBuf,
    options: OutputOptions,
    csv: FramesCsv,
    expect: Expect,
    summary: SummaryBuilder,
    /// What the plots draw, when they are on.
    plot_trace: Option<PlotTrace>,
    /// The last record's frame and whether it was lost, for the first lost frame's still.
    last_record: Option<(u64, bool)>,
    video: Option<VideoWriter>,
    stills: Stills,
    /// The resolved scenario and the overrides, for `summary.json`.
    provenance: Option<(serde_json::Value, Vec<String>)>,
    /// The tracker's and the controller's names, for `summary.json`.
    components: Option<(String, String)>,
    /// The event that ended the run early, for `summary.json`.
    ended_by: Option<EndedBy>,
}

/// Which stills are still to be written.
#[derive(Debug, Default)]
struct Stills {
    first_done: bool,
    /// `(frame, file)` not yet reached, in order.
    at_fraction: Vec<(u64, &'static str)>,
    first_lost_done: bool,
    /// The latest frame image, kept for `still_last.png` and a late loss judgement.
    last: Option<(u64, RgbImage)>,
}

/// The files a run writes only with video on: a run removes them when it starts, whether
/// or not it writes them again.
pub const VIDEO_OUTPUTS: [&str; 7] = [
    "video.gif",
    "still_first.png",
    "still_25pct.png",
    "still_50pct.png",
    "still_75pct.png",
    "still_first_lost.png",
    "still_last.png",
];

impl RunOutputs {
    /// Creates `dir` (and its parents) and starts `frames.csv` in it, removing the video and
    /// stills an earlier run left there ([`VIDEO_OUTPUTS`]). The run is judged against
    /// `expect`.
    pub fn create(
        dir: impl AsRef<Path>,
        options: OutputOptions,
        expect: &Expect,
    ) -> Result<RunOutputs, ReportError> {
        let dir = dir.as_ref().to_path_buf();
        std::fs::create_dir_all(&dir).map_err(ReportError::io(&dir))?;
        // What an earlier run in this folder wrote and this one may not: the video and its
        // stills must not pass for this run's.
        for name in VIDEO_OUTPUTS {
            let path = dir.join(name);
            match std::fs::remove_file(&path) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    return Err(ReportError::io(&path)(e))
                }
                _ => {}
            }
        }
        let csv = FramesCsv::create(dir.join("frames.csv"), options.features, options.traffic)?;
        let at_fraction = match options.expected_frames {
            Some(n) if options.video && n > 0 => vec![
                (n / 4, "still_25pct.png"),
                (n / 2, "still_50pct.png"),
                (n * 3 / 4, "still_75pct.png"),
            ],
            _ => Vec::new(),
        };
        let plot_trace = options.plots.then(PlotTrace::new);
        Ok(RunOutputs {
            dir,
            options,
            csv,
            expect: expect.clone(),
            summary: SummaryBuilder::new(expect.gap_band_m),
            plot_trace,
            last_record: None,
            video: None,
            stills: Stills {
                at_fraction,
                ..Stills::default()
            },
            provenance: None,
            components: None,
            ended_by: None,
        })
    }

    /// Records what was run, for `summary.json`: the scenario as resolved (the file with its
    /// overrides applied and defaults filled in) and the `--set` overrides, in order.
    pub fn set_provenance(&mut self, resolved: serde_json::Value, overrides: Vec<String>) {
        self.provenance = Some((resolved, overrides));
    }

    /// Names the event that ended the run before its duration, for `summary.json`.
    pub fn set_ended_by(&mut self, ended_by: Option<EndedBy>) {
        self.ended_by = ended_by;
    }

    /// Names the tracker and the controller that ran, for `summary.json`.
    pub fn set_components(&mut self, tracker: String, controller: String) {
        self.components = Some((tracker, controller));
    }

    /// The output directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Records one frame: appends (and flushes) its `frames.csv` row.
    pub fn record(&mut self, r: &FrameRecord) -> Result<(), ReportError> {
        self.csv.write(r)?;
        self.summary.push(r);
        if let Some(trace) = &mut self.plot_trace {
            trace.push(r);
        }
        self.last_record = Some((r.frame, r.lost_truth));
        if r.lost_truth && !self.stills.first_lost_done {
            if let Some((frame, img)) = &self.stills.last {
                if *frame == r.frame {
                    save_png(&self.dir.join("still_first_lost.png"), img)?;
                    self.stills.first_lost_done = true;
                }
            }
        }
        Ok(())
    }

    /// The camera image with the tracker's overlay for `frame` (see
    /// [`crate::draw_overlay`]). Ignored unless video is on. The frame's record may come
    /// before or after its image.
    pub fn frame_image(&mut self, frame: u64, img: &RgbImage) -> Result<(), ReportError> {
        if !self.options.video {
            return Ok(());
        }
        let stride = self.options.video_stride.max(1);
        if frame.is_multiple_of(u64::from(stride)) {
            if self.video.is_none() {
                self.video = Some(VideoWriter::create(
                    self.dir.join("video.gif"),
                    img.width(),
                    img.height(),
                    stride,
                )?);
            }
            if let Some(v) = &mut self.video {
                v.write(img)?;
            }
        }
        if !self.stills.first_done {
            save_png(&self.dir.join("still_first.png"), img)?;
            self.stills.first_done = true;
        }
        while let Some(&(at, file)) = self.stills.at_fraction.first() {
            if frame < at {
                break;
            }
            save_png(&self.dir.join(file), img)?;
            self.stills.at_fraction.remove(0);
        }
        let lost_now = self.last_record == Some((frame, true));
        if lost_now && !self.stills.first_lost_done {
            save_png(&self.dir.join("still_first_lost.png"), img)?;
            self.stills.first_lost_done = true;
        }
        self.stills.last = Some((frame, img.clone()));
        Ok(())
    }

    /// Ends the run: computes the [`Summary`], writes `summary.json`, the plots, the end of
    /// the video and its last still. `wall_s` is the run's wall-clock time, seconds, and `timing`
    /// where it went, if measured.
    pub fn finish(
        self,
        scenario: &str,
        seed: u64,
        wall_s: f64,
        timing: Option<LoopTiming>,
    ) -> Result<Summary, ReportError> {
        let expect = &self.expect;
        let mut summary = Summary::of(self.summary, scenario, seed, expect, wall_s);
        summary.timing = timing;
        if let Some((resolved, overrides)) = &self.provenance {
            summary.resolved_scenario = Some(resolved.clone());
            summary.overrides = overrides.clone();
        }
        if let Some((tracker, controller)) = &self.components {
            summary.tracker = Some(tracker.clone());
            summary.controller = Some(controller.clone());
        }
        summary.ended_by = self.ended_by.clone();
        summary.write_json(self.dir.join("summary.json"))?;
        if let Some(trace) = &self.plot_trace {
            write_plots(&self.dir, scenario, trace, expect)?;
        }
        if let Some(v) = self.video {
            v.finish()?;
        }
        if let Some((_, img)) = &self.stills.last {
            save_png(&self.dir.join("still_last.png"), img)?;
        }
        Ok(summary)
    }
}

impl Summary {
    /// Writes the summary as pretty-printed JSON with a final newline.
    pub fn write_json(&self, path: impl AsRef<Path>) -> Result<(), ReportError> {
        let path = path.as_ref();
        let file = File::create(path).map_err(ReportError::io(path))?;
        let mut out = BufWriter::new(file);
        serde_json::to_writer_pretty(&mut out, self).map_err(|source| ReportError::Json {
            path: path.to_path_buf(),
            source,
        })?;
        out.write_all(b"\n")
            .and_then(|()| out.flush())
            .map_err(ReportError::io(path))
    }
}

fn save_png(path: &Path, img: &RgbImage) -> Result<(), ReportError> {
    img.save_with_format(path, image::ImageFormat::Png)
        .map_err(|source| ReportError::Image {
            path: path.to_path_buf(),
            source,
        })
}

//! Replay of a recording (`carfollow track run.mcap`): the recorded camera frames through
//! the tracker again, set up from what the recording carries (the scenario as run, its
//! target, the camera and the tracker's start), with tracker settings optionally changed.
//!
//! The file is read as a stream, one frame at a time, so a long run's recording needs no
//! more memory than a short one's. With the settings of the run, every estimate equals the
//! run's bit for bit (`frames.csv`'s columns, which the replay's CSV shares, and the
//! recorded `/tracker/state`, which replay compares frame by frame).

use super::messages::{TrackerInputDecoded, TrackerStateDecoded};
use super::{topics, ReplaySetup, METADATA_NAME};
use crate::overlay::draw_overlay;
use crate::report::csv_writer;
use foxglove::messages::{CompressedImage, RawImage};
use foxglove::Decode;
use image::GrayImage;
use indicatif::{ProgressBar, ProgressStyle};
use mcap::records::Record;
use mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};
use prost::Message;
use sim_core::{Scenario, ScenarioError};
use sim_render::shift_noise;
use std::collections::{BTreeMap, HashMap};
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};
use thiserror::Error;
use tracker::{EgoMotion, GrayView, Location, Status, TrackOutput, Tracker};

/// The columns of the replay's CSV. Those that `frames.csv` also has carry its names and
/// its number format (Rust's shortest round-trip form; empty for a non-finite number), so
/// the two compare field by field. `same_as_recorded` is 1 where this frame's estimate and
/// status equal the recorded ones bit for bit.
pub const REPLAY_CSV_COLUMNS: [&str; 16] = [
    "frame",
    "t_s",
    "est_range_m",
    "est_lateral_m",
    "est_cx_px",
    "est_cy_px",
    "est_scale",
    "confidence_x",
    "confidence_y",
    "confidence_scale",
    "status",
    "coverage_h",
    "coverage_v",
    "coverage_gain",
    "tracker_event",
    "same_as_recorded",
];

/// Frames that may wait for the rest of their messages: a recording writes each frame's
/// messages together, so more than this means the file is not one of ours.
const MAX_PENDING_FRAMES: usize = 64;

/// The largest record (or chunk) a recording may hold, bytes: a recording's chunks are about
/// 1 MiB, so this refuses a damaged length before it allocates.
const MAX_RECORD_BYTES: usize = 256 << 20;

/// A replay that cannot run.
#[derive(Debug, Error)]
pub enum ReplayError {
    /// The recording is unreadable, not a carfollow recording, or the settings are refused.
    #[error("{0}")]
    BadInput(String),
    /// An output (the CSV or an overlay) cannot be written.
    #[error("{0}")]
    Output(String),
}

/// Everything one replay needs.
#[derive(Clone, Debug)]
pub struct ReplayJob {
    /// The recording.
    pub input: PathBuf,
    /// Changes to the tracker's settings; only `tracker.*` fields, and not
    /// `tracker.target`.
    pub overrides: Vec<SettingChange>,
    /// The CSV to write.
    pub out_csv: PathBuf,
    /// Where to write each frame with the overlay, if anywhere.
    pub overlay_dir: Option<PathBuf>,
    /// Show a progress bar (on a terminal).
    pub progress: bool,
}

/// A change to a recording's tracker settings: the assignment, as `--set` takes it
/// (`tracker.lambda=0.7`), and how the user gave it (a flag as typed, e.g. `--lambda 0.7`,
/// or the `--set` itself), which is what errors about it name.
#[derive(Clone, Debug, PartialEq)]
pub struct SettingChange {
    /// `key=value`.
    pub assignment: String,
    /// As given on the command line.
    pub given_as: String,
}

impl SettingChange {
    /// A change given as `--set assignment`.
    pub fn set(assignment: &str) -> SettingChange {
        SettingChange {
            assignment: assignment.to_string(),
            given_as: format!("--set {assignment}"),
        }
    }
}

/// What a replay did.
#[derive(Clone, Debug, PartialEq)]
pub struct ReplaySummary {
    /// The scenario the recording is of.
    pub scenario: String,
    /// Frames replayed.
    pub frames: u64,
    /// Frames the recording says the run had.
    pub frames_recorded: u64,
    /// Frames tracking, coasting and lost.
    pub tracking: u64,
    /// Frames coasting.
    pub coasting: u64,
    /// Frames lost.
    pub lost: u64,
    /// Acquisitions and re-acquisitions by search.
    pub acquisitions: u64,
    /// Frames whose estimate and status equal the recorded ones bit for bit.
    pub same_as_recorded: u64,
    /// The first frame that differs from the recording, if any.
    pub first_difference: Option<u64>,
}

/// A recording opened for replay: its setup, and the scenario rebuilt from it with the
/// job's overrides.
pub struct Tape {
    /// What the recording carries.
    pub setup: ReplaySetup,
    /// The scenario as run, with the overrides applied.
    pub scenario: Scenario,
    /// Where the tracker starts.
    pub start: Location,
}

fn bad(path: &Path, message: impl std::fmt::Display) -> ReplayError {
    ReplayError::BadInput(format!("{}: {message}", path.display()))
}

impl Tape {
    /// Rebuilds the run's scenario from the recording's `setup`, with `overrides` (tracker
    /// settings only).
    pub fn new(
        path: &Path,
        setup: ReplaySetup,
        changes: &[SettingChange],
    ) -> Result<Tape, ReplayError> {
        for c in changes {
            let key = c.assignment.split('=').next().unwrap_or("").trim();
            if !key.starts_with("tracker.") || key == "tracker.target" {
                return Err(ReplayError::BadInput(format!(
                    "{}: replay changes tracker settings only (tracker.*, not \
                     tracker.target): the rest of the run is on the tape",
                    c.given_as
                )));
            }
        }
        let overrides: Vec<String> = changes.iter().map(|c| c.assignment.clone()).collect();
        let where_ = PathBuf::from(format!("{}#resolved_scenario", path.display()));
        let target_text = setup.target_toml.clone();
        let target_path = PathBuf::from(format!("{}#target", path.display()));
        let scenario = Scenario::parse(&setup.resolved_toml, &where_, &overrides, |_| {
            sim_core::parse_target(&target_text, &target_path)
        })
        .map_err(|e| match e {
            // Named as the user gave it.
            ScenarioError::Override {
                assignment,
                message,
            } => {
                let given = changes.iter().find(|c| c.assignment == assignment);
                let given_as = given.map_or(format!("--set {assignment}"), |c| c.given_as.clone());
                ReplayError::BadInput(format!("{given_as}: {message}"))
            }
            e => ReplayError::BadInput(e.to_string()),
        })?;
        // Run as recorded, the tracker starts where it did; a changed placement error moves
        // that start by the change.
        let recorded = Scenario::parse(&setup.resolved_toml, &where_, &[], |_| {
            sim_core::parse_target(&target_text, &target_path)
        })
        .map_err(|e| ReplayError::BadInput(e.to_string()))?;
        let mut start = setup.start;
        if scenario.init_offset != recorded.init_offset {
            let [a, b, c] = recorded.init_offset;
            let [x, y, z] = scenario.init_offset;
            start = Location::new(start.c_x - a + x, start.c_y - b + y, start.scale - c + z);
        }
        Ok(Tape {
            setup,
            scenario,
            start,
        })
    }
}

/// A frame's messages as they arrive.
#[derive(Default)]
struct Pending {
    image: Option<GrayImage>,
    state: Option<TrackerStateDecoded>,
}

/// A number in `frames.csv`'s format: the shortest round-trip decimal, empty when not
/// finite, never `-0`.
fn num(v: f64) -> String {
    if v.is_finite() {
        let v = if v == 0.0 { 0.0 } else { v };
        format!("{v}")
    } else {
        String::new()
    }
}

/// One row of [`REPLAY_CSV_COLUMNS`].
fn row(out: &TrackOutput, frame: u64, same: bool) -> Vec<String> {
    let confidence = out.measurement.map_or([0.0; 3], |m| m.confidence);
    let mut r = vec![frame.to_string()];
    r.extend(
        [
            out.t_s,
            out.position_3d[2],
            out.position_3d[0],
            out.estimate.c_x,
            out.estimate.c_y,
            out.estimate.scale,
            confidence[0],
            confidence[1],
            confidence[2],
        ]
        .map(num),
    );
    r.push(out.status.as_str().to_string());
    r.extend([out.coverage[0], out.coverage[1], out.coverage_gain].map(num));
    r.push(out.event.map_or("", |e| e.as_str()).to_string());
    r.push(if same { "1" } else { "0" }.to_string());
    r
}

/// Whether the replayed output equals the recorded state, bit for bit.
fn same_as(out: &TrackOutput, recorded: Option<&TrackerStateDecoded>) -> bool {
    let Some(r) = recorded else {
        return false;
    };
    let bits = |a: f64, b: f64| a.to_bits() == b.to_bits();
    r.status == out.status.as_str()
        && bits(r.est_cx_px, out.estimate.c_x)
        && bits(r.est_cy_px, out.estimate.c_y)
        && bits(r.est_scale, out.estimate.scale)
        && bits(r.x_m, out.position_3d[0])
        && bits(r.z_m, out.position_3d[2])
}

/// Checks that the file ends as an MCAP file does: a truncated recording is refused before
/// anything is written.
fn check_complete(path: &Path, file: &mut File) -> Result<(), ReplayError> {
    let len = file
        .seek(SeekFrom::End(0))
        .map_err(|e| bad(path, format!("cannot read: {e}")))?;
    let mut tail = [0u8; 8];
    if len < 16 {
        return Err(bad(path, "not an MCAP file (too short)"));
    }
    file.seek(SeekFrom::End(-8))
        .and_then(|_| file.read_exact(&mut tail))
        .and_then(|()| file.seek(SeekFrom::Start(0)).map(|_| ()))
        .map_err(|e| bad(path, format!("cannot read: {e}")))?;
    if tail != *mcap::MAGIC {
        let mut head = [0u8; 8];
        let _ = file.read_exact(&mut head);
        let _ = file.seek(SeekFrom::Start(0));
        return Err(bad(
            path,
            if head == *mcap::MAGIC {
                "the recording is truncated (no MCAP footer): the run that wrote it did not finish"
            } else {
                "not an MCAP file"
            },
        ));
    }
    Ok(())
}

/// A camera frame of a recording: `foxglove.RawImage` mono8, or `foxglove.CompressedImage`
/// PNG as recordings made before the raw frames have them.
fn decode_image(schema: &str, data: &[u8]) -> Result<GrayImage, String> {
    match schema {
        "foxglove.RawImage" => {
            let m = <RawImage as Decode>::decode(data).map_err(|e| e.to_string())?;
            if m.encoding != "mono8" {
                return Err(format!("its encoding is {:?}, not mono8", m.encoding));
            }
            let (w, h) = (m.width as usize, m.height as usize);
            let step = m.step as usize;
            if w == 0 || h == 0 || step < w || m.data.len() < step * (h - 1) + w {
                return Err(format!(
                    "{} bytes do not hold {w}×{h} pixels with a step of {step}",
                    m.data.len()
                ));
            }
            let mut pixels = Vec::with_capacity(w * h);
            for row in m.data.chunks(step).take(h) {
                pixels.extend_from_slice(&row[..w]);
            }
            // The size was checked just above.
            GrayImage::from_raw(m.width, m.height, pixels)
                .ok_or_else(|| "the frame does not hold its pixels".to_string())
        }
        "foxglove.CompressedImage" => {
            let m = <CompressedImage as Decode>::decode(data).map_err(|e| e.to_string())?;
            if m.format != "png" {
                return Err(format!("its format is {:?}, not png", m.format));
            }
            match image::load_from_memory_with_format(&m.data, image::ImageFormat::Png)
                .map_err(|e| e.to_string())?
            {
                image::DynamicImage::ImageLuma8(g) => Ok(g),
                other => Err(format!("it is {:?}, not 8-bit grey", other.color())),
            }
        }
        other => Err(format!(
            "its schema is {other:?}, not foxglove.RawImage or foxglove.CompressedImage"
        )),
    }
}

/// Replays the recording through the tracker, writing the CSV (and overlays) as it goes.
/// `carfollow run` writes its metadata first; a recording whose metadata comes after its
/// first frame (another tool may write it anywhere) is read twice: once for the metadata,
/// then for the frames.
pub fn replay(job: &ReplayJob) -> Result<ReplaySummary, ReplayError> {
    match replay_pass(job, None)? {
        Pass::Done(summary) => Ok(summary),
        Pass::MetadataLater => {
            let setup = metadata_pass(job.input.as_path())?;
            match replay_pass(job, Some(setup))? {
                Pass::Done(summary) => Ok(summary),
                Pass::MetadataLater => unreachable!("the setup was given"),
            }
        }
    }
}

/// How a pass over the recording ended.
enum Pass {
    Done(ReplaySummary),
    /// A frame came before the metadata: read the metadata first.
    MetadataLater,
}

/// Opens a recording to read it from the start, refusing one cut short.
fn open_recording(path: &Path) -> Result<(File, LinearReader), ReplayError> {
    let mut file = File::open(path).map_err(|e| bad(path, format!("cannot read: {e}")))?;
    check_complete(path, &mut file)?;
    file.seek(SeekFrom::Start(0))
        .map_err(|e| bad(path, format!("cannot read: {e}")))?;
    // Every chunk's checksum is checked before any of its frames reaches the tracker: a
    // damaged tape is refused, not replayed to other estimates.
    let reader = LinearReader::new_with_options(
        LinearReaderOptions::default()
            .with_prevalidate_chunk_crcs(true)
            .with_validate_data_section_crc(true)
            .with_validate_summary_section_crc(true)
            .with_record_length_limit(MAX_RECORD_BYTES),
    );
    Ok((file, reader))
}

/// Reads the next `need` bytes of the recording into the reader.
fn feed(
    path: &Path,
    file: &mut File,
    reader: &mut LinearReader,
    need: usize,
) -> Result<(), ReplayError> {
    let read = file
        .read(reader.insert(need))
        .map_err(|e| bad(path, format!("cannot read: {e}")))?;
    if read == 0 {
        return Err(bad(path, "the recording ends in the middle of a record"));
    }
    reader.notify_read(read);
    Ok(())
}

/// The recording's setup, from its `carfollow` metadata wherever it stands.
fn metadata_pass(path: &Path) -> Result<ReplaySetup, ReplayError> {
    let (mut file, mut reader) = open_recording(path)?;
    while let Some(event) = reader.next_event() {
        let event = event.map_err(|e| bad(path, format!("not a readable MCAP file: {e}")))?;
        match event {
            LinearReadEvent::ReadRequest(need) => feed(path, &mut file, &mut reader, need)?,
            LinearReadEvent::Record { opcode, data } => {
                if let Record::Metadata(m) = mcap::parse_record(opcode, data)
                    .map_err(|e| bad(path, format!("a record cannot be read: {e}")))?
                {
                    if m.name == METADATA_NAME {
                        return ReplaySetup::from_metadata(&m.metadata).map_err(|e| bad(path, e));
                    }
                }
            }
        }
    }
    Err(bad(
        path,
        format!("not a carfollow recording: no `{METADATA_NAME}` metadata record"),
    ))
}

/// One pass over the recording; with `setup`, the metadata is already known.
fn replay_pass(job: &ReplayJob, setup: Option<ReplaySetup>) -> Result<Pass, ReplayError> {
    let path = job.input.as_path();
    let (mut file, mut reader) = open_recording(path)?;
    let mut topics_by_channel: HashMap<u16, String> = HashMap::new();
    let mut schema_names: HashMap<u16, String> = HashMap::new();
    // The image schema of each image channel: raw mono8, or PNG in older recordings.
    let mut image_schemas: HashMap<u16, String> = HashMap::new();
    let mut pending: BTreeMap<u64, Pending> = BTreeMap::new();
    let known = setup.is_some();
    let mut run: Option<Run> = match setup {
        Some(setup) => Some(Run::start(job, Tape::new(path, setup, &job.overrides)?)?),
        None => None,
    };
    let mut next_frame = 0u64;
    while let Some(event) = reader.next_event() {
        let event = event.map_err(|e| bad(path, format!("not a readable MCAP file: {e}")))?;
        let (opcode, data) = match event {
            LinearReadEvent::ReadRequest(need) => {
                feed(path, &mut file, &mut reader, need)?;
                continue;
            }
            LinearReadEvent::Record { opcode, data } => (opcode, data),
        };
        let record = mcap::parse_record(opcode, data)
            .map_err(|e| bad(path, format!("a record cannot be read: {e}")))?;
        match record {
            Record::Metadata(m) if m.name == METADATA_NAME && !known && run.is_none() => {
                let setup = ReplaySetup::from_metadata(&m.metadata).map_err(|e| bad(path, e))?;
                let tape = Tape::new(path, setup, &job.overrides)?;
                run = Some(Run::start(job, tape)?);
            }
            Record::Schema { header, .. } => {
                schema_names.insert(header.id, header.name);
            }
            Record::Channel(c) => {
                if c.topic == topics::IMAGE {
                    let schema = schema_names.get(&c.schema_id).cloned().unwrap_or_default();
                    image_schemas.insert(c.id, schema);
                }
                topics_by_channel.insert(c.id, c.topic.clone());
            }
            Record::Message { header, data } => {
                let topic = topics_by_channel
                    .get(&header.channel_id)
                    .map(String::as_str)
                    .unwrap_or("");
                let t = header.log_time;
                match topic {
                    topics::IMAGE => {
                        let schema = image_schemas
                            .get(&header.channel_id)
                            .map(String::as_str)
                            .unwrap_or("");
                        let image = decode_image(schema, data.as_ref()).map_err(|e| {
                            bad(path, format!("the image at {t} ns cannot be decoded: {e}"))
                        })?;
                        pending.entry(t).or_default().image = Some(image);
                    }
                    topics::TRACKER => {
                        let state = TrackerStateDecoded::decode(data.as_ref()).map_err(|e| {
                            bad(
                                path,
                                format!("a tracker state at {t} ns cannot be decoded: {e}"),
                            )
                        })?;
                        pending.entry(t).or_default().state = Some(state);
                    }
                    topics::INPUT => {
                        let input = TrackerInputDecoded::decode(data.as_ref()).map_err(|e| {
                            bad(
                                path,
                                format!("a tracker input at {t} ns cannot be decoded: {e}"),
                            )
                        })?;
                        let Some(run) = run.as_mut() else {
                            return Ok(Pass::MetadataLater);
                        };
                        let frame = pending.remove(&t).unwrap_or_default();
                        if input.frame != next_frame {
                            return Err(bad(
                                path,
                                format!(
                                    "frame {next_frame} is missing (the next is {})",
                                    input.frame
                                ),
                            ));
                        }
                        let Some(image) = frame.image else {
                            return Err(bad(path, format!("frame {} has no image", input.frame)));
                        };
                        if input.frame >= run.summary.frames_recorded {
                            return Err(bad(
                                path,
                                format!(
                                    "holds more frames than its metadata's {}: not one run's \
                                     recording",
                                    run.summary.frames_recorded
                                ),
                            ));
                        }
                        run.step(path, &image, &input, frame.state.as_ref())?;
                        next_frame += 1;
                    }
                    _ => {}
                }
                if pending.len() > MAX_PENDING_FRAMES {
                    return Err(bad(
                        path,
                        "not a carfollow recording: images without the tracker's input",
                    ));
                }
            }
            _ => {}
        }
    }
    let Some(run) = run else {
        return Err(bad(
            path,
            format!("not a carfollow recording: no `{METADATA_NAME}` metadata record"),
        ));
    };
    if next_frame == 0 {
        return Err(bad(path, "the recording has no frames"));
    }
    run.finish().map(Pass::Done)
}

/// The tracker on its way through the tape.
struct Run {
    tracker: Tracker,
    csv: csv::Writer<File>,
    csv_path: PathBuf,
    overlay_dir: Option<PathBuf>,
    bar: ProgressBar,
    summary: ReplaySummary,
    width: u32,
    height: u32,
    /// The sensor noise the images were recorded without, and its seed.
    noise: (f64, u64),
    /// The frame with its noise added back (the buffer is reused).
    noisy: Vec<u8>,
}

impl Run {
    fn start(job: &ReplayJob, tape: Tape) -> Result<Run, ReplayError> {
        let s = &tape.scenario;
        let tracker = Tracker::new(s.target.clone(), s.camera, s.tracker.clone(), tape.start)
            .map_err(|e| bad(&job.input, format!("cannot start the tracker: {e}")))?;
        let out_err = |p: &Path, e: std::io::Error| {
            ReplayError::Output(format!("{}: cannot write: {e}", p.display()))
        };
        if let Some(dir) = &job.overlay_dir {
            std::fs::create_dir_all(dir).map_err(|e| out_err(dir, e))?;
        }
        let file = File::create(&job.out_csv).map_err(|e| out_err(&job.out_csv, e))?;
        let mut csv = csv_writer(file);
        csv.write_record(REPLAY_CSV_COLUMNS)
            .map_err(|e| out_err(&job.out_csv, e.into()))?;
        let bar = if job.progress {
            ProgressBar::new(tape.setup.frames)
        } else {
            ProgressBar::hidden()
        };
        bar.set_style(
            ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} frames {msg}")
                .expect("valid template")
                .progress_chars("=> "),
        );
        Ok(Run {
            tracker,
            csv,
            csv_path: job.out_csv.clone(),
            overlay_dir: job.overlay_dir.clone(),
            bar,
            summary: ReplaySummary {
                scenario: tape.setup.scenario.clone(),
                frames: 0,
                frames_recorded: tape.setup.frames,
                tracking: 0,
                coasting: 0,
                lost: 0,
                acquisitions: 0,
                same_as_recorded: 0,
                first_difference: None,
            },
            width: tape.setup.width,
            height: tape.setup.height,
            noise: (tape.setup.noise_removed_sigma, tape.setup.seed),
            noisy: Vec::new(),
        })
    }

    fn step(
        &mut self,
        path: &Path,
        image: &GrayImage,
        input: &TrackerInputDecoded,
        recorded: Option<&TrackerStateDecoded>,
    ) -> Result<(), ReplayError> {
        let k = input.frame;
        if image.dimensions() != (self.width, self.height) {
            return Err(bad(
                path,
                format!(
                    "frame {k}'s image is {}×{}, not {}×{}",
                    image.width(),
                    image.height(),
                    self.width,
                    self.height
                ),
            ));
        }
        if !input.t_s.is_finite() {
            return Err(bad(path, format!("frame {k}'s time is not a number")));
        }
        // The sensor noise, recorded apart, added back exactly (see
        // `ReplaySetup::noise_removed_sigma`).
        shift_noise(
            image.as_raw(),
            &mut self.noisy,
            self.noise.0,
            self.noise.1,
            k,
            1,
        );
        let view = GrayView::new(image.width() as usize, image.height() as usize, &self.noisy)
            .map_err(|e| bad(path, format!("frame {k}: {e}")))?;
        let ego = input.aided.then_some(EgoMotion {
            rotation_rad: [input.ego_x_rad, input.ego_y_rad, input.ego_z_rad],
        });
        let diagnostics = self.overlay_dir.is_some();
        let (out, edges) = match (ego, diagnostics) {
            (Some(ego), true) => self
                .tracker
                .step_aided_with_diagnostics(view, input.t_s, ego),
            (Some(ego), false) => (self.tracker.step_aided(view, input.t_s, ego), Vec::new()),
            (None, true) => self.tracker.step_with_diagnostics(view, input.t_s),
            (None, false) => (self.tracker.step(view, input.t_s), Vec::new()),
        };
        let same = same_as(&out, recorded);
        let s = &mut self.summary;
        s.frames += 1;
        match out.status {
            Status::Tracking => s.tracking += 1,
            Status::Coasting => s.coasting += 1,
            Status::Lost => s.lost += 1,
        }
        s.acquisitions += u64::from(out.event.is_some_and(|e| e.is_acquisition()));
        if same {
            s.same_as_recorded += 1;
        } else if s.first_difference.is_none() {
            s.first_difference = Some(k);
        }
        let csv_path = &self.csv_path;
        let out_err = |e: std::io::Error| {
            ReplayError::Output(format!("{}: cannot write: {e}", csv_path.display()))
        };
        self.csv
            .write_record(row(&out, k, same))
            .map_err(|e| out_err(e.into()))?;
        if let Some(dir) = &self.overlay_dir {
            let target = dir.join(format!("frame-{k:06}.png"));
            draw_overlay(image, &out, &edges)
                .save(&target)
                .map_err(|e| {
                    ReplayError::Output(format!("{}: cannot write overlay: {e}", target.display()))
                })?;
        }
        self.bar.set_message(out.status.as_str());
        self.bar.inc(1);
        Ok(())
    }

    fn finish(mut self) -> Result<ReplaySummary, ReplayError> {
        self.bar.finish_and_clear();
        self.csv.flush().map_err(|e| {
            ReplayError::Output(format!("{}: cannot write: {e}", self.csv_path.display()))
        })?;
        Ok(self.summary)
    }
}

#[cfg(test)]
mod tests {
    use super::decode_image;
    use foxglove::messages::{CompressedImage, RawImage};
    use foxglove::Encode;
    use image::{GrayImage, Luma};

    fn encoded(m: &impl Encode) -> Vec<u8> {
        let mut buf = Vec::new();
        m.encode(&mut buf).unwrap();
        buf
    }

    fn frame() -> GrayImage {
        GrayImage::from_fn(5, 3, |x, y| Luma([(7 * x + 40 * y) as u8]))
    }

    fn raw(width: u32, height: u32, step: u32, data: Vec<u8>, encoding: &str) -> Vec<u8> {
        encoded(&RawImage {
            width,
            height,
            step,
            encoding: encoding.into(),
            data: data.into(),
            ..RawImage::default()
        })
    }

    #[test]
    fn raw_frames_come_back_with_and_without_row_padding() {
        let f = frame();
        let tight = raw(5, 3, 5, f.as_raw().clone(), "mono8");
        assert_eq!(decode_image("foxglove.RawImage", &tight).unwrap(), f);
        let padded: Vec<u8> = f
            .rows()
            .flat_map(|r| r.map(|p| p[0]).chain([0, 0]))
            .collect();
        let padded = raw(5, 3, 7, padded, "mono8");
        assert_eq!(decode_image("foxglove.RawImage", &padded).unwrap(), f);
    }

    #[test]
    fn png_frames_of_older_recordings_come_back() {
        let f = frame();
        let mut png = Vec::new();
        f.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .unwrap();
        let m = encoded(&CompressedImage {
            format: "png".into(),
            data: png.into(),
            ..CompressedImage::default()
        });
        assert_eq!(decode_image("foxglove.CompressedImage", &m).unwrap(), f);
    }

    #[test]
    fn bad_frames_are_refused_with_the_reason() {
        let f = frame();
        let short = raw(5, 3, 5, f.as_raw()[..14].to_vec(), "mono8");
        let e = decode_image("foxglove.RawImage", &short).unwrap_err();
        assert!(e.contains("14 bytes do not hold 5×3 pixels"), "{e}");
        let rgb = raw(5, 3, 15, vec![0; 45], "rgb8");
        let e = decode_image("foxglove.RawImage", &rgb).unwrap_err();
        assert!(e.contains("\"rgb8\", not mono8"), "{e}");
        let e = decode_image("foxglove.Grid", &[]).unwrap_err();
        assert!(e.contains("not foxglove.RawImage"), "{e}");
        let e = decode_image("foxglove.RawImage", &[0xff; 9]).unwrap_err();
        assert!(!e.is_empty());
    }
}

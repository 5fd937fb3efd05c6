//! Running points: one closed loop per point, each in a worker process with its own
//! renderer, `jobs` workers at once.
//!
//! **Why processes, not threads.** Mesa's llvmpipe rasterises every GL context of a process
//! on one rasteriser shared by the process, so renderers on threads of one process take
//! turns: two of them render no faster than one. Renderers in separate processes run side
//! by side. Each worker also rasterises on its own thread (llvmpipe's `LP_NUM_THREADS=0`,
//! unless the environment already sets it): the sweep's parallelism is its points, one per
//! core, and at 256×242 llvmpipe's own threads gain a single renderer little. For the same
//! reason a worker overlaps a point's physics with its rendering only when there are fewer
//! workers than cores (measured at `--jobs 2` on two cores: about 5 % faster without).
//!
//! **The protocol.** The parent starts each worker with the same sweep file and overrides
//! (`carfollow sweep-worker`), then writes one line per point, `INDEX ID`, to its stdin; the
//! worker answers each with one JSON line on its stdout: `{"Row": {...}}` or
//! `{"Error": "..."}`. The id guards against a sweep file edited in between. A worker that
//! dies costs only its current point, which is reported as an error; the next point starts
//! a fresh worker. The parent alone writes the results file, one line per finished point as
//! soon as it arrives, so an interrupted sweep keeps every finished point.

use super::{Point, ResultRow, ResultsWriter, Sweep, SweepError};
use crate::recording::{Recorder, RecorderOptions, ReplaySetup};
use crate::report::{Summary, SummaryBuilder};
use serde::{Deserialize, Serialize};
use sim_core::Child;
use sim_core::ClosedLoop;
use sim_render::Backend;
use std::collections::VecDeque;
use std::io::{BufRead, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::time::Instant;

/// Runs one point through the closed loop and returns its row. `overlap`: whether the
/// loop overlaps each frame's physics with its rendering (see
/// [`ClosedLoop::set_pipelined`]); worth it only when a core would otherwise be idle, that
/// is, with fewer workers than cores. The row is the same either way. With `recordings`, the
/// point is recorded (see [`crate::Recorder`]) to [`recording_path`] in that folder, and
/// the recording is kept only when a criterion failed.
pub fn run_point(
    sweep: &Sweep,
    point: &Point,
    backend: Backend,
    overlap: bool,
    recordings: Option<&Path>,
) -> Result<ResultRow, SweepError> {
    let fail = |message: String| SweepError::Run {
        point: point.describe(),
        message,
    };
    let plan = sweep.plan(point)?;
    let scenario = plan.scenario().clone();
    let started = Instant::now();
    let mut looped =
        ClosedLoop::new(plan, backend, recordings.is_some()).map_err(|e| fail(e.to_string()))?;
    looped.set_pipelined(overlap);
    // Only a recording looks at the frames.
    looped.set_whole_frames(recordings.is_some());
    let mut recorder = match recordings {
        None => None,
        Some(dir) => {
            std::fs::create_dir_all(dir)
                .map_err(|e| fail(format!("{}: cannot create: {e}", dir.display())))?;
            let options = RecorderOptions {
                mcap: Some(recording_path(dir, point)),
                live: None,
            };
            Some(
                Recorder::start(
                    &ReplaySetup::of(&scenario, &looped).map_err(fail)?,
                    &options,
                )
                .map_err(|e| fail(e.to_string()))?,
            )
        }
    };
    // The summary is built as the frames come: a point keeps no record.
    let mut built = SummaryBuilder::new(scenario.expect.gap_band_m);
    while let Some(out) = looped.step().map_err(|e| fail(e.to_string()))? {
        if let Some(r) = &mut recorder {
            r.frame(&out, looped.chase());
        }
        built.push(&out.record);
    }
    let wall_s = started.elapsed().as_secs_f64();
    let mut summary = Summary::of(
        built,
        &scenario.name,
        scenario.seed,
        &scenario.expect,
        wall_s,
    );
    summary.timing = Some(looped.timing());
    summary.ended_by = looped.run_ended().map(crate::report::EndedBy::of);
    summary.tracker = Some(looped.tracker_name());
    summary.controller = Some(looped.controller_name());
    // What this point changed of its scenario file: the sweep's `set`, `--set`, its seed and
    // its axes' values. (The resolved scenario follows from them and the file; a row does
    // not repeat it.)
    summary.overrides = scenario.overrides.clone();
    if let Some(r) = recorder {
        r.finish(Some(&summary), |s| s.is_some_and(|s| !s.passed))
            .map_err(|e| fail(e.to_string()))?;
    }
    Ok(ResultRow::new(point, &summary, &sweep.hash))
}

/// Where `sweep --mcap-failed` keeps a point's recording in `dir`:
/// `<scenario>-seed<seed>-<id>.mcap` (the id is the point's in `results.jsonl`).
pub fn recording_path(dir: &Path, point: &Point) -> PathBuf {
    dir.join(format!(
        "{}-seed{}-{}.mcap",
        point.scenario_name, point.seed, point.id
    ))
}

/// A worker's answer for one point.
#[derive(Debug, Serialize, Deserialize)]
enum Reply {
    /// The point ran: its row.
    Row(ResultRow),
    /// It could not run: why.
    Error(String),
}

/// The worker's side of the protocol (see the module notes): reads `INDEX ID` lines from
/// `input` until it ends, runs each point (see [`run_point`] for `overlap` and `recordings`)
/// and writes its reply line to `output`, flushed. Returns an error only when `input` or
/// `output` fails.
pub fn serve_points(
    sweep: &Sweep,
    backend: Backend,
    overlap: bool,
    recordings: Option<&Path>,
    input: impl BufRead,
    output: impl Write,
) -> std::io::Result<()> {
    let mut output = BufWriter::new(output);
    for line in input.lines() {
        let line = line?;
        let mut words = line.split_whitespace();
        let point = match (
            words.next().and_then(|w| w.parse::<usize>().ok()),
            words.next(),
        ) {
            (Some(index), Some(id)) => match sweep.points.get(index) {
                Some(p) if p.id == id => Ok(p),
                _ => Err(format!(
                    "point {index} ({id}) is not in {}: was the sweep file edited?",
                    sweep.path.display()
                )),
            },
            _ => Err(format!("not a point request: {line:?}")),
        };
        let reply = match point.map(|p| run_point(sweep, p, backend, overlap, recordings)) {
            Ok(Ok(row)) => Reply::Row(row),
            // The parent names the point; the reply says only what went wrong.
            Ok(Err(SweepError::Run { message, .. })) => Reply::Error(message),
            Ok(Err(e)) => Reply::Error(e.to_string()),
            Err(message) => Reply::Error(message),
        };
        serde_json::to_writer(&mut output, &reply)?;
        output.write_all(b"\n")?;
        output.flush()?;
        return_free_memory();
    }
    Ok(())
}

/// Hands the memory the last point freed back to the system (glibc's `malloc_trim`), so
/// that what one point left in pieces adds less to the next one's peak: a worker that ran
/// `nist-grounds` twice and then a 30-minute route twice peaked at 134-135 MB without this
/// and 132 MB with it (one that ran `nist-grounds` alone: 120 MB).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn return_free_memory() {
    // SAFETY: malloc_trim only returns free pages of the allocator's own arenas.
    unsafe { libc::malloc_trim(0) };
}

/// Elsewhere the allocator is left as it is.
#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn return_free_memory() {}

/// A running worker process.
struct Worker(Child);

impl Worker {
    /// Sends a point and waits for its reply; `Err` when the worker is gone.
    fn ask(&mut self, point: &Point) -> Result<Reply, String> {
        let child = &mut self.0;
        child
            .stdin()
            .and_then(|stdin| {
                writeln!(stdin, "{} {}", point.index, point.id)?;
                stdin.flush()
            })
            .map_err(|e| e.to_string())?;
        let mut line = String::new();
        match child.stdout().read_line(&mut line) {
            Ok(0) => Err("it exited without an answer".into()),
            Ok(_) => serde_json::from_str(&line).map_err(|e| format!("unreadable answer: {e}")),
            Err(e) => Err(e.to_string()),
        }
    }
}

/// Runs `points` on `jobs` worker processes, each started by `spawn_worker()` (a command
/// that speaks the protocol of [`serve_points`] for this sweep). Appends each row to
/// `writer` as soon as its point finishes and then calls `done` with it (or with the
/// error). Returns the errors of the points that could not run, in grid order; the others
/// are all written. A results file that cannot be written, or a worker that cannot be
/// started, stops the sweep with that error.
pub fn run_points(
    points: &[&Point],
    jobs: usize,
    spawn_worker: &(dyn Fn() -> Command + Sync),
    writer: &ResultsWriter,
    done: impl Fn(Result<&ResultRow, &SweepError>) + Sync,
) -> Result<Vec<SweepError>, SweepError> {
    let queue = Mutex::new(points.iter().copied().collect::<VecDeque<&Point>>());
    let next = || queue.lock().expect("no panics hold the queue").pop_front();
    let stop = || queue.lock().expect("no panics hold the queue").clear();
    let errors = Mutex::new(Vec::new());
    let fatal = Mutex::new(None);
    let give_up = |e: SweepError| {
        fatal.lock().expect("no panics hold it").get_or_insert(e);
        stop();
    };
    std::thread::scope(|scope| {
        for _ in 0..jobs.clamp(1, points.len().max(1)) {
            scope.spawn(|| {
                let mut current: Option<Worker> = None;
                while let Some(point) = next() {
                    let run_error = |message: String| SweepError::Run {
                        point: point.describe(),
                        message,
                    };
                    let mut worker = match current.take() {
                        Some(w) => w,
                        None => match Child::spawn(&mut spawn_worker()) {
                            Ok(child) => Worker(child),
                            Err(e) => {
                                give_up(run_error(format!("cannot start a worker process: {e}")));
                                break;
                            }
                        },
                    };
                    let result = match worker.ask(point) {
                        Ok(Reply::Row(row)) => {
                            current = Some(worker);
                            Ok(row)
                        }
                        Ok(Reply::Error(message)) => {
                            current = Some(worker);
                            Err(run_error(message))
                        }
                        Err(why) => {
                            let status = worker.0.finish();
                            Err(run_error(format!(
                                "the worker process died ({status}): {why}"
                            )))
                        }
                    };
                    match result {
                        Ok(row) => {
                            if let Err(e) = writer.append(&row) {
                                give_up(e);
                                break;
                            }
                            done(Ok(&row));
                        }
                        Err(e) => {
                            done(Err(&e));
                            errors
                                .lock()
                                .expect("no panics hold it")
                                .push((point.index, e));
                        }
                    }
                }
                // Dropping the worker closes its input and waits for it.
                drop(current);
            });
        }
    });
    if let Some(e) = fatal.into_inner().expect("no panics hold it") {
        return Err(e);
    }
    let mut errors = errors.into_inner().expect("no panics hold it");
    errors.sort_by_key(|(index, _)| *index);
    Ok(errors.into_iter().map(|(_, e)| e).collect())
}

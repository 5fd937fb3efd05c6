//! Running points: one closed loop per point, on a pool of `jobs` worker threads, each
//! point with its own renderer.

use super::{Point, ResultRow, ResultsWriter, Sweep, SweepError};
use crate::camera::Backend;
use crate::closed_loop::ClosedLoop;
use crate::report::Summary;
use rayon::prelude::*;
use std::time::Instant;

/// Runs one point through the closed loop and returns its row.
pub fn run_point(sweep: &Sweep, point: &Point, backend: Backend) -> Result<ResultRow, SweepError> {
    let fail = |message: String| SweepError::Run {
        point: point.describe(),
        message,
    };
    let scenario = sweep.scenario(point)?;
    let started = Instant::now();
    let mut looped = ClosedLoop::new(&scenario, backend, false).map_err(|e| fail(e.to_string()))?;
    let mut records = Vec::with_capacity(looped.frames() as usize);
    while let Some(out) = looped.step().map_err(|e| fail(e.to_string()))? {
        records.push(out.record);
    }
    let wall_s = started.elapsed().as_secs_f64();
    let mut summary = Summary::compute(
        &scenario.name,
        scenario.seed,
        &records,
        &scenario.expect,
        wall_s,
    );
    summary.timing = Some(looped.timing());
    Ok(ResultRow::new(point, &summary))
}

/// Runs `points` on `jobs` threads, appending each row to `writer` as soon as its point
/// finishes and then calling `done` with it (or with the error). Returns the errors of the
/// points that could not run; the others are all written.
pub fn run_points(
    sweep: &Sweep,
    points: &[&Point],
    jobs: usize,
    backend: Backend,
    writer: &ResultsWriter,
    done: impl Fn(Result<&ResultRow, &SweepError>) + Sync,
) -> Result<Vec<SweepError>, SweepError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.max(1))
        .thread_name(|i| format!("sweep-{i}"))
        .build()
        .map_err(|e| SweepError::Run {
            point: "(pool)".into(),
            message: e.to_string(),
        })?;
    let results: Vec<Result<(), SweepError>> = pool.install(|| {
        points
            .par_iter()
            // One point per task: points take seconds, so balance beats batching.
            .with_max_len(1)
            .map(|point| {
                let row = run_point(sweep, point, backend);
                match row {
                    Ok(row) => {
                        writer.append(&row)?;
                        done(Ok(&row));
                        Ok(())
                    }
                    Err(e) => {
                        done(Err(&e));
                        Err(e)
                    }
                }
            })
            .collect()
    });
    let mut errors = Vec::new();
    for r in results {
        match r {
            Ok(()) => {}
            // A results file that cannot be written stops the sweep's verdict outright.
            Err(e @ SweepError::Io { .. }) => return Err(e),
            Err(e) => errors.push(e),
        }
    }
    Ok(errors)
}

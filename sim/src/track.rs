//! `carfollow track`: the tracker alone on a recorded image sequence.
//!
//! Frames are the PNG and PGM files of a folder, in natural order of their names, converted
//! to grey. Each frame's result is written to the CSV as soon as it is known (and flushed), so
//! a frame that fails mid-run loses none of the rows before it.

use crate::overlay::draw_overlay;
use crate::report::csv_writer;
use anyhow::{bail, Context};
use image::GrayImage;
use indicatif::{ProgressBar, ProgressStyle};
use std::fs::File;

use std::path::{Path, PathBuf};
use std::time::Instant;
use tracker::{
    Camera, GrayView, Location, Status, TargetModel, TrackOutput, Tracker, TrackerConfig,
};

/// Everything one run needs.
#[derive(Clone, Debug)]
pub struct TrackJob {
    /// The folder of frames.
    pub frames_dir: PathBuf,
    /// The target model.
    pub model: TargetModel,
    /// Focal length in pixels.
    pub focal_px: f64,
    /// Pixel size on the sensor, millimetres (only the ratio to the focal length matters
    /// for stage 8; it is kept so the camera is a real one).
    pub pixel_size_mm: f64,
    /// Image centre, pixels; `None` for the middle of the frame.
    pub image_center_px: Option<[f64; 2]>,
    /// The teleoperator's placement in the first frame; `None` lets robust mode search the
    /// whole image for the target.
    pub init: Option<Location>,
    /// Tracker settings.
    pub config: TrackerConfig,
    /// The CSV to write.
    pub out_csv: PathBuf,
    /// Where to write overlay PNGs, if anywhere.
    pub overlay_dir: Option<PathBuf>,
    /// Show a progress bar (on a terminal).
    pub progress: bool,
}

/// What a run did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TrackSummary {
    /// Frames processed.
    pub frames: usize,
    /// Frames in each status: tracking, coasting, lost.
    pub tracking: usize,
    /// Frames coasting.
    pub coasting: usize,
    /// Frames lost.
    pub lost: usize,
    /// Acquisitions and re-acquisitions by search (robust mode).
    pub acquisitions: usize,
    /// Median wall time of one tracker step, microseconds.
    pub median_step_us: f64,
}

/// The frame files of a folder: `.png` and `.pgm` (any case), in natural order of their
/// names (digits by number: `frame_2` before `frame_10`, as zero-padded names sort too).
pub fn frame_files(dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let entries = std::fs::read_dir(dir)
        .with_context(|| format!("{}: cannot read the frames folder", dir.display()))?;
    let mut files = Vec::new();
    for entry in entries {
        let path = entry
            .with_context(|| format!("{}: cannot list the frames folder", dir.display()))?
            .path();
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if path.is_file() && matches!(ext.as_deref(), Some("png" | "pgm")) {
            files.push(path);
        }
    }
    files.sort_by_cached_key(|p| {
        let name = p.file_name().unwrap_or_default();
        (natural_key(&name.to_string_lossy()), name.to_owned())
    });
    if files.is_empty() {
        bail!("{}: no PNG or PGM frames in this folder", dir.display());
    }
    Ok(files)
}

/// A file name's natural sort key: its runs of digits as numbers (leading zeros aside),
/// the rest as text.
fn natural_key(name: &str) -> Vec<(String, u128, usize)> {
    let mut key = Vec::new();
    let mut rest = name;
    while !rest.is_empty() {
        let text_len = rest
            .find(|c: char| c.is_ascii_digit())
            .unwrap_or(rest.len());
        let (text, tail) = rest.split_at(text_len);
        let digits_len = tail
            .find(|c: char| !c.is_ascii_digit())
            .unwrap_or(tail.len());
        let (digits, tail) = tail.split_at(digits_len);
        let trimmed = digits.trim_start_matches('0');
        // Runs too long for a number sort by length, then as text.
        let number = if trimmed.is_empty() {
            0
        } else {
            trimmed.parse::<u128>().unwrap_or(u128::MAX)
        };
        key.push((text.to_string(), number, trimmed.len()));
        rest = tail;
    }
    key
}

/// Reads one frame as 8-bit grey (colour is converted by luminance).
pub fn read_frame(path: &Path) -> anyhow::Result<GrayImage> {
    let img =
        image::open(path).with_context(|| format!("{}: cannot read frame", path.display()))?;
    Ok(img.into_luma8())
}

/// The largest scale `--init` may give: the target 100 times its size at the nominal range.
const MAX_INIT_SCALE: f64 = 100.0;

/// The CSV header: frame, estimate and status first, then the rest.
fn header(model: &TargetModel) -> Vec<String> {
    let mut h: Vec<String> = [
        "frame",
        "cx",
        "cy",
        "scale",
        "status",
        "t_s",
        "measured",
        "w_x",
        "w_y",
        "w_scale",
        "fit_residual",
        "features_used",
        "pred_cx",
        "pred_cy",
        "pred_scale",
        "next_cx",
        "next_cy",
        "next_scale",
        "x_m",
        "y_m",
        "z_m",
        "window_x0",
        "window_y0",
        "window_x1",
        "window_y1",
        "window_size",
        "coverage_h",
        "coverage_v",
        "edge_threshold",
        "searched",
        "event",
    ]
    .map(String::from)
    .to_vec();
    for j in 0..model.segments().len() {
        h.push(format!("f{j}_points"));
        h.push(format!("f{j}_confidence"));
    }
    // Each feature's σ² of eq. 13 (empty where no point was associated).
    for j in 0..model.segments().len() {
        h.push(format!("f{j}_sigma2"));
    }
    h
}

/// One row; `features` is the model's segment count (a frame without a measurement, in a
/// search, has fewer located features: their columns are left empty).
fn row(out: &TrackOutput, features: usize) -> Vec<String> {
    let e = out.estimate;
    let (measured, w, residual, used) = match out.measurement {
        Some(m) => (1, m.confidence, m.residual, m.features_used),
        None => (0, [0.0; 3], f64::NAN, 0),
    };
    let [x, y, z] = out.position_3d;
    let (p, n, win) = (out.predicted, out.next, out.window);
    let mut r = vec![
        out.frame.to_string(),
        format!("{:.4}", e.c_x),
        format!("{:.4}", e.c_y),
        format!("{:.6}", e.scale),
        out.status.as_str().to_string(),
        format!("{:.6}", out.t_s),
        measured.to_string(),
        format!("{:.5}", w[0]),
        format!("{:.5}", w[1]),
        format!("{:.5}", w[2]),
        format!("{residual:.5}"),
        used.to_string(),
        format!("{:.4}", p.c_x),
        format!("{:.4}", p.c_y),
        format!("{:.6}", p.scale),
        format!("{:.4}", n.c_x),
        format!("{:.4}", n.c_y),
        format!("{:.6}", n.scale),
        format!("{x:.4}"),
        format!("{y:.4}"),
        format!("{z:.4}"),
        win.x0.to_string(),
        win.y0.to_string(),
        win.x1.to_string(),
        win.y1.to_string(),
        win.size_index.to_string(),
        format!("{:.3}", out.coverage[0]),
        format!("{:.3}", out.coverage[1]),
        format!("{:.2}", out.edge_threshold),
        u8::from(out.searched).to_string(),
        out.event.map_or("", |e| e.as_str()).to_string(),
    ];
    for j in 0..features {
        match out.features.get(j) {
            Some(f) => {
                r.push(f.points.to_string());
                r.push(format!("{:.5}", f.confidence));
            }
            None => r.extend([String::new(), String::new()]),
        }
    }
    for j in 0..features {
        r.push(
            out.features
                .get(j)
                .and_then(|f| f.variance)
                .map_or(String::new(), |v| format!("{v:.6}")),
        );
    }
    r
}

/// An output of `track` that could not be written (the CSV, the overlay folder or an
/// overlay): the run could not complete, where every other error is bad input.
#[derive(Debug, thiserror::Error)]
#[error(transparent)]
pub struct TrackOutputError(pub anyhow::Error);

/// `e` as a [`TrackOutputError`].
fn output(e: anyhow::Error) -> anyhow::Error {
    anyhow::Error::new(TrackOutputError(e))
}

/// Runs the tracker over the folder, writing the CSV (and overlays) as it goes. An error
/// writing them is a [`TrackOutputError`].
pub fn run(job: &TrackJob) -> anyhow::Result<TrackSummary> {
    let files = frame_files(&job.frames_dir)?;
    let first = read_frame(&files[0])?;
    let (width, height) = first.dimensions();
    let inside = |[x, y]: [f64; 2]| {
        (0.0..f64::from(width)).contains(&x) && (0.0..f64::from(height)).contains(&y)
    };
    if let Some(init) = &job.init {
        if !inside([init.c_x, init.c_y]) || init.scale > MAX_INIT_SCALE {
            bail!(
                "--init {},{},{}: the centre must lie in the {width}×{height} frame and the \
                 scale be at most {MAX_INIT_SCALE}",
                init.c_x,
                init.c_y,
                init.scale
            );
        }
    }
    if let Some(c) = job.image_center_px.filter(|&c| !inside(c)) {
        bail!(
            "--center {},{}: the image centre must lie in the {width}×{height} frame",
            c[0],
            c[1]
        );
    }
    let camera = Camera {
        focal_length_mm: job.focal_px * job.pixel_size_mm,
        pixel_size_mm: [job.pixel_size_mm; 2],
        image_center_px: job.image_center_px.unwrap_or([
            (f64::from(width) - 1.0) / 2.0,
            (f64::from(height) - 1.0) / 2.0,
        ]),
    };
    let mut tracker = match job.init {
        Some(init) => Tracker::new(job.model.clone(), camera, job.config.clone(), init),
        None => Tracker::new_searching(job.model.clone(), camera, job.config.clone()),
    }
    .context("cannot start the tracker")?;
    if let Some(dir) = &job.overlay_dir {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create the overlay folder", dir.display()))
            .map_err(output)?;
    }
    let file = File::create(&job.out_csv)
        .with_context(|| format!("{}: cannot create the CSV", job.out_csv.display()))
        .map_err(output)?;
    let mut csv = csv_writer(file);
    let write_err = |e: std::io::Error| {
        output(anyhow::Error::new(e).context(format!("{}: cannot write", job.out_csv.display())))
    };
    csv.write_record(header(&job.model))
        .map_err(|e| write_err(e.into()))?;
    csv.flush().map_err(write_err)?;

    let bar = if job.progress {
        ProgressBar::new(files.len() as u64)
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{elapsed_precise} [{bar:40}] {pos}/{len} frames {per_sec} {msg}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    let mut summary = TrackSummary::default();
    let mut step_us = Vec::with_capacity(files.len());
    let mut next_image = Some(first);
    for (k, path) in files.iter().enumerate() {
        let image = match next_image.take() {
            Some(img) => img,
            None => read_frame(path)?,
        };
        if image.dimensions() != (width, height) {
            bail!(
                "{}: frame is {}×{}, but the first frame ({}) is {width}×{height}",
                path.display(),
                image.width(),
                image.height(),
                files[0].display()
            );
        }
        let view = GrayView::new(width as usize, height as usize, image.as_raw())
            .with_context(|| format!("{}: unusable frame", path.display()))?;
        let t_s = k as f64 / job.config.rate_hz;
        let started = Instant::now();
        let (out, edges) = if job.overlay_dir.is_some() {
            tracker.step_with_diagnostics(view, t_s)
        } else {
            (tracker.step(view, t_s), Vec::new())
        };
        step_us.push(started.elapsed().as_secs_f64() * 1e6);
        csv.write_record(row(&out, job.model.segments().len()))
            .map_err(|e| write_err(e.into()))?;
        csv.flush().map_err(write_err)?;
        if let Some(dir) = &job.overlay_dir {
            let name = path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            let target = dir.join(format!("{name}.png"));
            draw_overlay(&image, &out, &edges)
                .save(&target)
                .with_context(|| format!("{}: cannot write overlay", target.display()))
                .map_err(output)?;
        }
        summary.frames += 1;
        match out.status {
            Status::Tracking => summary.tracking += 1,
            Status::Coasting => summary.coasting += 1,
            Status::Lost => summary.lost += 1,
        }
        summary.acquisitions += usize::from(out.event.is_some_and(|e| e.is_acquisition()));
        bar.set_message(out.status.as_str());
        bar.inc(1);
    }
    bar.finish_and_clear();
    step_us.sort_by(f64::total_cmp);
    summary.median_step_us = step_us[step_us.len() / 2];
    Ok(summary)
}

/// Parses `CX,CY,SCALE`.
pub fn parse_location(text: &str) -> anyhow::Result<Location> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let numbers: Option<Vec<f64>> = parts.iter().map(|p| p.parse::<f64>().ok()).collect();
    match numbers.as_deref() {
        Some(&[c_x, c_y, scale])
            if [c_x, c_y, scale].iter().all(|v| v.is_finite()) && scale > 0.0 =>
        {
            Ok(Location::new(c_x, c_y, scale))
        }
        Some(&[_, _, scale]) if scale <= 0.0 => {
            bail!("expected CX,CY,SCALE with SCALE > 0, got `{text}`")
        }
        _ => bail!(
            "expected CX,CY,SCALE (three comma-separated numbers, pixels and scale), got `{text}`"
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_sort_in_natural_order() {
        let mut names = vec![
            "frame_10",
            "frame_2",
            "frame_1",
            "frame_0",
            "a",
            "frame_002b",
        ];
        names.sort_by_key(|n| natural_key(n));
        assert_eq!(
            names,
            [
                "a",
                "frame_0",
                "frame_1",
                "frame_2",
                "frame_002b",
                "frame_10"
            ]
        );
        // Zero-padded names keep their plain order.
        let mut padded: Vec<String> = (0..120).map(|k| format!("frame_{k:04}.png")).collect();
        let plain = padded.clone();
        padded.reverse();
        padded.sort_by_key(|n| natural_key(n));
        assert_eq!(padded, plain);
    }
}

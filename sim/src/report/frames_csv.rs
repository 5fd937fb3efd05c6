//! `frames.csv`: one row per camera frame, written and flushed as each frame is recorded, so a
//! crash keeps every frame that ran.
//!
//! Format: a header line, then one comma-separated row per frame, `\n` line ends. Numbers are
//! plain decimals (Rust's shortest round-trip form, never an exponent); a non-finite number (an
//! estimate the tracker did not make) is an empty field, which pandas reads as NaN and a
//! spreadsheet as blank. Booleans are `0`/`1`. The status is the tracker's own word
//! (`tracking`, `coasting`, `lost`). Text is quoted only when it needs to be (RFC 4180).

use std::fmt::Write as _;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use super::ReportError;
use crate::record::FrameRecord;

/// The columns of `frames.csv`, in order. The order is stable: new columns go at the end.
pub const FRAMES_CSV_COLUMNS: [&str; 40] = [
    "frame",
    "t_s",
    "true_range_m",
    "est_range_m",
    "true_lateral_m",
    "est_lateral_m",
    "true_cx_px",
    "est_cx_px",
    "true_cy_px",
    "est_cy_px",
    "true_scale",
    "est_scale",
    "target_in_view",
    "confidence_x",
    "confidence_y",
    "confidence_scale",
    "status",
    "lost_truth",
    "gap_m",
    "chase_speed_mps",
    "lead_speed_mps",
    "steering_rad",
    "throttle",
    "brake",
    "lateral_deviation_m",
    "chase_distance_m",
    "chase_x_m",
    "chase_z_m",
    "lead_x_m",
    "lead_z_m",
    "collision",
    "chase_mode",
    "coverage_h",
    "coverage_v",
    "coverage_gain",
    "tracker_event",
    "fit_residual",
    "loss_cause",
    "camera_pan_deg",
    "desired_gap_m",
];

/// The name of the column after [`FRAMES_CSV_COLUMNS`] holding feature `j`'s σ² (eq. 13),
/// one per segment of the target model: `sigma2_f0`, `sigma2_f1`, ...
pub fn sigma2_column(j: usize) -> String {
    format!("sigma2_f{j}")
}

/// A streaming writer of `frames.csv`.
#[derive(Debug)]
pub struct FramesCsv {
    path: PathBuf,
    out: BufWriter<File>,
    line: String,
    features: usize,
}

impl FramesCsv {
    /// Creates (or truncates) the file and writes the header: [`FRAMES_CSV_COLUMNS`], then
    /// one σ² column per feature of a model with `features` segments ([`sigma2_column`]).
    pub fn create(path: impl AsRef<Path>, features: usize) -> Result<FramesCsv, ReportError> {
        let path = path.as_ref().to_path_buf();
        let file = File::create(&path).map_err(ReportError::io(&path))?;
        let mut csv = FramesCsv {
            path,
            out: BufWriter::new(file),
            line: String::with_capacity(512),
            features,
        };
        let mut header = FRAMES_CSV_COLUMNS.join(",");
        for j in 0..features {
            header.push(',');
            header.push_str(&sigma2_column(j));
        }
        csv.write_line(header)?;
        Ok(csv)
    }

    /// The file being written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Writes one row for `r` and flushes it to the file.
    pub fn write(&mut self, r: &FrameRecord) -> Result<(), ReportError> {
        let line = format_row(r, self.features, std::mem::take(&mut self.line));
        self.write_line(line)
    }

    fn write_line(&mut self, mut line: String) -> Result<(), ReportError> {
        line.push('\n');
        let result = self
            .out
            .write_all(line.as_bytes())
            .and_then(|()| self.out.flush())
            .map_err(ReportError::io(&self.path));
        line.clear();
        self.line = line;
        result
    }
}

/// One row, without its line end, in [`FRAMES_CSV_COLUMNS`] order, then `features` σ²
/// columns (empty where the record has none).
fn format_row(r: &FrameRecord, features: usize, mut s: String) -> String {
    s.clear();
    let _ = write!(s, "{}", r.frame);
    for v in [
        r.t_s,
        r.true_range_m,
        r.est_range_m,
        r.true_lateral_m,
        r.est_lateral_m,
        r.true_cx,
        r.est_cx,
        r.true_cy,
        r.est_cy,
        r.true_scale,
        r.est_scale,
    ] {
        s.push(',');
        num(&mut s, v);
    }
    flag(&mut s, r.target_in_view);
    for v in r.confidence {
        s.push(',');
        num(&mut s, v);
    }
    s.push(',');
    s.push_str(r.status.as_str());
    flag(&mut s, r.lost_truth);
    for v in [
        r.gap_m,
        r.chase_speed_mps,
        r.lead_speed_mps,
        r.steering_rad,
        r.throttle,
        r.brake,
        r.lateral_deviation_m,
        r.chase_distance_m,
        r.chase_xz[0],
        r.chase_xz[1],
        r.lead_xz[0],
        r.lead_xz[1],
    ] {
        s.push(',');
        num(&mut s, v);
    }
    flag(&mut s, r.collision);
    s.push(',');
    text(&mut s, &r.chase_mode);
    for v in [r.coverage[0], r.coverage[1], r.coverage_gain] {
        s.push(',');
        num(&mut s, v);
    }
    s.push(',');
    text(&mut s, &r.tracker_event);
    s.push(',');
    num(&mut s, r.fit_residual);
    s.push(',');
    s.push_str(r.loss_cause.as_str());
    for v in [r.camera_pan_deg, r.desired_gap_m] {
        s.push(',');
        num(&mut s, v);
    }
    for j in 0..features {
        s.push(',');
        num(&mut s, r.feature_sigma2.get(j).copied().unwrap_or(f64::NAN));
    }
    s
}

fn num(s: &mut String, v: f64) {
    if v.is_finite() {
        // Normalise -0 so that a sign bit never changes the file.
        let v = if v == 0.0 { 0.0 } else { v };
        let _ = write!(s, "{v}");
    }
}

fn flag(s: &mut String, b: bool) {
    s.push_str(if b { ",1" } else { ",0" });
}

fn text(s: &mut String, t: &str) {
    if t.contains([',', '"', '\n', '\r']) || t.starts_with(' ') || t.ends_with(' ') {
        s.push('"');
        s.push_str(&t.replace('"', "\"\""));
        s.push('"');
    } else {
        s.push_str(t);
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::record::TrackerStatus;

    /// A plausible record at frame `i` (15 Hz): 10 m gap, tracking, on the path.
    pub(crate) fn record(i: u64) -> FrameRecord {
        let t = i as f64 / 15.0;
        FrameRecord {
            frame: i,
            t_s: t,
            true_cx: 320.0,
            true_cy: 240.0,
            true_scale: 1.0,
            true_range_m: 10.0,
            true_lateral_m: 0.0,
            target_in_view: true,
            est_cx: 321.0,
            est_cy: 239.5,
            est_scale: 1.01,
            est_range_m: 10.25,
            est_lateral_m: 0.05,
            confidence: [0.9, 0.8, 0.7],
            status: TrackerStatus::Tracking,
            lost_truth: false,
            gap_m: 10.0,
            chase_speed_mps: 5.0,
            lead_speed_mps: 5.0,
            steering_rad: 0.0,
            throttle: 0.3,
            brake: 0.0,
            lateral_deviation_m: 0.1,
            chase_distance_m: 5.0 * t,
            chase_xz: [5.0 * t, 0.0],
            lead_xz: [5.0 * t + 10.0, 0.0],
            collision: false,
            chase_mode: "following".into(),
            coverage: [0.95, 0.9],
            coverage_gain: 0.25,
            tracker_event: String::new(),
            fit_residual: 0.5,
            feature_sigma2: vec![0.1, f64::NAN, 0.25],
            loss_cause: crate::record::LossCause::None,
            camera_pan_deg: 0.0,
            desired_gap_m: 10.0,
        }
    }

    fn parse(line: &str) -> Vec<&str> {
        line.split(',').collect()
    }

    #[test]
    fn header_then_one_flushed_row_per_frame() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("frames.csv");
        let mut csv = FramesCsv::create(&path, 3).unwrap();
        csv.write(&record(0)).unwrap();
        let mut r = record(1);
        r.est_range_m = f64::NAN;
        r.status = TrackerStatus::Coasting;
        r.lost_truth = true;
        r.collision = true;
        csv.write(&r).unwrap();
        // No drop, no finish: the rows must already be in the file.
        let text = std::fs::read_to_string(&path).unwrap();
        drop(csv);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3, "{text}");
        assert_eq!(
            lines[0],
            format!(
                "{},sigma2_f0,sigma2_f1,sigma2_f2",
                FRAMES_CSV_COLUMNS.join(",")
            )
        );
        for line in &lines {
            assert_eq!(parse(line).len(), FRAMES_CSV_COLUMNS.len() + 3, "{line}");
        }
        let col = |name: &str| FRAMES_CSV_COLUMNS.iter().position(|c| *c == name).unwrap();
        let row0 = parse(lines[1]);
        assert_eq!(row0[col("frame")], "0");
        assert_eq!(row0[col("t_s")], "0");
        assert_eq!(row0[col("est_range_m")], "10.25");
        assert_eq!(row0[col("confidence_y")], "0.8");
        assert_eq!(row0[col("status")], "tracking");
        assert_eq!(row0[col("lost_truth")], "0");
        assert_eq!(row0[col("lead_x_m")], "10");
        assert_eq!(row0[col("chase_mode")], "following");
        let row1 = parse(lines[2]);
        assert_eq!(row1[col("t_s")], (1.0f64 / 15.0).to_string());
        assert_eq!(row1[col("est_range_m")], "");
        assert_eq!(row1[col("status")], "coasting");
        assert_eq!(row1[col("lost_truth")], "1");
        assert_eq!(row1[col("collision")], "1");
        assert_eq!(row0[col("coverage_v")], "0.9");
        assert_eq!(row0[col("tracker_event")], "");
        assert_eq!(row0[col("fit_residual")], "0.5");
        let n = FRAMES_CSV_COLUMNS.len();
        assert_eq!(&row0[n..], ["0.1", "", "0.25"]);
    }

    #[test]
    fn numbers_are_plain_and_text_is_quoted_when_needed() {
        let mut r = record(2);
        r.gap_m = 1e-7;
        r.throttle = -0.0;
        r.brake = 1e21;
        r.chase_mode = "stop, \"now\"".into();
        let row = format_row(&r, 0, String::new());
        assert!(row.contains(",0.0000001,"), "{row}");
        assert!(row.contains(",1000000000000000000000,"), "{row}");
        assert!(!row.contains("-0"), "{row}");
        let numbers = &row[..row.rfind(",\"stop").unwrap()];
        assert!(!numbers.contains(['e', 'E']), "{row}");
        assert!(row.contains(",\"stop, \"\"now\"\"\","), "{row}");
    }

    #[test]
    fn create_names_the_file_on_error() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("missing-dir").join("frames.csv");
        let err = FramesCsv::create(&path, 3).unwrap_err();
        assert!(err.to_string().contains("frames.csv"), "{err}");
    }
}

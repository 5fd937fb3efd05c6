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
use std::path::{Path, PathBuf};

use super::ReportError;
use sim_core::FrameRecord;

/// The columns of `frames.csv`, in order. The order is stable: new columns go at the end.
pub const FRAMES_CSV_COLUMNS: [&str; 42] = [
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
    "target_partly_out_of_view",
    "false_alarm",
];

/// The columns after the σ² columns in a run with traffic (other vehicles or events; see
/// `sim_core::TrafficFrame`): the vehicle in the chase's path (empty when the road ahead
/// is clear), the gap to it and the time to collision with it (empty when not closing),
/// the vehicle the tracker holds (empty when none), and the events that started or ended
/// since the previous frame (`vehicle/event:started`, separated by `;`).
pub const TRAFFIC_COLUMNS: [&str; 5] = [
    "path_vehicle",
    "path_gap_m",
    "path_ttc_s",
    "tracked_vehicle",
    "event",
];

/// The name of the column after [`FRAMES_CSV_COLUMNS`] holding feature `j`'s σ² (eq. 13),
/// one per segment of the target model: `sigma2_f0`, `sigma2_f1`, ...
pub fn sigma2_column(j: usize) -> String {
    format!("sigma2_f{j}")
}

/// A streaming writer of `frames.csv`, on the `csv` crate's writer (RFC 4180 quoting, `\n`
/// line ends).
#[derive(Debug)]
pub struct FramesCsv {
    path: PathBuf,
    out: csv::Writer<File>,
    features: usize,
    /// Whether the rows end with the [`TRAFFIC_COLUMNS`].
    traffic: bool,
    /// The row being written, one field at a time, reused.
    row: Row,
}

impl FramesCsv {
    /// Creates (or truncates) the file and writes the header: [`FRAMES_CSV_COLUMNS`], then
    /// one σ² column per feature of a model with `features` segments ([`sigma2_column`]),
    /// then, with `traffic`, the [`TRAFFIC_COLUMNS`].
    pub fn create(
        path: impl AsRef<Path>,
        features: usize,
        traffic: bool,
    ) -> Result<FramesCsv, ReportError> {
        let path = path.as_ref().to_path_buf();
        let file = File::create(&path).map_err(ReportError::io(&path))?;
        let mut csv = FramesCsv {
            path,
            out: csv_writer(file),
            features,
            traffic,
            row: Row::default(),
        };
        let traffic_columns = if traffic { &TRAFFIC_COLUMNS[..] } else { &[] };
        let header: Vec<String> = FRAMES_CSV_COLUMNS
            .iter()
            .map(|c| c.to_string())
            .chain((0..features).map(sigma2_column))
            .chain(traffic_columns.iter().map(|c| c.to_string()))
            .collect();
        csv.out
            .write_record(&header)
            .map_err(|e| csv_error(&csv.path, e))?;
        csv.flush()?;
        Ok(csv)
    }

    /// The file being written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Writes one row for `r` and flushes it to the file.
    pub fn write(&mut self, r: &FrameRecord) -> Result<(), ReportError> {
        self.row.fill(r, self.features);
        if self.traffic {
            self.row.traffic(r.traffic.as_ref());
        }
        self.out
            .write_record(&self.row.fields)
            .map_err(|e| csv_error(&self.path, e))?;
        self.flush()
    }

    fn flush(&mut self) -> Result<(), ReportError> {
        self.out.flush().map_err(ReportError::io(&self.path))
    }
}

/// A CSV writer as carfollow's CSV files are written: comma-separated, `\n` line ends,
/// quoted only where needed (RFC 4180).
pub fn csv_writer<W: std::io::Write>(out: W) -> csv::Writer<W> {
    csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(out)
}

/// A `csv` error as the report's: what it is, on the file.
fn csv_error(path: &Path, e: csv::Error) -> ReportError {
    match e.into_kind() {
        csv::ErrorKind::Io(e) => ReportError::io(path)(e),
        other => ReportError::io(path)(std::io::Error::other(format!("{other:?}"))),
    }
}

/// One row's fields as text, their buffers kept from row to row.
#[derive(Debug, Default)]
struct Row {
    fields: Vec<String>,
    next: usize,
}

impl Row {
    /// The fields of `r`, in [`FRAMES_CSV_COLUMNS`] order, then `features` σ² columns
    /// (empty where the record has none).
    fn fill(&mut self, r: &FrameRecord, features: usize) {
        self.next = 0;
        self.text(&r.frame.to_string());
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
            self.num(v);
        }
        self.flag(r.target_in_view);
        for v in r.confidence {
            self.num(v);
        }
        self.text(r.status.as_str());
        self.flag(r.lost_truth);
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
            self.num(v);
        }
        self.flag(r.collision);
        self.text(&r.chase_mode);
        for v in [r.coverage[0], r.coverage[1], r.coverage_gain] {
            self.num(v);
        }
        self.text(&r.tracker_event);
        self.num(r.fit_residual);
        self.text(r.loss_cause.as_str());
        for v in [r.camera_pan_deg, r.desired_gap_m] {
            self.num(v);
        }
        self.flag(r.target_partly_out_of_view);
        self.flag(r.false_alarm);
        for j in 0..features {
            self.num(r.feature_sigma2.get(j).copied().unwrap_or(f64::NAN));
        }
        self.fields.truncate(self.next);
    }

    /// The [`TRAFFIC_COLUMNS`] of a record (empty fields without its traffic).
    fn traffic(&mut self, t: Option<&sim_core::TrafficFrame>) {
        fn name(v: Option<&String>) -> &str {
            v.map_or("", String::as_str)
        }
        match t {
            Some(t) => {
                self.text(name(t.path_vehicle.as_ref()));
                self.num(t.path_gap_m);
                self.num(t.path_ttc_s);
                self.text(name(t.tracked_vehicle.as_ref()));
                let events = t.events.join(";");
                self.text(&events);
            }
            None => {
                for _ in TRAFFIC_COLUMNS {
                    self.text("");
                }
            }
        }
        self.fields.truncate(self.next);
    }

    /// The next field, cleared.
    fn field(&mut self) -> &mut String {
        if self.next == self.fields.len() {
            self.fields.push(String::new());
        }
        self.next += 1;
        let field = &mut self.fields[self.next - 1];
        field.clear();
        field
    }

    fn text(&mut self, t: &str) {
        self.field().push_str(t);
    }

    /// A number as a plain decimal (Rust's shortest round-trip form); empty when not finite.
    fn num(&mut self, v: f64) {
        let field = self.field();
        if v.is_finite() {
            // Normalise -0 so that a sign bit never changes the file.
            let v = if v == 0.0 { 0.0 } else { v };
            let _ = write!(field, "{v}");
        }
    }

    fn flag(&mut self, b: bool) {
        self.field().push(if b { '1' } else { '0' });
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use sim_core::TrackerStatus;

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
            target_partly_out_of_view: false,
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
            loss_cause: sim_core::LossCause::None,
            camera_pan_deg: 0.0,
            desired_gap_m: 10.0,
            false_alarm: false,
            traffic: None,
        }
    }

    fn parse(line: &str) -> Vec<&str> {
        line.split(',').collect()
    }

    #[test]
    fn header_then_one_flushed_row_per_frame() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("frames.csv");
        let mut csv = FramesCsv::create(&path, 3, false).unwrap();
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
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("frames.csv");
        let mut csv = FramesCsv::create(&path, 0, false).unwrap();
        csv.write(&r).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let row = text.lines().nth(1).unwrap();
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
        let err = FramesCsv::create(&path, 3, false).unwrap_err();
        assert!(err.to_string().contains("frames.csv"), "{err}");
    }
}

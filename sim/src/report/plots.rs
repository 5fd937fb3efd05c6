//! The run's PNG plots, drawn with plotters on an in-memory bitmap and saved with `image`:
//!
//! - `gap.png`: the following distance over time, with the `[expect]` band shaded;
//! - `range.png`: the estimated range against the true range, lost frames shaded;
//! - `status.png`: a timeline with two lanes, the tracker's own status and the ground-truth
//!   judgement (on target, lost, lost out of view, on target with the target partly out of
//!   view, and not yet acquired: a searching tracker before it first held its target);
//! - `trajectories.png`: top-down paths of both vehicles, one metre the same length on both axes;
//! - `lateral_deviation.png`: the chase vehicle's distance from the lead's path, with its limit.
//!
//! Text uses DejaVu Sans, shipped in `sim/assets/` and compiled in: there is no system font
//! lookup, so a fresh machine draws the same pixels.

use std::error::Error;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::ranged1d::SegmentValue;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::summary::FramePeriod;
use super::ReportError;
use sim_core::{Expect, FrameRecord, LossCause, TrackerStatus};

/// The plot files written by [`write_plots`], in order.
pub const PLOT_FILES: [&str; 5] = [
    "gap.png",
    "range.png",
    "status.png",
    "trajectories.png",
    "lateral_deviation.png",
];

/// DejaVu Sans (Bitstream Vera licence, `sim/assets/DejaVuSans-LICENSE.txt`).
static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");
/// The family name every text style here uses.
const FONT_FAMILY: &str = "sans-serif";

/// Size of the time-series plots, pixels.
const WIDE: (u32, u32) = (1100, 500);
/// Width of the trajectory plot, and the range of its height, pixels.
const TOP_VIEW_WIDTH: u32 = 1100;
const TOP_VIEW_HEIGHT: [u32; 2] = [450, 1100];
/// Space around the trajectory plot's plotting area, pixels.
const TOP_VIEW_MARGIN: u32 = 15;
const TOP_VIEW_X_LABELS: u32 = 50;
const TOP_VIEW_Y_LABELS: u32 = 70;
const TOP_VIEW_TITLE: u32 = 50;
/// Title and label sizes, pixels.
const TITLE_PX: u32 = 24;
const LABEL_PX: u32 = 16;
const TICK_PX: u32 = 14;

const BLUE_LINE: RGBColor = RGBColor(31, 100, 200);
const TRUTH_LINE: RGBColor = RGBColor(20, 20, 20);
const LIMIT_LINE: RGBColor = RGBColor(200, 30, 30);
const BAND_FILL: RGBColor = RGBColor(200, 235, 200);
const LOST_FILL: RGBColor = RGBColor(250, 215, 215);
const TRACKING: RGBColor = RGBColor(40, 160, 60);
const COASTING: RGBColor = RGBColor(245, 165, 0);
const LOST: RGBColor = RGBColor(210, 30, 30);
const OUT_OF_VIEW: RGBColor = RGBColor(150, 150, 150);
const CHASE: RGBColor = RGBColor(31, 100, 200);
const LEAD: RGBColor = RGBColor(210, 60, 30);

const PARTLY_OUT: RGBColor = RGBColor(120, 200, 190);
/// A searching tracker that has not yet held its target: no loss of a track (pale violet,
/// apart from the losses' red and grey).
const NOT_ACQUIRED: RGBColor = RGBColor(190, 170, 225);

pub(crate) type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;
pub(crate) type DrawResult = Result<(), Box<dyn Error>>;

/// Draws every plot of [`PLOT_FILES`] into `dir`; returns the paths written.
pub fn write_plots(
    dir: &Path,
    scenario: &str,
    trace: &PlotTrace,
    expect: &Expect,
) -> Result<Vec<PathBuf>, ReportError> {
    register_font(dir)?;
    let rows = trace.rows();
    let records = &rows[..];
    let mut period = FramePeriod::default();
    for r in records {
        period.push(r.t_s);
    }
    let series = Series::new(records, period.period());
    let mut written = Vec::new();
    let mut plot = |file: &str, size, draw: &dyn Fn(&Area) -> DrawResult| {
        let path = dir.join(file);
        render(&path, size, draw)?;
        written.push(path);
        Ok::<(), ReportError>(())
    };
    plot(PLOT_FILES[0], WIDE, &|a| gap(a, scenario, &series, expect))?;
    plot(PLOT_FILES[1], WIDE, &|a| range(a, scenario, &series))?;
    plot(PLOT_FILES[2], (WIDE.0, 300), &|a| {
        status(a, scenario, &series)
    })?;
    plot(PLOT_FILES[3], trajectory_size(records), &|a| {
        trajectories(a, scenario, records)
    })?;
    plot(PLOT_FILES[4], WIDE, &|a| {
        lateral(a, scenario, &series, expect)
    })?;
    Ok(written)
}

pub(crate) fn register_font(dir: &Path) -> Result<(), ReportError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FONT_FAMILY, FontStyle::Normal, FONT).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(ReportError::Plot {
            path: dir.to_path_buf(),
            message: "the shipped font DejaVuSans.ttf is not a valid font".into(),
        })
    }
}

/// Draws on a white bitmap of `size` and saves it as PNG at `path`.
pub(crate) fn render(
    path: &Path,
    size: (u32, u32),
    draw: &dyn Fn(&Area) -> DrawResult,
) -> Result<(), ReportError> {
    let mut buf = vec![0u8; size.0 as usize * size.1 as usize * 3];
    {
        let area = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        let drawn = area
            .fill(&WHITE)
            .map_err(|e| e.into())
            .and_then(|()| draw(&area))
            .and_then(|()| area.present().map_err(|e| e.into()));
        drawn.map_err(|e: Box<dyn Error>| ReportError::Plot {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
    }
    let img = image::RgbImage::from_raw(size.0, size.1, buf).expect("buffer of the plot's size");
    img.save_with_format(path, image::ImageFormat::Png)
        .map_err(|source| ReportError::Image {
            path: path.to_path_buf(),
            source,
        })
}

/// What the plots draw of one frame (a few of its record's fields), or of a run of frames
/// merged by [`PlotRow::merge`].
#[derive(Clone, Copy, Debug, PartialEq)]
struct PlotRow {
    t_s: f64,
    gap_m: f64,
    true_range_m: f64,
    est_range_m: f64,
    lateral_deviation_m: f64,
    chase_xz: [f64; 2],
    lead_xz: [f64; 2],
    status: TrackerStatus,
    lost_truth: bool,
    lost_out_of_view: bool,
    /// Lost by the ground truth only before the first acquisition (`loss_cause` is
    /// `not_acquired` on every lost frame of the row, and some frame of it is lost).
    not_acquired: bool,
    partly_out_of_view: bool,
}

impl PlotRow {
    fn of(r: &FrameRecord) -> PlotRow {
        PlotRow {
            t_s: r.t_s,
            gap_m: r.gap_m,
            true_range_m: r.true_range_m,
            est_range_m: r.est_range_m,
            lateral_deviation_m: r.lateral_deviation_m,
            chase_xz: r.chase_xz,
            lead_xz: r.lead_xz,
            status: r.status,
            lost_truth: r.lost_truth,
            lost_out_of_view: r.lost_truth && r.loss_cause == LossCause::OutOfView,
            not_acquired: r.lost_truth && r.loss_cause == LossCause::NotAcquired,
            partly_out_of_view: r.target_partly_out_of_view,
        }
    }

    /// This row and the `later` one as one row, keeping what a plot must not hide: the
    /// start time and the positions of the earlier; the smaller gap; the larger lateral
    /// deviation; the ranges of the frame with the larger range error (a frame with no
    /// estimate counts as the largest, so the estimate's line still breaks there); the
    /// worse tracker status; and any loss or partial view of either (a loss after the first
    /// acquisition outweighing the search before it).
    fn merge(self, later: PlotRow) -> PlotRow {
        let error = |r: &PlotRow| {
            let e = (r.est_range_m - r.true_range_m).abs();
            if e.is_nan() {
                f64::INFINITY
            } else {
                e
            }
        };
        let ranges = if error(&later) > error(&self) {
            later
        } else {
            self
        };
        PlotRow {
            t_s: self.t_s,
            gap_m: self.gap_m.min(later.gap_m),
            true_range_m: ranges.true_range_m,
            est_range_m: ranges.est_range_m,
            lateral_deviation_m: self.lateral_deviation_m.max(later.lateral_deviation_m),
            chase_xz: self.chase_xz,
            lead_xz: self.lead_xz,
            status: worse(self.status, later.status),
            lost_truth: self.lost_truth || later.lost_truth,
            lost_out_of_view: self.lost_out_of_view || later.lost_out_of_view,
            not_acquired: (self.lost_truth || later.lost_truth)
                && (self.not_acquired || !self.lost_truth)
                && (later.not_acquired || !later.lost_truth),
            partly_out_of_view: self.partly_out_of_view || later.partly_out_of_view,
        }
    }
}

/// The worse of two statuses: lost, then coasting, then tracking.
fn worse(a: TrackerStatus, b: TrackerStatus) -> TrackerStatus {
    let rank = |s| match s {
        TrackerStatus::Tracking => 0,
        TrackerStatus::Coasting => 1,
        TrackerStatus::Lost => 2,
    };
    if rank(b) > rank(a) {
        b
    } else {
        a
    }
}

/// Rows a [`PlotTrace`] keeps before it halves them: 32 768 (36 minutes at 15 Hz, 2.9 MB).
const TRACE_ROWS: usize = 1 << 15;

/// What the plots need of a run, kept as the records come: [`write_plots`] draws from it at
/// the end.
///
/// Its memory is bounded. Up to 32 768 frames (36 minutes at 15 Hz) it keeps a row a frame,
/// so the plots are drawn frame by frame. At that many rows it merges them in pairs, and
/// from then on keeps a row for every two frames, then four, and so on: between 16 384 and
/// 32 768 rows (2.9 MB at most), far more than a plot has pixels across. A merged row keeps
/// the closest gap, the largest deviation and range error, the worse status and any loss of
/// its frames, so that a single lost frame still shows in `status.png` after a day's run.
#[derive(Clone, Debug)]
pub struct PlotTrace {
    rows: Vec<PlotRow>,
    /// Frames each row of `rows` stands for: a power of two.
    stride: u64,
    /// The frames since the last full row, merged, and how many they are (under `stride`).
    pending: Option<(PlotRow, u64)>,
    /// Rows kept before halving: [`TRACE_ROWS`], smaller in tests.
    cap: usize,
}

impl Default for PlotTrace {
    fn default() -> PlotTrace {
        PlotTrace::with_cap(TRACE_ROWS)
    }
}

impl PlotTrace {
    /// An empty trace.
    pub fn new() -> PlotTrace {
        PlotTrace::default()
    }

    fn with_cap(cap: usize) -> PlotTrace {
        PlotTrace {
            rows: Vec::new(),
            stride: 1,
            pending: None,
            cap: cap.max(2),
        }
    }

    /// The trace of `records`.
    pub fn of(records: &[FrameRecord]) -> PlotTrace {
        let mut trace = PlotTrace::new();
        for r in records {
            trace.push(r);
        }
        trace
    }

    /// Takes the next record.
    pub fn push(&mut self, r: &FrameRecord) {
        self.push_row(PlotRow::of(r));
    }

    fn push_row(&mut self, row: PlotRow) {
        let (merged, n) = match self.pending.take() {
            Some((earlier, n)) => (earlier.merge(row), n + 1),
            None => (row, 1),
        };
        if n < self.stride {
            self.pending = Some((merged, n));
            return;
        }
        self.rows.push(merged);
        if self.rows.len() >= self.cap {
            self.rows = self
                .rows
                .chunks(2)
                .map(|pair| match *pair {
                    [a, b] => a.merge(b),
                    [a] => a,
                    _ => unreachable!("chunks of two"),
                })
                .collect();
            self.stride *= 2;
        }
    }

    /// The rows to draw: the full ones, then the frames since.
    fn rows(&self) -> Vec<PlotRow> {
        let mut rows = self.rows.clone();
        rows.extend(self.pending.map(|(row, _)| row));
        rows
    }
}

/// Per-frame intervals and the time axis shared by the time-series plots.
struct Series<'r> {
    records: &'r [PlotRow],
    /// `[start, end)` of each frame's interval, seconds.
    spans: Vec<(f64, f64)>,
    t0: f64,
    t1: f64,
    period: f64,
}

impl<'r> Series<'r> {
    fn new(records: &'r [PlotRow], period: f64) -> Series<'r> {
        let spans: Vec<(f64, f64)> = records
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let end = records
                    .get(i + 1)
                    .map(|n| n.t_s)
                    .filter(|e| *e > r.t_s)
                    .unwrap_or(r.t_s + period);
                (r.t_s, end)
            })
            .collect();
        let t0 = records.first().map_or(0.0, |r| r.t_s);
        let t1 = spans.last().map_or(1.0, |s| s.1).max(t0 + period);
        Series {
            records,
            spans,
            t0,
            t1,
            period,
        }
    }

    /// `(t, f(r))` as polylines, broken where the value is not finite or frames are missing.
    fn lines(&self, f: impl Fn(&PlotRow) -> f64) -> Vec<Vec<(f64, f64)>> {
        let mut lines = Vec::new();
        let mut current: Vec<(f64, f64)> = Vec::new();
        let mut last_t = f64::NEG_INFINITY;
        for r in self.records {
            let v = f(r);
            let broken = r.t_s - last_t > 1.5 * self.period;
            if !v.is_finite() || broken {
                if current.len() > 1 {
                    lines.push(std::mem::take(&mut current));
                }
                current.clear();
            }
            if v.is_finite() {
                current.push((r.t_s, v));
            }
            last_t = r.t_s;
        }
        if current.len() > 1 {
            lines.push(current);
        } else if let Some(&p) = current.first() {
            lines.push(vec![p, (p.0 + self.period, p.1)]);
        }
        lines
    }

    /// Maximal runs of frames with the same class, as `(start, end, class)`.
    fn runs<C: PartialEq + Copy>(&self, class: impl Fn(&PlotRow) -> C) -> Vec<(f64, f64, C)> {
        let mut runs: Vec<(f64, f64, C)> = Vec::new();
        for (r, &(a, b)) in self.records.iter().zip(&self.spans) {
            let c = class(r);
            match runs.last_mut() {
                Some(last) if last.2 == c && (a - last.1).abs() < 1e-9 => last.1 = b,
                _ => runs.push((a, b, c)),
            }
        }
        runs
    }

    /// A padded value range covering `f` over the records and `extra` values.
    fn value_range(&self, f: impl Fn(&PlotRow) -> f64, extra: &[f64]) -> (f64, f64) {
        let values = self.records.iter().map(f).chain(extra.iter().copied());
        padded_range(values)
    }
}

fn padded_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = if hi - lo > 1e-9 {
        (hi - lo) * 0.05
    } else {
        0.5
    };
    // Quantities that never go negative (distances) keep zero as their floor.
    let floor = if lo >= 0.0 { 0.0 } else { f64::NEG_INFINITY };
    ((lo - pad).max(floor), hi + pad)
}

/// A tick label: at most three decimals (two significant digits under 0.001), no trailing
/// zeros, no "-0".
pub(crate) fn tick(v: &f64) -> String {
    // Three decimals, or for a tick under 0.001 (an axis of small values: 0.0004 m) two
    // significant digits, so that no tick of a small axis reads 0.
    let decimals = if *v != 0.0 && v.abs() < 1e-3 && v.is_finite() {
        (-v.abs().log10()).ceil() as usize + 1
    } else {
        3
    };
    let t = format!("{v:.decimals$}");
    let t = t.trim_end_matches('0').trim_end_matches('.');
    if t == "-0" {
        "0".into()
    } else {
        t.into()
    }
}

pub(crate) fn font(px: u32) -> TextStyle<'static> {
    (FONT_FAMILY, px).into_font().into()
}

fn title(scenario: &str, what: &str) -> String {
    format!("{scenario}: {what}")
}

/// The house style of a chart's axes (shared by the run and sweep reports): described axes,
/// a light grid, and tick labels without a trailing `.0`; font sizes in pixels.
pub(crate) fn draw_axes<'a, 'b>(
    chart: &mut ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    x_desc: &str,
    y_desc: &str,
    (label_px, tick_px): (u32, u32),
) -> DrawResult {
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .axis_desc_style(font(label_px))
        .label_style(font(tick_px))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(205, 205, 205))
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .draw()?;
    Ok(())
}

/// A chart over time with the given y range and labels.
fn time_chart<'a, 'b>(
    area: &'a Area<'b>,
    caption: String,
    s: &Series,
    (y0, y1): (f64, f64),
    y_desc: &str,
) -> Result<
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    Box<dyn Error>,
> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, font(TITLE_PX))
        .margin(15)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(s.t0..s.t1, y0..y1)?;
    draw_axes(&mut chart, "time (s)", y_desc, (LABEL_PX, TICK_PX))?;
    Ok(chart)
}

fn legend_line(colour: RGBColor) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
}

fn legend_box(colour: RGBColor) -> impl Fn((i32, i32)) -> Rectangle<(i32, i32)> {
    move |(x, y)| Rectangle::new([(x, y - 6), (x + 24, y + 6)], colour.filled())
}

fn gap(area: &Area, scenario: &str, s: &Series, expect: &Expect) -> DrawResult {
    let band = expect.gap_band_m;
    let extra: Vec<f64> = band.map(|b| b.to_vec()).unwrap_or_default();
    let yr = s.value_range(|r| r.gap_m, &extra);
    let mut chart = time_chart(
        area,
        title(scenario, "following distance"),
        s,
        yr,
        "gap (m)",
    )?;
    if let Some([lo, hi]) = band {
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(s.t0, lo), (s.t1, hi)],
                BAND_FILL.filled(),
            )))?
            .label(format!("expected band [{lo}, {hi}] m"))
            .legend(legend_box(BAND_FILL));
    }
    chart
        .draw_series(
            s.lines(|r| r.gap_m)
                .into_iter()
                .map(|l| PathElement::new(l, BLUE_LINE.stroke_width(2))),
        )?
        .label("gap (true)")
        .legend(legend_line(BLUE_LINE));
    draw_legend(&mut chart)
}

fn range(area: &Area, scenario: &str, s: &Series) -> DrawResult {
    let yr = padded_range(
        s.records
            .iter()
            .flat_map(|r| [r.true_range_m, r.est_range_m]),
    );
    let mut chart = time_chart(
        area,
        title(scenario, "range, estimate against truth"),
        s,
        yr,
        "range (m)",
    )?;
    let lost: Vec<_> = s
        .runs(|r| r.lost_truth)
        .into_iter()
        .filter(|r| r.2)
        .collect();
    if !lost.is_empty() {
        chart
            .draw_series(
                lost.iter()
                    .map(|&(a, b, _)| Rectangle::new([(a, yr.0), (b, yr.1)], LOST_FILL.filled())),
            )?
            .label("lost (ground truth)")
            .legend(legend_box(LOST_FILL));
    }
    chart
        .draw_series(
            s.lines(|r| r.true_range_m)
                .into_iter()
                .map(|l| PathElement::new(l, TRUTH_LINE.stroke_width(2))),
        )?
        .label("true range")
        .legend(legend_line(TRUTH_LINE));
    chart
        .draw_series(
            s.lines(|r| r.est_range_m)
                .into_iter()
                .map(|l| PathElement::new(l, BLUE_LINE.stroke_width(2))),
        )?
        .label("estimated range (tracker)")
        .legend(legend_line(BLUE_LINE));
    draw_legend(&mut chart)
}

/// Lane 1 (top): the tracker's own status; lane 0 (bottom): the ground-truth judgement.
fn status(area: &Area, scenario: &str, s: &Series) -> DrawResult {
    let (area, legend) = area.split_vertically(area.dim_in_pixel().1 - 30);
    status_legend(&legend, s.records.iter().any(|r| r.not_acquired))?;
    let mut chart = ChartBuilder::on(&area)
        .caption(
            title(scenario, "tracker status and ground truth"),
            font(TITLE_PX),
        )
        .margin(15)
        .x_label_area_size(50)
        .y_label_area_size(120)
        .build_cartesian_2d(s.t0..s.t1, (0u32..1u32).into_segmented())?;
    chart
        .configure_mesh()
        .disable_y_mesh()
        .x_desc("time (s)")
        .axis_desc_style(font(LABEL_PX))
        .label_style(font(TICK_PX))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(205, 205, 205))
        .x_label_formatter(&tick)
        .y_label_formatter(&|v| match v {
            SegmentValue::CenterOf(0) => "ground truth".into(),
            SegmentValue::CenterOf(1) => "tracker".into(),
            _ => String::new(),
        })
        .draw()?;
    let lane = |lane: u32, a: f64, b: f64, c: RGBColor| {
        Rectangle::new(
            [
                (a, SegmentValue::Exact(lane)),
                (b, SegmentValue::Exact(lane + 1)),
            ],
            c.filled(),
        )
    };
    let tracker = s.runs(|r| r.status);
    chart.draw_series(tracker.iter().map(|&(a, b, st)| {
        let c = match st {
            TrackerStatus::Tracking => TRACKING,
            TrackerStatus::Coasting => COASTING,
            TrackerStatus::Lost => LOST,
        };
        lane(1, a, b, c)
    }))?;
    #[derive(Clone, Copy, PartialEq)]
    enum Truth {
        Tracked,
        TrackedPartlyOut,
        Lost,
        LostOutOfView,
        NotAcquired,
    }
    let truth = s.runs(|r| match (r.lost_truth, r.lost_out_of_view) {
        (true, _) if r.not_acquired => Truth::NotAcquired,
        (true, true) => Truth::LostOutOfView,
        (true, false) => Truth::Lost,
        (false, _) if r.partly_out_of_view => Truth::TrackedPartlyOut,
        (false, _) => Truth::Tracked,
    });
    chart.draw_series(truth.iter().map(|&(a, b, t)| {
        let c = match t {
            Truth::Tracked => TRACKING,
            Truth::TrackedPartlyOut => PARTLY_OUT,
            Truth::Lost => LOST,
            Truth::LostOutOfView => OUT_OF_VIEW,
            Truth::NotAcquired => NOT_ACQUIRED,
        };
        lane(0, a, b, c)
    }))?;
    // A white rule between the lanes.
    chart.draw_series(std::iter::once(PathElement::new(
        vec![
            (s.t0, SegmentValue::Exact(1)),
            (s.t1, SegmentValue::Exact(1)),
        ],
        WHITE.stroke_width(3),
    )))?;
    Ok(())
}

/// A row of coloured boxes with labels, left to right, for the status timeline; with
/// `not_acquired`, also the shade of a search before the first acquisition.
fn status_legend(area: &Area, not_acquired: bool) -> DrawResult {
    let mut x = 140;
    let searched = not_acquired.then_some(("not yet acquired", NOT_ACQUIRED));
    for (label, colour) in [
        ("tracking / on target", TRACKING),
        ("coasting", COASTING),
        ("lost", LOST),
        ("lost, out of view", OUT_OF_VIEW),
        ("on target, partly out of view", PARTLY_OUT),
    ]
    .into_iter()
    .chain(searched)
    {
        area.draw(&Rectangle::new([(x, 8), (x + 24, 22)], colour.filled()))?;
        area.draw_text(label, &font(TICK_PX), (x + 32, 7))?;
        let (w, _) = area.estimate_text_size(label, &font(TICK_PX))?;
        x += 32 + w as i32 + 30;
    }
    Ok(())
}

/// Top view: world x to the right, world z down the page (y up, towards the reader), with one
/// metre the same number of pixels on both axes.
fn trajectories(area: &Area, scenario: &str, records: &[PlotRow]) -> DrawResult {
    const MARGIN: u32 = TOP_VIEW_MARGIN;
    const X_LABELS: u32 = TOP_VIEW_X_LABELS;
    const Y_LABELS: u32 = TOP_VIEW_Y_LABELS;
    let (title_area, body) = area.split_vertically(TOP_VIEW_TITLE);
    title_area.titled(
        &title(scenario, "trajectories seen from above"),
        font(TITLE_PX),
    )?;
    let (w, h) = body.dim_in_pixel();
    let plot_w = f64::from(w - 2 * MARGIN - Y_LABELS);
    let plot_h = f64::from(h - 2 * MARGIN - X_LABELS);
    let ((x0, x1), (z0, z1)) = ground_ranges(records);
    let metres_per_px = ((x1 - x0) / plot_w).max((z1 - z0) / plot_h);
    let (xc, zc) = ((x0 + x1) / 2.0, (z0 + z1) / 2.0);
    let (hx, hz) = (metres_per_px * plot_w / 2.0, metres_per_px * plot_h / 2.0);
    let mut chart = ChartBuilder::on(&body)
        .margin(MARGIN)
        .x_label_area_size(X_LABELS)
        .y_label_area_size(Y_LABELS)
        // z grows down the page: the y range runs from the larger value to the smaller.
        .build_cartesian_2d((xc - hx)..(xc + hx), (zc + hz)..(zc - hz))?;
    draw_axes(
        &mut chart,
        "world x (m)",
        "world z (m)",
        (LABEL_PX, TICK_PX),
    )?;
    // The lead is drawn wider, so that it shows on both sides of the chase on a shared path.
    for (label, colour, width, xz) in [
        (
            "lead",
            LEAD,
            5,
            records.iter().map(|r| r.lead_xz).collect::<Vec<_>>(),
        ),
        (
            "chase",
            CHASE,
            2,
            records.iter().map(|r| r.chase_xz).collect::<Vec<_>>(),
        ),
    ] {
        let points: Vec<(f64, f64)> = xz
            .iter()
            .map(|p| (p[0], p[1]))
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .collect();
        if points.is_empty() {
            // No lead in the scenario: nothing to draw or name.
            continue;
        }
        let start = points.first().copied();
        chart
            .draw_series(std::iter::once(PathElement::new(
                points,
                colour.stroke_width(width),
            )))?
            .label(label)
            .legend(legend_line(colour));
        if let Some(p) = start {
            chart.draw_series(std::iter::once(Circle::new(p, 6, colour.filled())))?;
        }
    }
    chart
        .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())?
        .label("start")
        .legend(|(x, y)| Circle::new((x + 12, y), 6, BLACK.filled()));
    draw_legend(&mut chart)
}

/// Padded ranges of world x and z over both vehicles, metres.
fn ground_ranges(records: &[PlotRow]) -> ((f64, f64), (f64, f64)) {
    let x = padded_range(records.iter().flat_map(|r| [r.chase_xz[0], r.lead_xz[0]]));
    let z = padded_range(records.iter().flat_map(|r| [r.chase_xz[1], r.lead_xz[1]]));
    (x, z)
}

/// The trajectory figure's size: fixed width, the height that fits the ground's aspect (within
/// [`TOP_VIEW_HEIGHT`]), so little of the figure is empty.
fn trajectory_size(records: &[PlotRow]) -> (u32, u32) {
    let ((x0, x1), (z0, z1)) = ground_ranges(records);
    let plot_w = TOP_VIEW_WIDTH - 2 * TOP_VIEW_MARGIN - TOP_VIEW_Y_LABELS;
    let extra_h = TOP_VIEW_TITLE + 2 * TOP_VIEW_MARGIN + TOP_VIEW_X_LABELS;
    let plot_h = (f64::from(plot_w) * (z1 - z0) / (x1 - x0)).round() as u32;
    let h = (plot_h + extra_h).clamp(TOP_VIEW_HEIGHT[0], TOP_VIEW_HEIGHT[1]);
    (TOP_VIEW_WIDTH, h)
}

fn lateral(area: &Area, scenario: &str, s: &Series, expect: &Expect) -> DrawResult {
    let limit = expect.max_lateral_deviation_m;
    let mut extra = vec![0.0];
    extra.extend(limit);
    let yr = s.value_range(|r| r.lateral_deviation_m, &extra);
    let mut chart = time_chart(
        area,
        title(scenario, "distance from the lead's path"),
        s,
        yr,
        "lateral deviation (m)",
    )?;
    if let Some(l) = limit {
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(s.t0, l), (s.t1, l)],
                LIMIT_LINE.stroke_width(2),
            )))?
            .label(format!("allowed ({l} m)"))
            .legend(legend_line(LIMIT_LINE));
    }
    chart
        .draw_series(
            s.lines(|r| r.lateral_deviation_m)
                .into_iter()
                .map(|l| PathElement::new(l, BLUE_LINE.stroke_width(2))),
        )?
        .label("chase vehicle")
        .legend(legend_line(BLUE_LINE));
    draw_legend(&mut chart)
}

fn draw_legend<'a, 'b: 'a, X: Ranged, Y: Ranged>(
    chart: &mut ChartContext<'a, BitMapBackend<'b>, Cartesian2d<X, Y>>,
) -> DrawResult {
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .label_font(font(TICK_PX))
        .draw()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_follow_the_magnitude_of_small_values() {
        assert_eq!(tick(&0.0004), "0.0004");
        assert_eq!(tick(&0.00045), "0.00045");
        assert_eq!(tick(&-0.0002), "-0.0002");
        assert_eq!(tick(&0.0), "0");
        assert_eq!(tick(&-0.0), "0");
        assert_eq!(tick(&0.30000000000000004), "0.3");
        assert_eq!(tick(&12.5), "12.5");
    }

    /// Frame `i` of a run at 15 Hz: a gap and a deviation that wander, tracking on target.
    fn frame(i: u64) -> PlotRow {
        let t = i as f64 / 15.0;
        PlotRow {
            t_s: t,
            gap_m: 10.0 + (t * 0.3).sin(),
            true_range_m: 10.0 + (t * 0.3).sin(),
            est_range_m: 10.0 + (t * 0.3).sin() + 0.01 * (t * 7.0).cos(),
            lateral_deviation_m: 0.1 * (t * 0.05).cos().abs(),
            chase_xz: [t, 0.0],
            lead_xz: [t + 10.0, 0.0],
            status: TrackerStatus::Tracking,
            lost_truth: false,
            lost_out_of_view: false,
            not_acquired: false,
            partly_out_of_view: false,
        }
    }

    fn trace_of(cap: usize, frames: impl Iterator<Item = PlotRow>) -> PlotTrace {
        let mut trace = PlotTrace::with_cap(cap);
        for f in frames {
            trace.push_row(f);
            assert!(trace.rows.len() < cap, "the trace outgrew its cap");
        }
        trace
    }

    #[test]
    fn a_trace_within_its_cap_keeps_every_frame() {
        let frames: Vec<PlotRow> = (0..99).map(frame).collect();
        let trace = trace_of(100, frames.iter().copied());
        assert_eq!(trace.rows(), frames);
    }

    #[test]
    fn a_long_trace_stays_within_its_cap_and_hides_no_event() {
        const N: u64 = 100_000;
        let (lost_at, coasting_at, close_at, wide_at, no_estimate_at) =
            (40_001, 61_234, 77_777, 12_345, 90_001);
        let frames = (0..N).map(|i| {
            let mut f = frame(i);
            if i == lost_at {
                f.lost_truth = true;
                f.status = TrackerStatus::Lost;
            }
            if i == coasting_at {
                f.status = TrackerStatus::Coasting;
            }
            if i == close_at {
                f.gap_m = 2.5;
            }
            if i == wide_at {
                f.lateral_deviation_m = 1.7;
            }
            if i == no_estimate_at {
                f.est_range_m = f64::NAN;
            }
            f
        });
        let cap = 64;
        let rows = trace_of(cap, frames).rows();
        assert!(
            rows.len() >= cap / 2 && rows.len() <= cap,
            "{} rows",
            rows.len()
        );
        assert!(rows.windows(2).all(|w| w[0].t_s < w[1].t_s));
        assert_eq!(rows[0].t_s, 0.0);
        // Each event is in the row whose span holds its frame, and in no other.
        let row_of = |i: u64| {
            let t = i as f64 / 15.0;
            rows.iter().rposition(|r| r.t_s <= t).unwrap()
        };
        let lost: Vec<usize> = (0..rows.len()).filter(|&k| rows[k].lost_truth).collect();
        assert_eq!(lost, [row_of(lost_at)]);
        assert_eq!(rows[row_of(lost_at)].status, TrackerStatus::Lost);
        assert_eq!(rows[row_of(coasting_at)].status, TrackerStatus::Coasting);
        let gaps = rows.iter().map(|r| r.gap_m);
        assert_eq!(gaps.fold(f64::INFINITY, f64::min), 2.5);
        assert_eq!(rows[row_of(close_at)].gap_m, 2.5);
        assert_eq!(rows[row_of(wide_at)].lateral_deviation_m, 1.7);
        assert!(rows[row_of(no_estimate_at)].est_range_m.is_nan());
        assert_eq!(rows.iter().filter(|r| r.est_range_m.is_nan()).count(), 1);
    }

    /// The status plot of `rows` as RGB pixels.
    fn status_pixels(rows: &[PlotRow]) -> Vec<u8> {
        register_font(Path::new(".")).unwrap();
        let mut period = FramePeriod::default();
        for r in rows {
            period.push(r.t_s);
        }
        let series = Series::new(rows, period.period());
        let size = (WIDE.0, 300);
        let mut buf = vec![0u8; size.0 as usize * size.1 as usize * 3];
        {
            let area = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
            area.fill(&WHITE).unwrap();
            status(&area, "x", &series).unwrap();
            area.present().unwrap();
        }
        buf
    }

    fn count(pixels: &[u8], c: RGBColor) -> usize {
        pixels
            .chunks_exact(3)
            .filter(|p| p == &[c.0, c.1, c.2])
            .count()
    }

    #[test]
    fn the_status_plot_shades_a_search_before_acquisition_apart_from_losses() {
        // 150 frames: searching (lost by the truth, not yet acquired) for the first 30,
        // then on target, lost after acquisition for frames 100..110.
        let rows: Vec<PlotRow> = (0..150)
            .map(|i| {
                let mut f = frame(i);
                if i < 30 {
                    (f.lost_truth, f.not_acquired) = (true, true);
                    f.status = TrackerStatus::Lost;
                }
                if (100..110).contains(&i) {
                    f.lost_truth = true;
                }
                f
            })
            .collect();
        let with_search = status_pixels(&rows);
        // The search's shade in the lane and in the legend; the loss after acquisition is
        // still red in the truth lane (the tracker's lane is red for the search too).
        let searched = count(&with_search, NOT_ACQUIRED);
        assert!(searched > 1000, "{searched}");
        let red = count(&with_search, LOST);
        // Without the search: no such shade, no legend entry; the search's frames drawn red.
        let plain: Vec<PlotRow> = rows
            .iter()
            .map(|r| PlotRow {
                not_acquired: false,
                ..*r
            })
            .collect();
        let without = status_pixels(&plain);
        assert_eq!(count(&without, NOT_ACQUIRED), 0);
        assert!(count(&without, LOST) > red + searched / 2, "{red}");
        // The loss after acquisition stays red whatever the search: rows merged over both
        // count as lost.
        let merged = rows[29].merge(rows[30]).merge(rows[105]);
        assert!(!merged.not_acquired && merged.lost_truth);
        assert!(rows[0].merge(rows[1]).not_acquired);
        assert!(rows[0].merge(rows[40]).not_acquired);
    }
}

//! One PNG per numeric axis, `sweep-<axis>.png`: four panels (tracking-loss time, range
//! error, time outside the gap band, path deviation) against the axis, one colour per
//! scenario. The line is the mean over the seeds (and the other axes' values) at each value,
//! the shaded band their minimum to maximum, and the dots the single runs.
//!
//! The font and the bitmap-to-PNG step are the run plots' (`report::plots`).

use super::results::{axis_paths, scenario_order, FIGURES};
use super::{ResultRow, SweepError};
use crate::report::plots::{draw_axes, font, register_font, render, Area, DrawResult};
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Size of one axis's figure, pixels.
const SIZE: (u32, u32) = (1400, 1500);
const TITLE_PX: u32 = 22;
const LABEL_PX: u32 = 15;
const TICK_PX: u32 = 13;
/// Scenario colours, in the rows' order (repeating after eight).
const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 100, 200),
    RGBColor(210, 60, 30),
    RGBColor(40, 150, 60),
    RGBColor(150, 60, 180),
    RGBColor(230, 150, 0),
    RGBColor(20, 160, 170),
    RGBColor(120, 80, 40),
    RGBColor(100, 100, 100),
];

/// Draws one figure per numeric axis into `dir`; returns the paths written.
pub(crate) fn write_plots(dir: &Path, rows: &[ResultRow]) -> Result<Vec<PathBuf>, SweepError> {
    register_font(dir)?;
    let scenarios = scenario_order(rows);
    let mut written = Vec::new();
    for axis in axis_paths(rows) {
        if !rows.iter().all(|r| r.param(&axis).is_some()) {
            continue; // not numeric: the table and summary still list it
        }
        let path = dir.join(format!("sweep-{axis}.png"));
        render(&path, SIZE, &|area: &Area| {
            let panels = area.split_evenly((3, 2));
            for (panel, figure) in panels.iter().zip(FIGURES.iter()) {
                draw_panel(panel, rows, &scenarios, &axis, figure)?;
            }
            Ok(())
        })?;
        written.push(path);
    }
    Ok(written)
}

/// Mean, minimum and maximum of one figure per axis value, ascending, for one scenario.
fn spread(
    rows: &[ResultRow],
    scenario: &str,
    axis: &str,
    pointer: &str,
) -> Vec<(f64, f64, f64, f64)> {
    let mut points: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.scenario == scenario)
        .filter_map(|r| Some((r.param(axis)?, r.figure(pointer)?)))
        .collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<(f64, f64, f64, f64)> = Vec::new();
    for chunk in points.chunk_by(|a, b| a.0 == b.0) {
        let ys: Vec<f64> = chunk.iter().map(|p| p.1).collect();
        let mean = ys.iter().sum::<f64>() / ys.len() as f64;
        let lo = ys.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        out.push((chunk[0].0, mean, lo, hi));
    }
    out
}

fn draw_panel(
    area: &Area,
    rows: &[ResultRow],
    scenarios: &[String],
    axis: &str,
    &(_, pointer, label): &(&str, &str, &str),
) -> DrawResult {
    let xs: Vec<f64> = rows.iter().filter_map(|r| r.param(axis)).collect();
    let ys: Vec<f64> = rows.iter().filter_map(|r| r.figure(pointer)).collect();
    let (x0, x1) = min_max(&xs);
    let pad = ((x1 - x0) * 0.04).max(1e-3);
    let y1 = ys.iter().copied().fold(0.0, f64::max);
    let y1 = if y1 > 0.0 { y1 * 1.1 } else { 1.0 };
    let mut chart = ChartBuilder::on(area)
        .caption(format!("{label} against {axis}"), font(TITLE_PX))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d((x0 - pad)..(x1 + pad), 0.0..y1)?;
    draw_axes(&mut chart, axis, label, (LABEL_PX, TICK_PX))?;
    for (i, scenario) in scenarios.iter().enumerate() {
        let colour = PALETTE[i % PALETTE.len()];
        let s = spread(rows, scenario, axis, pointer);
        if s.is_empty() {
            continue;
        }
        // The min–max band over the seeds.
        let band: Vec<(f64, f64)> = s
            .iter()
            .map(|p| (p.0, p.3))
            .chain(s.iter().rev().map(|p| (p.0, p.2)))
            .collect();
        chart.draw_series(std::iter::once(Polygon::new(
            band,
            colour.mix(0.15).filled(),
        )))?;
        // The single runs.
        chart.draw_series(
            rows.iter()
                .filter(|r| &r.scenario == scenario)
                .filter_map(|r| Some((r.param(axis)?, r.figure(pointer)?)))
                .map(|p| Circle::new(p, 3, colour.mix(0.6).filled())),
        )?;
        // The mean.
        chart
            .draw_series(LineSeries::new(
                s.iter().map(|p| (p.0, p.1)),
                colour.stroke_width(3),
            ))?
            .label(scenario.as_str())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
            });
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(180, 180, 180))
        .label_font(font(TICK_PX))
        .draw()?;
    Ok(())
}

fn min_max(xs: &[f64]) -> (f64, f64) {
    let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if lo.is_finite() {
        (lo, hi)
    } else {
        (0.0, 1.0)
    }
}

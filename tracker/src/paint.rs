//! How a target model is painted on the lead vehicle's back: the one paint rule that the
//! renderer (`sim`) and the synthetic frames ([`crate::synth`]) share, so that what the
//! camera sees is the object the tracker models.
//!
//! The board is a light rectangle, the corners' bounding box plus [`BOARD_MARGIN_M`]. What is
//! painted on it depends on the model's [`Paint`]:
//!
//! - [`Paint::Steps`] (the default, the paper's): every segment is one step edge between two
//!   filled regions (2.1.1: "each line segment corresponds to a physical feature that gives
//!   rise to a strong edge"). The segments cut the board into regions; regions that share a
//!   segment get different tones, so each segment is a single edge and nothing else on the
//!   board is. See [`layout`].
//! - [`Paint::Stripes`] (not the paper's): every segment is a dark stripe [`STRIPE_WIDTH_M`]
//!   wide, centred on the segment and extended [`STRIPE_EXTENSION_M`] past its end points. A
//!   stripe gives two parallel edges of opposite sense, one on each side of the segment,
//!   whose mean is the segment itself (eq. 12). Their spread makes the variance of eq. 13
//!   about 1–4 px² on every feature, so the cap of eq. 14 never applies and the confidence
//!   weighting cannot tell a clean feature from one with a shadow on it; kept for comparison
//!   and for models whose segments do not bound regions.

pub use crate::model::Paint;
use crate::model::{TargetModel, AXIS_TOLERANCE_M};
use thiserror::Error;

/// Margin of the light board beyond the corners' bounding box, metres. The board's own
/// border is a strong edge parallel to the outer segments (section 4's second failure mode,
/// on the target itself): 0.35 m puts it 11 px beyond them at the nominal 10 m and 7.5 px at
/// 15 m, so only a prediction more than 3.5 px off brings it within the default ζ of 4 px.
/// Once it is within ζ it pulls the outer features, and with them the scale, outwards, the
/// next prediction brings it nearer still, and the track runs away to the border: with a
/// 0.25 m margin (5.8 px at 14 m) that happened in bends on every seed of the 17-minute tape
/// tried (7 of 7), with 0.35 m on none.
pub const BOARD_MARGIN_M: f64 = 0.35;
/// Width of each painted segment in [`Paint::Stripes`], metres: 2 px at the nominal 10 m, so
/// both of a stripe's edges lie within ζ of the segment at every range from 5 to 15 m.
pub const STRIPE_WIDTH_M: f64 = 0.06;
/// How far each stripe runs past its segment's end points, metres, so that stripes meeting
/// at a corner close it.
pub const STRIPE_EXTENSION_M: f64 = 0.03;

/// One painted rectangle in the target's frame: metres from the target centre, x right and
/// y up, `[x0, y0, x1, y1]`, with its tone: 1 is the board's light paint, 0 the darkest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaintRect {
    /// `[x0, y0, x1, y1]`, metres, x0 < x1 and y0 < y1.
    pub bounds_m: [f64; 4],
    /// 0 (dark) to 1 (the board's light paint).
    pub tone: f64,
}

/// Why a model cannot be painted with step edges.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum PaintError {
    /// A segment (or part of one) has the same region on both sides: it ends in open board,
    /// so no filled region can give it a step edge.
    #[error(
        "segment {segment} does not bound a closed region (part of it has the same region on \
         both sides), so it cannot be painted as one step edge; close the region, or set \
         paint = \"stripes\" (two edges per segment, not the paper's)"
    )]
    NotABoundary {
        /// The segment's index.
        segment: usize,
    },
}

/// The board's rectangle, metres: the corners' bounding box plus [`BOARD_MARGIN_M`].
pub fn board_m(model: &TargetModel) -> [f64; 4] {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &[x, y] in model.corners_m() {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let m = BOARD_MARGIN_M;
    [x0 - m, y0 - m, x1 + m, y1 + m]
}

/// What to paint for `model`, by its [`TargetModel::paint`]: the board first (tone 1), then
/// the rectangles on it, which do not overlap in [`Paint::Steps`] and may in
/// [`Paint::Stripes`].
///
/// Steps: the distinct x of the corners and of the board's sides, and likewise y, cut the
/// board into a grid of cells. Two neighbouring cells are in one region unless a segment
/// runs along their shared side. Regions are coloured greedily, the region at the board's
/// border first (it keeps the board's tone), each with the lowest colour none of its
/// neighbours across a segment has; colour 0 is tone 1, colour 1 tone 0, and any further
/// colours share the tones between (the shipped target needs three: its two centre bars
/// split the frame between the outer and inner rectangles in two). Deterministic: the same
/// model always gives the same rectangles.
pub fn layout(model: &TargetModel) -> Result<Vec<PaintRect>, PaintError> {
    match model.paint() {
        Paint::Steps => steps(model),
        Paint::Stripes => Ok(stripes(model)),
    }
}

/// The [`Paint::Stripes`] layout of any model, whatever its own paint: the board, then one
/// dark stripe per segment.
pub fn stripes(model: &TargetModel) -> Vec<PaintRect> {
    let mut out = vec![PaintRect {
        bounds_m: board_m(model),
        tone: 1.0,
    }];
    let (hw, ext) = (0.5 * STRIPE_WIDTH_M, STRIPE_EXTENSION_M);
    let corners = model.corners_m();
    for &[a, b] in model.segments() {
        let ([ax, ay], [bx, by]) = (corners[a], corners[b]);
        let bounds_m = if (ay - by).abs() <= AXIS_TOLERANCE_M {
            let y = 0.5 * (ay + by);
            [ax.min(bx) - ext, y - hw, ax.max(bx) + ext, y + hw]
        } else {
            let x = 0.5 * (ax + bx);
            [x - hw, ay.min(by) - ext, x + hw, ay.max(by) + ext]
        };
        out.push(PaintRect {
            bounds_m,
            tone: 0.0,
        });
    }
    out
}

/// Sorted coordinates, merged within [`AXIS_TOLERANCE_M`].
fn grid_lines(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    let mut out: Vec<f64> = Vec::with_capacity(v.len());
    for x in v {
        if out.last().is_none_or(|&l| x - l > AXIS_TOLERANCE_M) {
            out.push(x);
        }
    }
    out
}

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

fn steps(model: &TargetModel) -> Result<Vec<PaintRect>, PaintError> {
    let board = board_m(model);
    let corners = model.corners_m();
    let xs = grid_lines(
        corners
            .iter()
            .map(|c| c[0])
            .chain([board[0], board[2]])
            .collect(),
    );
    let ys = grid_lines(
        corners
            .iter()
            .map(|c| c[1])
            .chain([board[1], board[3]])
            .collect(),
    );
    let (nx, ny) = (xs.len() - 1, ys.len() - 1);
    let cell = |i: usize, j: usize| j * nx + i;
    let index_of = |lines: &[f64], v: f64| {
        lines
            .iter()
            .position(|&l| (l - v).abs() <= AXIS_TOLERANCE_M)
    };
    // Barriers: `vertical[cell(i, j)]` is the segment along the left side of cell (i, j)
    // (between cells (i − 1, j) and (i, j)); `horizontal[cell(i, j)]` along its bottom.
    let mut vertical: Vec<Option<usize>> = vec![None; nx * ny];
    let mut horizontal: Vec<Option<usize>> = vec![None; nx * ny];
    for (segment, &[a, b]) in model.segments().iter().enumerate() {
        let ([ax, ay], [bx, by]) = (corners[a], corners[b]);
        let horizontal_segment = (ay - by).abs() <= AXIS_TOLERANCE_M;
        let (across, lo, hi, along_lines, across_lines) = if horizontal_segment {
            (ay, ax.min(bx), ax.max(bx), &xs, &ys)
        } else {
            (ax, ay.min(by), ay.max(by), &ys, &xs)
        };
        let (Some(k), Some(from), Some(to)) = (
            index_of(across_lines, across),
            index_of(along_lines, lo),
            index_of(along_lines, hi),
        ) else {
            unreachable!("every corner coordinate is a grid line");
        };
        for piece in from..to {
            if horizontal_segment {
                horizontal[cell(piece, k)] = Some(segment);
            } else {
                vertical[cell(k, piece)] = Some(segment);
            }
        }
    }
    // Regions: cells joined across every side no segment runs along.
    let mut parent: Vec<usize> = (0..nx * ny).collect();
    for j in 0..ny {
        for i in 0..nx {
            if i > 0 && vertical[cell(i, j)].is_none() {
                let (p, q) = (
                    find(&mut parent, cell(i - 1, j)),
                    find(&mut parent, cell(i, j)),
                );
                parent[p.max(q)] = p.min(q);
            }
            if j > 0 && horizontal[cell(i, j)].is_none() {
                let (p, q) = (
                    find(&mut parent, cell(i, j - 1)),
                    find(&mut parent, cell(i, j)),
                );
                parent[p.max(q)] = p.min(q);
            }
        }
    }
    let region: Vec<usize> = (0..nx * ny).map(|c| find(&mut parent, c)).collect();
    // Neighbours across segments; a segment with one region on both sides is refused.
    let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); nx * ny];
    let mut link = |p: usize, q: usize, segment: usize| {
        if p == q {
            return Err(PaintError::NotABoundary { segment });
        }
        if !neighbours[p].contains(&q) {
            neighbours[p].push(q);
            neighbours[q].push(p);
        }
        Ok(())
    };
    for j in 0..ny {
        for i in 0..nx {
            if let Some(s) = vertical[cell(i, j)] {
                link(region[cell(i - 1, j)], region[cell(i, j)], s)?;
            }
            if let Some(s) = horizontal[cell(i, j)] {
                link(region[cell(i, j - 1)], region[cell(i, j)], s)?;
            }
        }
    }
    // Greedy colouring in order of first appearance; cell (0, 0) is the board's margin.
    let mut colour: Vec<Option<usize>> = vec![None; nx * ny];
    for &r in &region {
        if colour[r].is_some() {
            continue;
        }
        let taken: Vec<usize> = neighbours[r].iter().filter_map(|&q| colour[q]).collect();
        colour[r] = (0..).find(|c| !taken.contains(c));
    }
    let colours = colour.iter().flatten().max().map_or(1, |&c| c + 1);
    let tone = |c: usize| match c {
        0 => 1.0,
        1 => 0.0,
        c => (c - 1) as f64 / (colours - 1) as f64,
    };
    let mut out = vec![PaintRect {
        bounds_m: board,
        tone: 1.0,
    }];
    // Runs of equal tone along each row of cells, skipping the board's own tone.
    for j in 0..ny {
        let mut i = 0;
        while i < nx {
            let c = colour[region[cell(i, j)]].unwrap_or(0);
            let mut end = i + 1;
            while end < nx && colour[region[cell(end, j)]].unwrap_or(0) == c {
                end += 1;
            }
            if c != 0 {
                out.push(PaintRect {
                    bounds_m: [xs[i], ys[j], xs[end], ys[j + 1]],
                    tone: tone(c),
                });
            }
            i = end;
        }
    }
    Ok(out)
}

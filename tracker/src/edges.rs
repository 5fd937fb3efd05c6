//! Stage 1: edge extraction (paper 2.3, eq. 3, 4 and 7).
//!
//! Inside the window of interest: the 3×3 Sobel gradient, non-maximum suppression across
//! the edge, a magnitude threshold, and the near-horizontal / near-vertical classes of
//! eq. 7. The result is two lists of edge points, one per class, as the paper's IS-MAP stage
//! produced (section 3).

use crate::config::TrackerConfig;
use crate::gray::GrayView;
use crate::model::Orientation;
use crate::window::Window;

/// An edge point that passed stage 1: its image position (pixels; integer unless sub-pixel
/// edges are on, then refined across the edge).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgePoint {
    /// Image x.
    pub x: f32,
    /// Image y.
    pub y: f32,
}

/// The output of stage 1: the two lists of classified edge points.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Edges {
    /// Points whose edge direction is within δ of horizontal (eq. 7, first test).
    pub horizontal: Vec<EdgePoint>,
    /// Points whose edge direction is within δ of vertical (eq. 7, second test).
    pub vertical: Vec<EdgePoint>,
}

impl Edges {
    /// Empties both lists, keeping their memory.
    pub fn clear(&mut self) {
        self.horizontal.clear();
        self.vertical.clear();
    }

    /// The list for one class.
    pub fn of(&self, orientation: Orientation) -> &[EdgePoint] {
        match orientation {
            Orientation::Horizontal => &self.horizontal,
            Orientation::Vertical => &self.vertical,
        }
    }
}

/// What became of one edge point (a local maximum across the edge) in the window: the
/// reason it was dropped, or the feature it was associated with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeFate {
    /// Below the magnitude threshold (2.3).
    Weak,
    /// Neither near-horizontal nor near-vertical (eq. 7).
    WrongOrientation,
    /// Classified, but no predicted feature of its class spans it (eq. 8, 10) within ζ (2.4).
    TooFar,
    /// Associated with feature j (the model's segment j) (2.4).
    Associated(usize),
}

/// One edge point and its fate, for drawing and inspection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeDiagnostic {
    /// Image x.
    pub x: f32,
    /// Image y.
    pub y: f32,
    /// Its class, when it had one.
    pub class: Option<Orientation>,
    /// What became of it.
    pub fate: EdgeFate,
}

/// Edge direction θ of eq. 3, radians in [0, π): perpendicular to the intensity gradient
/// (∇f_x, ∇f_y). θ = π/2 is a horizontal edge, θ = 0 a vertical one.
pub fn edge_direction(grad_x: f64, grad_y: f64) -> f64 {
    let theta = grad_x.atan2(grad_y) + std::f64::consts::FRAC_PI_2;
    theta.rem_euclid(std::f64::consts::PI)
}

/// The class of eq. 7 for an edge direction θ (radians, any turn): horizontal when
/// |π/2 − θ| < δ, vertical when |0 − θ| < δ, both measured modulo π.
pub fn classify_direction(theta: f64, delta: f64) -> Option<Orientation> {
    let pi = std::f64::consts::PI;
    let t = theta.rem_euclid(pi);
    let from_vertical = t.min(pi - t);
    if (std::f64::consts::FRAC_PI_2 - t).abs() < delta {
        Some(Orientation::Horizontal)
    } else if from_vertical < delta {
        Some(Orientation::Vertical)
    } else {
        None
    }
}

/// Stage 1, with its scratch buffers kept between frames so the hot path allocates nothing.
#[derive(Clone, Debug, Default)]
pub struct EdgeExtractor {
    gx: Vec<i16>,
    gy: Vec<i16>,
    mag2: Vec<i32>,
    /// One row of the vertical [1 2 1] smoothing (separable Sobel).
    smooth: Vec<i16>,
    /// One row of the vertical [−1 0 1] difference.
    diff: Vec<i16>,
}

/// tan(22.5°): the border between the axis and diagonal bins of non-maximum suppression.
const TAN_22_5: f32 = 0.414_213_57;

impl EdgeExtractor {
    /// Extracts the classified edge points inside `window` into `out` (cleared first).
    /// With `diagnostics`, the local maxima dropped for weakness or orientation are
    /// recorded there too.
    pub fn extract(
        &mut self,
        image: GrayView<'_>,
        window: Window,
        config: &TrackerConfig,
        out: &mut Edges,
        mut diagnostics: Option<&mut Vec<EdgeDiagnostic>>,
    ) {
        out.clear();
        if window.is_empty() {
            return;
        }
        // The gradient is needed one pixel beyond the window, for the suppression test at
        // its border; the 3×3 operator itself needs one more.
        let (w, h) = (image.width(), image.height());
        let ex0 = window.x0.saturating_sub(1).max(1);
        let ey0 = window.y0.saturating_sub(1).max(1);
        let ex1 = (window.x1 + 1).min(w - 1);
        let ey1 = (window.y1 + 1).min(h - 1);
        let rw = ex1 - ex0;
        let rh = ey1 - ey0;
        self.sobel(image, ex0, ey0, rw, rh);

        // The threshold is on eq. 4's magnitude |∇f|, grey levels per pixel: the raw 3×3
        // Sobel response over 8 (weights 1 + 2 + 1 on each side of a two-pixel span), so a
        // step of h grey levels has |∇f| = h/2 and the paper's 8 passes steps of 16.
        let thr = 8.0 * config.edge_threshold;
        // Squared magnitudes are whole numbers, so m² ≥ thr² exactly when m² ≥ ⌈thr²⌉.
        let thr2 = (thr * thr).ceil() as i32;
        let tan_delta = (config.delta_deg.to_radians() as f32).tan();
        if diagnostics.is_none() && tan_delta <= TAN_22_5 {
            self.extract_axis_aligned(
                window,
                (ex0, ey0, rw, rh),
                thr2,
                tan_delta,
                config.subpixel_edges,
                out,
            );
            return;
        }
        let mag = |i: isize| -> f32 {
            // Outside the computed region counts as no gradient.
            if i < 0 || i as usize >= self.mag2.len() {
                0.0
            } else {
                self.mag2[i as usize] as f32
            }
        };
        let rwi = rw as isize;
        for y in window.y0..window.y1 {
            let ry = y - ey0;
            for x in window.x0..window.x1 {
                let rx = x - ex0;
                let i = ry * rw + rx;
                let m2i = self.mag2[i];
                let strong = m2i >= thr2;
                if m2i == 0 || (!strong && diagnostics.is_none()) {
                    continue;
                }
                let m2 = m2i as f32;
                let gx = self.gx[i] as f32;
                let gy = self.gy[i] as f32;
                let (ax, ay) = (gx.abs(), gy.abs());
                // Eq. 7 on the gradient: the edge is within δ of horizontal when the gradient
                // is within δ of vertical, i.e. |∇f_x| < tan δ · |∇f_y|.
                let class = if ax < tan_delta * ay {
                    Some(Orientation::Horizontal)
                } else if ay < tan_delta * ax {
                    Some(Orientation::Vertical)
                } else {
                    None
                };
                if diagnostics.is_none() && !(strong && class.is_some()) {
                    continue;
                }
                // Non-maximum suppression across the edge, i.e. along the gradient, with the
                // direction quantised to four bins. Ties keep the point nearer the origin.
                let (dx, dy): (isize, isize) = if ay <= TAN_22_5 * ax {
                    (1, 0)
                } else if ax <= TAN_22_5 * ay {
                    (0, 1)
                } else if (gx > 0.0) == (gy > 0.0) {
                    (1, 1)
                } else {
                    (1, -1)
                };
                // Neighbours outside the computed region (only at the image border) are 0.
                let neighbour = |sx: isize, sy: isize| -> f32 {
                    let nx = rx as isize + sx;
                    let ny = ry as isize + sy;
                    if nx < 0 || ny < 0 || nx >= rwi || ny >= rh as isize {
                        0.0
                    } else {
                        mag(ny * rwi + nx)
                    }
                };
                let before = neighbour(-dx, -dy);
                let after = neighbour(dx, dy);
                if !(m2 > before && m2 >= after) {
                    continue;
                }
                match (strong, class) {
                    (true, Some(class)) => {
                        let mut p = EdgePoint {
                            x: x as f32,
                            y: y as f32,
                        };
                        if config.subpixel_edges {
                            refine(
                                &mut p,
                                class,
                                |s| match class {
                                    Orientation::Horizontal => neighbour(0, s),
                                    Orientation::Vertical => neighbour(s, 0),
                                },
                                m2,
                            );
                        }
                        match class {
                            Orientation::Horizontal => out.horizontal.push(p),
                            Orientation::Vertical => out.vertical.push(p),
                        }
                    }
                    (strong, class) => {
                        if let Some(d) = diagnostics.as_deref_mut() {
                            d.push(EdgeDiagnostic {
                                x: x as f32,
                                y: y as f32,
                                class,
                                fate: if strong {
                                    EdgeFate::WrongOrientation
                                } else {
                                    EdgeFate::Weak
                                },
                            });
                        }
                    }
                }
            }
        }
    }

    /// The hot path of [`EdgeExtractor::extract`], without diagnostics and for δ ≤ 22.5°:
    /// then every classified point's gradient falls in an axis bin of the suppression, so a
    /// horizontal edge compares with the pixels above and below, a vertical one with those
    /// left and right. Gives exactly the points of the general path (a test checks).
    fn extract_axis_aligned(
        &self,
        window: Window,
        (ex0, ey0, rw, rh): (usize, usize, usize, usize),
        thr2: i32,
        tan_delta: f32,
        subpixel: bool,
        out: &mut Edges,
    ) {
        // A zero magnitude is never an edge point, whatever the threshold.
        let thr2 = thr2.max(1);
        let mag2 = &self.mag2[..rw * rh];
        let (rx0, rx1) = (window.x0 - ex0, window.x1 - ex0);
        for ry in window.y0 - ey0..window.y1 - ey0 {
            let row = ry * rw;
            let mut start = rx0;
            while start < rx1 {
                // Most of a window is below the threshold: skip a chunk of pixels when none
                // of them passes (the maximum over a chunk vectorises).
                let end = (start + 16).min(rx1);
                let chunk = &mag2[row + start..row + end];
                if chunk.iter().fold(0, |a, &m| a.max(m)) < thr2 {
                    start = end;
                    continue;
                }
                for rx in start..end {
                    let i = row + rx;
                    let m2 = mag2[i];
                    if m2 < thr2 {
                        continue;
                    }
                    let ax = f32::from(self.gx[i]).abs();
                    let ay = f32::from(self.gy[i]).abs();
                    let (class, before, after) = if ax < tan_delta * ay {
                        let up = if ry > 0 { mag2[i - rw] } else { 0 };
                        let down = if ry + 1 < rh { mag2[i + rw] } else { 0 };
                        (Orientation::Horizontal, up, down)
                    } else if ay < tan_delta * ax {
                        let left = if rx > 0 { mag2[i - 1] } else { 0 };
                        let right = if rx + 1 < rw { mag2[i + 1] } else { 0 };
                        (Orientation::Vertical, left, right)
                    } else {
                        continue;
                    };
                    if !(m2 > before && m2 >= after) {
                        continue;
                    }
                    let mut p = EdgePoint {
                        x: (rx + ex0) as f32,
                        y: (ry + ey0) as f32,
                    };
                    if subpixel {
                        let side = |s: isize| if s < 0 { before as f32 } else { after as f32 };
                        refine(&mut p, class, side, m2 as f32);
                    }
                    match class {
                        Orientation::Horizontal => out.horizontal.push(p),
                        Orientation::Vertical => out.vertical.push(p),
                    }
                }
                start = end;
            }
        }
    }

    /// The 3×3 Sobel gradient (eq. 3–4's ∇f) over `rw × rh` pixels from (x0, y0); every
    /// pixel there has all eight neighbours in the image.
    ///
    /// The operator is separable: per row, a vertical [1 2 1] smoothing and a vertical
    /// [−1 0 1] difference over the columns x0 − 1 ..= x0 + rw, then the horizontal
    /// difference of the first and the horizontal smoothing of the second. Each pass is a
    /// plain loop over contiguous slices, which the compiler vectorises.
    fn sobel(&mut self, image: GrayView<'_>, x0: usize, y0: usize, rw: usize, rh: usize) {
        let n = rw * rh;
        self.gx.resize(n, 0);
        self.gy.resize(n, 0);
        self.mag2.resize(n, 0);
        self.smooth.resize(rw + 2, 0);
        self.diff.resize(rw + 2, 0);
        let w = image.width();
        let px = image.pixels();
        for ry in 0..rh {
            let y = y0 + ry;
            let cut = |row: usize| &px[row * w + x0 - 1..row * w + x0 + rw + 1];
            let (up, mid, down) = (cut(y - 1), cut(y), cut(y + 1));
            for (((s, d), (&u, &m)), &dn) in self
                .smooth
                .iter_mut()
                .zip(self.diff.iter_mut())
                .zip(up.iter().zip(mid))
                .zip(down)
            {
                let (u, m, dn) = (i16::from(u), i16::from(m), i16::from(dn));
                *s = u + 2 * m + dn;
                *d = dn - u;
            }
            let out = ry * rw..(ry + 1) * rw;
            let (s, d) = (&self.smooth[..rw + 2], &self.diff[..rw + 2]);
            for (k, ((gx, gy), m2)) in self.gx[out.clone()]
                .iter_mut()
                .zip(&mut self.gy[out.clone()])
                .zip(&mut self.mag2[out])
                .enumerate()
            {
                let x = s[k + 2] - s[k];
                let yv = d[k] + 2 * d[k + 1] + d[k + 2];
                *gx = x;
                *gy = yv;
                *m2 = i32::from(x) * i32::from(x) + i32::from(yv) * i32::from(yv);
            }
        }
    }
}

/// Sub-pixel refinement (an option beyond the paper): the vertex of the parabola through
/// the gradient magnitudes at −1, 0, +1 pixels across the edge.
fn refine(p: &mut EdgePoint, class: Orientation, neighbour: impl Fn(isize) -> f32, m2: f32) {
    let (a, b, c) = (neighbour(-1).sqrt(), m2.sqrt(), neighbour(1).sqrt());
    let denom = a - 2.0 * b + c;
    if denom < 0.0 {
        let offset = (0.5 * (a - c) / denom).clamp(-0.5, 0.5);
        match class {
            Orientation::Horizontal => p.y += offset,
            Orientation::Vertical => p.x += offset,
        }
    }
}

//! Robust mode's chamfer search: the model's outline matched against the distance
//! transforms of the horizontal and vertical edge maps over position and scale, coarse to
//! fine (H. G. Barrow et al., "Parametric correspondence and chamfer matching", IJCAI 1977;
//! G. Borgefors, "Hierarchical chamfer matching", IEEE PAMI 10(6), 1988). Not in the paper,
//! whose start was a person's (2.2); see [`crate::robust`].
//!
//! The coarse pass scores a grid of centres [`SEARCH_STEP_PX`] apart. Its centres are whole
//! pixels, so at one scale almost every outline sample lies a fixed whole-pixel offset from
//! the centre, and one grid row's scores are sums of rows of the truncated distance
//! transforms, shifted: added a row at a time, with no rounding per sample. The transforms
//! are kept split by column modulo the step, so a row holds only the grid's columns. A
//! sample within rounding of a half pixel is rounded per centre, as the fine pass rounds
//! every one; a centre whose samples reach off the region is scored sample by sample.

use crate::config::TrackerConfig;
use crate::edges::{EdgeExtractor, Edges};
use crate::gate::AcquireGate;
use crate::gray::GrayView;
use crate::location::Location;
use crate::model::{Feature, Orientation};
use crate::robust::{
    CHAMFER_SAMPLES, CHAMFER_TRUNCATION_PX, SEARCH_REFINE, SEARCH_SCALE_STEP, SEARCH_STEP_PX,
};
use crate::window::Window;

/// A search result: where the model fits best, and how well (mean truncated chamfer
/// distance of its outline samples, pixels).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchHit {
    /// The location found.
    pub location: Location,
    /// Mean truncated chamfer distance, pixels (0 is a perfect fit).
    pub score: f64,
}

/// How near a half pixel a sample's offset may lie and still be rounded as its sum with a
/// whole centre is, pixels: far more than the sum's rounding error (an image's
/// coordinates are below 2¹⁰, so under 2⁻⁴² px), far less than any offset's spacing.
const NEAR_HALF_PX: f64 = 1e-9;

/// How many runs of four samples [`ChamferSearch::row_sums`] adds between looks at
/// whether a row is already past the bound.
const PRUNE_EVERY: usize = 2;

/// The distance transform's value at the truncation, in its units (a third of a pixel).
const CAP: u8 = (CHAMFER_TRUNCATION_PX * 3.0) as u8;

/// Chamfer matching of the model's outline over position and scale, coarse to fine.
#[derive(Clone, Debug, Default)]
pub struct ChamferSearch {
    extractor: EdgeExtractor,
    edges: Edges,
    region: Window,
    /// The distance transforms of the two classes (3-4 chamfer units, a third of a pixel),
    /// truncated at [`CAP`], row-major over the region.
    capped: [Vec<u8>; 2],
    /// The same transforms split by column modulo [`SEARCH_STEP_PX`]: for each class,
    /// `phase × height` rows of [`ChamferSearch::phase_width`] values, the row `p · h + y`
    /// holding columns `p, p + step, …` of row `y` (padded with [`CAP`]).
    phased: [Vec<u8>; 2],
    /// The width of a row of [`ChamferSearch::phased`].
    phase_width: usize,
    /// Outline samples at scale 1: (class, x offset, y offset).
    samples: Vec<(usize, f64, f64)>,
    /// The samples at the coarse pass's scale, on whole pixels.
    grid: Grid,
    /// One grid row's sums of truncated distances, a grid centre each.
    sums: Vec<u16>,
    /// What the edges and transforms were found from, so that searches of one frame one
    /// after another (each model's, sharing this search) find them once.
    prepared: Option<PreparedFor>,
}

/// The image, region and settings edges and transforms were found from.
#[derive(Clone, Debug, PartialEq)]
struct PreparedFor {
    region: Window,
    config: TrackerConfig,
    width: usize,
    pixels: Vec<u8>,
}

/// The outline samples at one scale, as whole-pixel offsets from a centre on whole pixels:
/// `round(c + x · scale) = c + ⌊x · scale + ½⌋` for a whole `c` where the sum is not
/// negative (below 0 both are off the region), unless `x · scale` lies within
/// [`NEAR_HALF_PX`] of a half pixel, where the rounding of the sum `c + x · scale` may
/// decide: such a sample is rounded per centre.
#[derive(Clone, Debug, Default)]
struct Grid {
    /// The scale.
    scale: f64,
    /// Per sample not near a half pixel: its class and offset `(dx, dy)`, pixels.
    offsets: Vec<(usize, i64, i64)>,
    /// Per sample near a half pixel in x or y: its class and offset `(x · scale, y ·
    /// scale)`, pixels, rounded with each centre.
    ambiguous: Vec<(usize, f64, f64)>,
    /// The whole offsets' extent, `[dx_min, dx_max, dy_min, dy_max]`, pixels (all 0 when
    /// there are none).
    bounds: [i64; 4],
}

/// The best coarse hits so far, and the score a new one must beat once they are
/// [`SEARCH_REFINE`].
struct Kept {
    best: Vec<SearchHit>,
    worst: f64,
}

impl Kept {
    /// The bound a new score must not exceed to be kept.
    fn bound(&self) -> f64 {
        if self.best.len() < SEARCH_REFINE {
            f64::INFINITY
        } else {
            self.worst
        }
    }

    /// Keeps `hit` if it is among the best (see [`keep`]).
    fn offer(&mut self, hit: SearchHit) {
        keep(&mut self.best, hit, KEEP_APART_PX);
        if self.best.len() >= SEARCH_REFINE {
            self.worst = self.best.last().map_or(f64::INFINITY, |h| h.score);
        }
    }
}

impl ChamferSearch {
    /// Searches `region` of `image` for the model `features` (at scale 1, about the object
    /// centre) at scales in `scales`, and returns the best fit if any position fits the
    /// target wholly inside the region, keeping only fits that `gate` admits (none: any).
    /// `config` gives the edge settings (with the threshold already adapted).
    #[allow(clippy::too_many_arguments)]
    pub fn search(
        &mut self,
        image: GrayView<'_>,
        region: Window,
        features: &[Feature],
        half_extent_px: [f64; 2],
        scales: [f64; 2],
        config: &TrackerConfig,
        gate: Option<&AcquireGate>,
    ) -> Option<SearchHit> {
        if region.is_empty() || !(scales[0] > 0.0 && scales[1] >= scales[0]) {
            return None;
        }
        self.prepare(image, region, features, config);
        let best = self.coarse(half_extent_px, scales, gate);
        self.fine(best, half_extent_px, gate)
    }

    /// The best fit about `at`'s centre at scales in `scales`, from the transforms of the
    /// last [`ChamferSearch::search`]: each scale of a ladder [`SEARCH_SCALE_STEP`] apart,
    /// from the least, centred on `at` and refined as the fine pass refines a coarse hit;
    /// of the refined fits whose scale stayed within `scales`, the best. `None` when no
    /// scale of the ladder fits the target wholly inside the last search's region.
    pub fn best_about(
        &self,
        at: Location,
        half_extent_px: [f64; 2],
        scales: [f64; 2],
    ) -> Option<SearchHit> {
        let mut best: Option<SearchHit> = None;
        let mut scale = scales[0];
        while scale > 0.0 && scale <= scales[1] {
            let start = Location::new(at.c_x, at.c_y, scale);
            let score = self
                .inside(start, half_extent_px)
                .then(|| self.score(start, f64::INFINITY))
                .flatten();
            if let Some(score) = score {
                let hit = SearchHit {
                    location: start,
                    score,
                };
                let refined = self.fine(vec![hit], half_extent_px, None);
                if let Some(h) = refined.filter(|h| h.location.scale <= scales[1]) {
                    if best.is_none_or(|b| h.score < b.score) {
                        best = Some(h);
                    }
                }
            }
            scale *= SEARCH_SCALE_STEP;
        }
        best
    }

    /// The coarse pass: a grid of positions and scales; the best few, far enough apart.
    fn coarse(
        &mut self,
        half_extent_px: [f64; 2],
        scales: [f64; 2],
        gate: Option<&AcquireGate>,
    ) -> Vec<SearchHit> {
        let region = self.region;
        let mut kept = Kept {
            best: Vec::with_capacity(SEARCH_REFINE + 1),
            worst: f64::INFINITY,
        };
        let mut scale = scales[0];
        loop {
            let (hw, hh) = (half_extent_px[0] * scale, half_extent_px[1] * scale);
            let mut xs = (region.x0 as f64 + hw).ceil() as i64;
            let mut xe = (region.x1 as f64 - 1.0 - hw).floor() as i64;
            let mut ys = (region.y0 as f64 + hh).ceil() as i64;
            let mut ye = (region.y1 as f64 - 1.0 - hh).floor() as i64;
            // The gate's centres at this scale, once: the grid's positions inside them.
            match gate.map(|g| g.centres(scale)) {
                Some(None) => xe = xs - 1,
                Some(Some([x, y])) => {
                    (xs, xe) = within_on_grid(xs, xe, x);
                    (ys, ye) = within_on_grid(ys, ye, y);
                }
                None => {}
            }
            if xs <= xe {
                self.set_grid(scale);
                let mut y = ys;
                while y <= ye {
                    self.grid_row(y, [xs, xe], &mut kept);
                    y += SEARCH_STEP_PX as i64;
                }
            }
            if scale >= scales[1] {
                break;
            }
            scale = (scale * SEARCH_SCALE_STEP).min(scales[1]);
        }
        kept.best
    }

    /// Scores the grid's centres `x0, x0 + step, … ≤ x1` of row `y` at the grid's scale,
    /// in order, offering each to `kept`.
    fn grid_row(&mut self, y: i64, [x0, x1]: [i64; 2], kept: &mut Kept) {
        let r = self.region;
        let ry = y - r.y0 as i64;
        let fast = self.fast_span(ry, [x0 - r.x0 as i64, x1 - r.x0 as i64]);
        let n = self.samples.len().max(1) as f64;
        // Once the bound is finite it never rises (`Kept`): a row whose every fast centre
        // is already past it is none the bound will admit.
        let beyond = fast.is_some_and(|[lo, hi]| {
            let limit = kept.bound() * 3.0 * n;
            !self.row_sums(ry, lo, (hi - lo) as usize / SEARCH_STEP_PX + 1, limit)
        });
        let step = SEARCH_STEP_PX as i64;
        let mut x = x0;
        while x <= x1 {
            let bound = kept.bound();
            let rx = x - r.x0 as i64;
            let score = match fast {
                // The fast centres offer nothing: on to the first after them.
                Some([lo, hi]) if beyond && (lo..=hi).contains(&rx) => {
                    x += (hi - rx) / step * step + step;
                    continue;
                }
                Some([lo, hi]) if (lo..=hi).contains(&rx) => {
                    let sum = f64::from(self.sums[(rx - lo) as usize / SEARCH_STEP_PX]);
                    (sum <= bound * 3.0 * n).then_some(sum / (3.0 * n))
                }
                _ => self.score(Location::new(x as f64, y as f64, self.grid.scale), bound),
            };
            if let Some(score) = score {
                let location = Location::new(x as f64, y as f64, self.grid.scale);
                kept.offer(SearchHit { location, score });
            }
            x += step;
        }
    }

    /// The grid centres `lo, lo + step, … ≤ hi` of row `ry` (region coordinates, `lo` on
    /// the grid) whose whole offsets all lie in the region, when the row sums fit in 16
    /// bits (a model of fewer than `u16::MAX / CAP` samples): the first and last, those the
    /// row sums score.
    fn fast_span(&self, ry: i64, [lo, hi]: [i64; 2]) -> Option<[i64; 2]> {
        let (w, h) = (self.region.width() as i64, self.region.height() as i64);
        let b = self.grid.bounds;
        let step = SEARCH_STEP_PX as i64;
        let fits = self.samples.len() <= usize::from(u16::MAX / u16::from(CAP));
        let first = lo + ((-b[0] - lo).max(0) + step - 1) / step * step;
        let hi = hi.min(w - 1 - b[1]);
        (fits && ry + b[2] >= 0 && ry + b[3] < h && first <= hi).then_some([first, hi])
    }

    /// Sets [`ChamferSearch::sums`] to the sums of truncated distances of the `count`
    /// centres `(lo + i · step, ry)`, region coordinates, every whole offset of which lies
    /// in the region; a sample near a half pixel is rounded per centre, and counts [`CAP`]
    /// off the region, as [`ChamferSearch::score`] counts it. Returns `false`, the sums
    /// left unfinished, as soon as every centre's partial sum exceeds `limit` (the sums
    /// only grow).
    fn row_sums(&mut self, ry: i64, lo: i64, count: usize, limit: f64) -> bool {
        let step = SEARCH_STEP_PX as i64;
        let (h, pw) = (self.region.height() as i64, self.phase_width as i64);
        self.sums.clear();
        self.sums.resize(count, 0);
        let plane = |&(k, dx, dy): &(usize, i64, i64)| {
            let q = lo + dx;
            let start = (((q % step) * h + ry + dy) * pw + q / step) as usize;
            &self.phased[k][start..start + count]
        };
        // Four samples' rows added at a time: the sums are read and written a quarter as
        // often (integer sums, so the order does not matter).
        let mut fours = self.grid.offsets.chunks_exact(4);
        for (i, four) in (&mut fours).enumerate() {
            let [a, b, c, d] = [0, 1, 2, 3].map(|i| plane(&four[i]));
            for ((((sum, &a), &b), &c), &d) in self.sums.iter_mut().zip(a).zip(b).zip(c).zip(d) {
                *sum += u16::from(a) + u16::from(b) + u16::from(c) + u16::from(d);
            }
            if i % PRUNE_EVERY == PRUNE_EVERY - 1
                && f64::from(self.sums.iter().fold(u16::MAX, |m, &s| m.min(s))) > limit
            {
                return false;
            }
        }
        for offset in fours.remainder() {
            for (sum, &d) in self.sums.iter_mut().zip(plane(offset)) {
                *sum += u16::from(d);
            }
        }
        if self.grid.ambiguous.is_empty() {
            return true;
        }
        let r = self.region;
        let y = (ry + r.y0 as i64) as f64;
        for i in 0..count {
            let x = (lo + i as i64 * step + r.x0 as i64) as f64;
            for &(k, a, b) in &self.grid.ambiguous {
                self.sums[i] += u16::from(self.at(k, x + a, y + b));
            }
        }
        true
    }

    /// The truncated distance of class `k` at the image point `(x, y)` rounded to a pixel;
    /// [`CAP`] off the region.
    fn at(&self, k: usize, x: f64, y: f64) -> u8 {
        let r = self.region;
        let (w, h) = (r.width() as i64, r.height() as i64);
        let px = round_to_i64(x) - r.x0 as i64;
        let py = round_to_i64(y) - r.y0 as i64;
        if (0..w).contains(&px) && (0..h).contains(&py) {
            self.capped[k][(py * w + px) as usize]
        } else {
            CAP
        }
    }

    /// Sets the coarse pass's samples for `scale`.
    fn set_grid(&mut self, scale: f64) {
        let grid = &mut self.grid;
        grid.scale = scale;
        grid.offsets.clear();
        grid.ambiguous.clear();
        grid.bounds = [i64::MAX, i64::MIN, i64::MAX, i64::MIN];
        for &(k, x, y) in &self.samples {
            let [a, b] = [x * scale, y * scale];
            // Within rounding of a half pixel, c + a may round either way.
            let near_half = |v: f64| (v - v.floor() - 0.5).abs() < NEAR_HALF_PX;
            if near_half(a) || near_half(b) {
                grid.ambiguous.push((k, a, b));
                continue;
            }
            let dx = (a + 0.5).floor() as i64;
            let dy = (b + 0.5).floor() as i64;
            let b = &mut grid.bounds;
            (b[0], b[1]) = (b[0].min(dx), b[1].max(dx));
            (b[2], b[3]) = (b[2].min(dy), b[3].max(dy));
            grid.offsets.push((k, dx, dy));
        }
        if grid.offsets.is_empty() {
            grid.bounds = [0; 4];
        }
    }

    /// The fine pass: each kept candidate by single pixels and small scale steps, greedily;
    /// the best.
    fn fine(
        &self,
        best: Vec<SearchHit>,
        half_extent_px: [f64; 2],
        gate: Option<&AcquireGate>,
    ) -> Option<SearchHit> {
        let admitted = |at: Location| gate.is_none_or(|g| g.admits(at));
        let mut out: Option<SearchHit> = None;
        for mut hit in best {
            loop {
                let mut improved = false;
                let l = hit.location;
                for (dx, dy, ds) in NEIGHBOURS {
                    let at = Location::new(l.c_x + dx, l.c_y + dy, l.scale * ds);
                    if !self.inside(at, half_extent_px) || !admitted(at) {
                        continue;
                    }
                    if let Some(score) = self.score(at, hit.score) {
                        if score < hit.score {
                            hit = SearchHit {
                                location: at,
                                score,
                            };
                            improved = true;
                        }
                    }
                }
                if !improved {
                    break;
                }
            }
            if out.is_none_or(|o| hit.score < o.score) {
                out = Some(hit);
            }
        }
        out
    }

    /// Extracts the region's edges and builds the distance transforms (unless they were
    /// last built from the same image, region and settings), and the outline samples.
    fn prepare(
        &mut self,
        image: GrayView<'_>,
        region: Window,
        features: &[Feature],
        config: &TrackerConfig,
    ) {
        let same = self.prepared.as_ref().is_some_and(|p| {
            p.region == region
                && p.width == image.width()
                && p.config == *config
                && p.pixels == image.pixels()
        });
        if !same {
            self.prepare_edges(image, region, config);
            let mut pixels = self.prepared.take().map(|p| p.pixels).unwrap_or_default();
            pixels.clear();
            pixels.extend_from_slice(image.pixels());
            self.prepared = Some(PreparedFor {
                region,
                config: config.clone(),
                width: image.width(),
                pixels,
            });
        }
        self.samples.clear();
        for f in features {
            let k = match f.orientation {
                Orientation::Horizontal => 0,
                Orientation::Vertical => 1,
            };
            for i in 0..CHAMFER_SAMPLES {
                let t = (i as f64 + 0.5) / CHAMFER_SAMPLES as f64;
                let along = f.extent_px[0] + t * (f.extent_px[1] - f.extent_px[0]);
                let (x, y) = match f.orientation {
                    Orientation::Horizontal => (along, f.offset_px),
                    Orientation::Vertical => (f.offset_px, along),
                };
                self.samples.push((k, x, y));
            }
        }
    }

    /// Extracts the region's edges and builds the distance transforms.
    fn prepare_edges(&mut self, image: GrayView<'_>, region: Window, config: &TrackerConfig) {
        self.region = region;
        self.extractor
            .extract(image, region, config, &mut self.edges, None);
        let (w, h) = (region.width(), region.height());
        for (k, points) in [&self.edges.horizontal, &self.edges.vertical]
            .into_iter()
            .enumerate()
        {
            let dt = &mut self.capped[k];
            dt.clear();
            dt.resize(w * h, CAP);
            for p in points.iter() {
                let x = p.x.round() as i64 - region.x0 as i64;
                let y = p.y.round() as i64 - region.y0 as i64;
                if (0..w as i64).contains(&x) && (0..h as i64).contains(&y) {
                    stamp(dt, w as i64, h as i64, x, y);
                }
            }
        }
        self.split_phases();
    }

    /// Sets [`ChamferSearch::phased`] from [`ChamferSearch::capped`].
    fn split_phases(&mut self) {
        let (w, h) = (self.region.width(), self.region.height());
        let pw = w.div_ceil(SEARCH_STEP_PX);
        self.phase_width = pw;
        for (capped, phased) in self.capped.iter().zip(&mut self.phased) {
            phased.clear();
            phased.resize(SEARCH_STEP_PX * h * pw, CAP);
            for (y, row) in capped.chunks_exact(w).enumerate() {
                for (x, &d) in row.iter().enumerate() {
                    let (j, p) = (x / SEARCH_STEP_PX, x % SEARCH_STEP_PX);
                    phased[(p * h + y) * pw + j] = d;
                }
            }
        }
    }

    /// Whether a target at `at` lies wholly inside the region.
    fn inside(&self, at: Location, half_extent_px: [f64; 2]) -> bool {
        let r = self.region;
        let (hw, hh) = (half_extent_px[0] * at.scale, half_extent_px[1] * at.scale);
        at.scale > 0.0
            && at.c_x - hw >= r.x0 as f64
            && at.c_x + hw <= r.x1 as f64 - 1.0
            && at.c_y - hh >= r.y0 as f64
            && at.c_y + hh <= r.y1 as f64 - 1.0
    }

    /// The mean truncated chamfer distance of the outline at `at`, pixels; `None` when it
    /// cannot beat `bound`.
    fn score(&self, at: Location, bound: f64) -> Option<f64> {
        let n = self.samples.len().max(1) as f64;
        let limit = bound * 3.0 * n;
        let mut sum = 0u32;
        for &(k, x, y) in &self.samples {
            let d = self.at(k, at.c_x + x * at.scale, at.c_y + y * at.scale);
            sum += u32::from(d);
            if f64::from(sum) > limit {
                return None;
            }
        }
        Some(f64::from(sum) / (3.0 * n))
    }
}

/// Coarse candidates nearer than this to a better one are dropped, pixels: more than the
/// coarse step, so one fit is not kept many times, and less than the spacing of a target's
/// parallel features, so a fit one feature over is kept beside the true one.
const KEEP_APART_PX: f64 = 5.0;

/// Single-pixel and 2 % scale steps of the fine search.
const NEIGHBOURS: [(f64, f64, f64); 10] = [
    (1.0, 0.0, 1.0),
    (-1.0, 0.0, 1.0),
    (0.0, 1.0, 1.0),
    (0.0, -1.0, 1.0),
    (1.0, 1.0, 1.0),
    (-1.0, -1.0, 1.0),
    (1.0, -1.0, 1.0),
    (-1.0, 1.0, 1.0),
    (0.0, 0.0, 1.02),
    (0.0, 0.0, 1.0 / 1.02),
];

/// The grid's positions `start, start + step, … ≤ end` (step [`SEARCH_STEP_PX`]) that lie
/// within `[lo, hi]`: the first and last, the grid itself unmoved.
fn within_on_grid(start: i64, end: i64, [lo, hi]: [f64; 2]) -> (i64, i64) {
    let step = SEARCH_STEP_PX as i64;
    let lo = lo.ceil().max(start as f64);
    let first = if lo > start as f64 {
        // Clamped to the grid's own span, so the cast cannot overflow.
        let lo = lo.min((end + step) as f64) as i64;
        start + (lo - start + step - 1) / step * step
    } else {
        start
    };
    (first, end.min(hi.floor().max((start - 1) as f64) as i64))
}

/// `v.round() as i64` (half away from zero, saturating, NaN to 0), without the library
/// call `f64::round` makes on targets without a rounding instruction: `v - trunc(v)` is
/// exact for every finite `v`.
fn round_to_i64(v: f64) -> i64 {
    let t = v as i64;
    let f = v - t as f64;
    if f >= 0.5 {
        t.saturating_add(1)
    } else if f <= -0.5 {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// Keeps the best [`SEARCH_REFINE`] hits in `best`, sorted by score, no two nearer than
/// `min_apart` pixels (the nearer of two keeps the better score).
fn keep(best: &mut Vec<SearchHit>, hit: SearchHit, min_apart: f64) {
    let near = |a: &SearchHit| {
        (a.location.c_x - hit.location.c_x).abs() < min_apart
            && (a.location.c_y - hit.location.c_y).abs() < min_apart
    };
    if let Some(i) = best.iter().position(near) {
        if best[i].score <= hit.score {
            return;
        }
        best.remove(i);
    }
    let at = best.partition_point(|h| h.score <= hit.score);
    best.insert(at, hit);
    best.truncate(SEARCH_REFINE);
}

/// The truncated 3-4 chamfer distances about an edge point: `(dx, dy, distance)` for every
/// offset nearer than [`CAP`]. The 3-4 chamfer distance (Borgefors 1986; units a third of a
/// pixel) between pixels `|dx|, |dy|` apart is 3·max + min, what its two-pass transform
/// gives; beyond two pixels it is at least `CAP`.
const STAMP: [(i64, i64, u8); 25] = {
    let mut out = [(0, 0, 0); 25];
    let mut i = 0;
    while i < 25 {
        let (dx, dy) = (i as i64 % 5 - 2, i as i64 / 5 - 2);
        let (a, b) = (dx.abs(), dy.abs());
        let (max, min) = if a > b { (a, b) } else { (b, a) };
        out[i] = (dx, dy, (3 * max + min) as u8);
        i += 1;
    }
    out
};

/// Lowers the truncated distance transform `d` (`w × h`, row-major) about the edge point
/// `(x, y)`: every pixel's value is the least over the edge
/// points stamped, the whole transform's truncated at [`CAP`].
fn stamp(d: &mut [u8], w: i64, h: i64, x: i64, y: i64) {
    for (dx, dy, v) in STAMP {
        let (px, py) = (x + dx, y + dy);
        if (0..w).contains(&px) && (0..h).contains(&py) {
            let at = &mut d[(py * w + px) as usize];
            *at = (*at).min(v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 3-4 chamfer distance transform in place (Borgefors 1986), truncated at [`CAP`]: two
    /// raster passes; units are a third of a pixel. `d` holds 0 on edge points and `CAP`
    /// elsewhere; as min(min(a, C) + w, C) = min(a + w, C), every value comes out as the whole
    /// transform's, truncated. Each pass takes a row's neighbours in the row before first, then
    /// runs along the row.
    fn chamfer_34(d: &mut [u8], w: usize, h: usize) {
        let from_row = |row: &mut [u8], other: &[u8]| {
            for x in 0..w {
                let mut v = row[x].min(other[x] + 3);
                if x > 0 {
                    v = v.min(other[x - 1] + 4);
                }
                if x + 1 < w {
                    v = v.min(other[x + 1] + 4);
                }
                row[x] = v;
            }
        };
        for y in 0..h {
            let (done, rest) = d.split_at_mut(y * w);
            let row = &mut rest[..w];
            if y > 0 {
                from_row(row, &done[(y - 1) * w..]);
            }
            for x in 1..w {
                row[x] = row[x].min(row[x - 1] + 3);
            }
        }
        for y in (0..h).rev() {
            let (rest, below) = d.split_at_mut((y + 1) * w);
            let row = &mut rest[y * w..];
            if y + 1 < h {
                from_row(row, &below[..w]);
            }
            for x in (0..w.saturating_sub(1)).rev() {
                row[x] = row[x].min(row[x + 1] + 3);
            }
        }
    }

    /// The stamps give the two-pass transform's distances, truncated, on edge maps with
    /// points anywhere, the borders too.
    #[test]
    fn stamps_are_the_two_pass_transform_truncated() {
        let (w, h) = (23usize, 17usize);
        let mut seed = 12345u64;
        for round in 0..200 {
            let mut two_pass = vec![CAP; w * h];
            let mut stamped = vec![CAP; w * h];
            for _ in 0..1 + round % 9 {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let x = (seed >> 33) as usize % w;
                let y = (seed >> 13) as usize % h;
                stamp(&mut stamped, w as i64, h as i64, x as i64, y as i64);
                two_pass[y * w + x] = 0;
            }
            chamfer_34(&mut two_pass, w, h);
            assert_eq!(stamped, two_pass, "round {round}");
        }
    }

    #[test]
    fn chamfer_distance_is_exact_along_axes() {
        let (w, h) = (9, 5);
        let mut dt = vec![CAP; w * h];
        dt[2 * w + 4] = 0;
        chamfer_34(&mut dt, w, h);
        assert_eq!(dt[2 * w + 7], 9);
        assert_eq!(dt[2 * w + 8], CAP);
        assert_eq!(dt[4 * w + 8], CAP);
        assert_eq!(dt[4 * w + 4], 6);
        assert_eq!(dt[3 * w + 5], 4);
    }

    /// The coarse pass's row sums score every grid centre as scoring sample by sample does,
    /// at every scale and position, inside the region and at its borders, with samples
    /// near a half pixel or not; a row is given up only when none of its centres could
    /// pass the limit.
    #[test]
    fn grid_rows_score_as_each_sample_does() {
        use crate::synth::{benchmark_frame, nist_ten_segment};
        let model = nist_ten_segment();
        let camera = crate::Camera::default();
        let (_, pixels) = benchmark_frame(&model, &camera);
        let image = GrayView::new(256, 242, &pixels).unwrap();
        let features = model.features_px(&camera);
        let region = Window {
            x0: 20,
            y0: 10,
            x1: 230,
            y1: 200,
            size_index: 0,
        };
        let mut search = ChamferSearch::default();
        search.prepare(image, region, &features, &crate::TrackerConfig::default());
        let (w, h) = (region.width() as i64, region.height() as i64);
        let n = search.samples.len() as f64;
        let step = SEARCH_STEP_PX as i64;
        let (mut compared, mut inexact, mut pruned) = (0, 0, 0);
        for scale in [0.4, 0.77, 1.0, 1.31, 2.2] {
            search.set_grid(scale);
            inexact += usize::from(!search.grid.ambiguous.is_empty());
            let b = search.grid.bounds;
            // Every centre whose whole offsets all lie in the region, rows to its borders,
            // the grid started at each column modulo the step.
            for ry in -b[2]..h - b[3] {
                for phase in 0..step {
                    let Some([lo, hi]) = search.fast_span(ry, [phase, w]) else {
                        continue;
                    };
                    let count = ((hi - lo) / step + 1) as usize;
                    assert!(search.row_sums(ry, lo, count, f64::INFINITY));
                    let each: Vec<f64> = (lo..=hi)
                        .step_by(step as usize)
                        .map(|rx| {
                            let x = (rx + region.x0 as i64) as f64;
                            let y = (ry + region.y0 as i64) as f64;
                            search
                                .score(Location::new(x, y, scale), f64::INFINITY)
                                .unwrap()
                        })
                        .collect();
                    for (i, &each) in each.iter().enumerate() {
                        let sum = f64::from(search.sums[i]);
                        assert_eq!(sum / (3.0 * n), each, "at ({lo} + {i} · {step}, {ry})");
                        compared += 1;
                    }
                    // With a limit, a row is given up only when every centre's whole sum
                    // is past it; a row not given up is summed whole.
                    let least = f64::from(*search.sums.iter().min().unwrap());
                    for limit in [0.0, 0.5 * least, least - 1.0, least, least + 0.5] {
                        if search.row_sums(ry, lo, count, limit) {
                            let sums = search.sums.iter().map(|&s| f64::from(s) / (3.0 * n));
                            assert!(sums.eq(each.iter().copied()));
                        } else {
                            assert!(least > limit, "{least} given up at {limit}");
                            pruned += 1;
                        }
                    }
                }
            }
        }
        assert!(compared > 50_000, "{compared} compared");
        assert!(pruned > 1_000, "{pruned} rows given up");
        // Some scales put a sample within rounding of a half pixel (2.2 does, by a few
        // 1e-15 px; 1.0 has offsets of whole half pixels): both kinds of sample are tried.
        assert!((1..5).contains(&inexact), "{inexact} of 5 scales inexact");
    }

    /// Edges found for one model's search serve the next model's of the same frame and
    /// region, and another frame finds its own: every hit is what a fresh search finds.
    #[test]
    fn a_search_shared_between_models_finds_what_each_finds_alone() {
        use crate::synth::{benchmark_frame, nist_ten_segment};
        let model = nist_ten_segment();
        let camera = crate::Camera::default();
        let (at, pixels) = benchmark_frame(&model, &camera);
        // The same scene 6 px to the left: another frame of the same size.
        let mut moved = pixels.clone();
        for row in moved.chunks_exact_mut(256) {
            row.rotate_left(6);
        }
        let whole = Window {
            x0: 1,
            y0: 1,
            x1: 255,
            y1: 241,
            size_index: 0,
        };
        let all = model.features_px(&camera);
        let part = all[..6].to_vec();
        let half = [60.0, 45.0];
        let config = crate::TrackerConfig::default();
        let mut shared = ChamferSearch::default();
        let mut found = Vec::new();
        for (frame, features) in [
            (&pixels, &all),
            (&pixels, &part),
            (&moved, &part),
            (&moved, &all),
        ] {
            let image = GrayView::new(256, 242, frame).unwrap();
            let search = |s: &mut ChamferSearch| {
                s.search(image, whole, features, half, [0.8, 1.25], &config, None)
            };
            let hit = search(&mut shared);
            assert_eq!(hit, search(&mut ChamferSearch::default()));
            found.push(hit.expect("a fit").location);
        }
        // The whole model is found where it was drawn, and 6 px over on the moved frame.
        assert!(
            (found[0].c_x - at.c_x).abs() < 1.5,
            "{:?} vs {at:?}",
            found[0]
        );
        assert!(
            (found[3].c_x - (at.c_x - 6.0)).abs() < 1.5,
            "{:?}",
            found[3]
        );
    }

    /// The rounding without a library call is `f64::round`'s, cast, at halves, near them,
    /// at the cast's limits and on NaN.
    #[test]
    fn rounding_is_the_librarys() {
        let mut values = vec![f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 9.3e18, -9.3e18];
        for base in [-1e6, -513.0, -2.0, -0.0, 0.0, 1.0, 255.0, 1023.0, 4.5e15] {
            for d in [
                -0.5,
                0.5,
                -0.25,
                0.49999999999999994,
                0.5000000000000001,
                0.7,
            ] {
                let v: f64 = base + d;
                values.extend([v, v.next_up(), v.next_down()]);
            }
        }
        for v in values {
            assert_eq!(round_to_i64(v), v.round() as i64, "{v:e}");
        }
    }
}

//! The path the lead has driven, and the chase's distance from it: the `lateral_deviation_m`
//! of `frames.csv` and the `max_lateral_deviation_m` criterion.
//!
//! The deviation is the distance on the ground from the chase's rear axle to the nearest
//! point of the whole polyline the lead's rear axle has driven since the start (with the lane
//! behind the lead's start before it). Nearest over the whole path, not over a recent stretch
//! of it: a chase that stops, or falls far behind, is measured against the part of the path
//! where it is, however long ago the lead drove there. A grid of cells indexes the segments,
//! so each query looks only at the cells around the chase.

use std::collections::BTreeMap;

/// Side of a grid cell, metres.
const CELL_M: f64 = 10.0;

/// A polyline on the ground (world x, z) with a grid index of its segments.
#[derive(Clone, Debug, Default)]
pub struct DrivenPath {
    points: Vec<[f64; 2]>,
    /// Segment k joins points k and k + 1; each cell lists the segments that touch it.
    cells: BTreeMap<(i64, i64), Vec<u32>>,
    /// The cells' extent so far: min and max cell indices.
    extent: Option<[(i64, i64); 2]>,
}

fn cell_of(p: [f64; 2]) -> (i64, i64) {
    (
        (p[0] / CELL_M).floor() as i64,
        (p[1] / CELL_M).floor() as i64,
    )
}

/// Distance from `p` to the segment from `a` to `b`.
fn to_segment(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1]];
    let ap = [p[0] - a[0], p[1] - a[1]];
    let len2 = ab[0] * ab[0] + ab[1] * ab[1];
    let t = if len2 > 0.0 {
        ((ap[0] * ab[0] + ap[1] * ab[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (ap[0] - t * ab[0]).hypot(ap[1] - t * ab[1])
}

impl DrivenPath {
    /// An empty path.
    pub fn new() -> DrivenPath {
        DrivenPath::default()
    }

    /// Points so far.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether no point has been added.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Extends the path to `p`.
    ///
    /// A lead at rest (its body asleep, so at exactly the same place frame after frame)
    /// adds a point once more and then nothing: the segment from that point to itself is
    /// there already, so another would give every query the same distance again. So the
    /// path grows with the lead's movement, not with the time it stands still.
    pub fn push(&mut self, p: [f64; 2]) {
        if let [.., a, b] = self.points[..] {
            if a == p && b == p {
                return;
            }
        }
        self.extend(p);
    }

    /// Adds `p` and the segment to it, whatever it repeats.
    fn extend(&mut self, p: [f64; 2]) {
        self.points.push(p);
        let n = self.points.len();
        let a = self.points[n.saturating_sub(2)];
        let (c0, c1) = (cell_of(a), cell_of(p));
        let segment = n.saturating_sub(2) as u32;
        for i in c0.0.min(c1.0)..=c0.0.max(c1.0) {
            for j in c0.1.min(c1.1)..=c0.1.max(c1.1) {
                self.cells.entry((i, j)).or_default().push(segment);
                self.extent = Some(match self.extent {
                    None => [(i, j), (i, j)],
                    Some([lo, hi]) => [(lo.0.min(i), lo.1.min(j)), (hi.0.max(i), hi.1.max(j))],
                });
            }
        }
    }

    fn segment_distance(&self, k: u32, p: [f64; 2]) -> f64 {
        let k = k as usize;
        let b = self.points[(k + 1).min(self.points.len() - 1)];
        to_segment(self.points[k], b, p)
    }

    /// The distance from `p` to the nearest point of the path, metres (infinite for an
    /// empty path).
    pub fn distance(&self, p: [f64; 2]) -> f64 {
        let Some([lo, hi]) = self.extent else {
            return f64::INFINITY;
        };
        let (ci, cj) = cell_of(p);
        // Rings of cells around p's: every point of ring r is at least (r − 1) cells
        // away, so once the best distance is within that, no further ring can beat it.
        let reach = [ci - lo.0, hi.0 - ci, cj - lo.1, hi.1 - cj]
            .into_iter()
            .map(i64::abs)
            .max()
            .unwrap_or(0);
        let mut best = f64::INFINITY;
        for r in 0..=reach {
            if best <= (r - 1).max(0) as f64 * CELL_M {
                break;
            }
            for i in ci - r..=ci + r {
                for j in cj - r..=cj + r {
                    if (i - ci).abs() != r && (j - cj).abs() != r {
                        continue;
                    }
                    if let Some(segments) = self.cells.get(&(i, j)) {
                        for &k in segments {
                            best = best.min(self.segment_distance(k, p));
                        }
                    }
                }
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A brute-force distance to compare with.
    fn brute(points: &[[f64; 2]], p: [f64; 2]) -> f64 {
        if points.len() == 1 {
            return to_segment(points[0], points[0], p);
        }
        points
            .windows(2)
            .map(|w| to_segment(w[0], w[1], p))
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn the_grid_finds_what_brute_force_finds() {
        // A winding path of 3 km, a point every 0.6 m, with loops that come back near
        // themselves.
        let mut path = DrivenPath::new();
        let mut points = Vec::new();
        for k in 0..5000 {
            let s = k as f64 * 0.6;
            let p = [s * 0.3 + 40.0 * (s / 90.0).sin(), 60.0 * (s / 130.0).cos()];
            points.push(p);
            path.push(p);
        }
        for q in 0..400 {
            let p = [
                -50.0 + (q as f64 * 7.3) % 1000.0,
                -120.0 + (q as f64 * 13.7) % 260.0,
            ];
            let (a, b) = (path.distance(p), brute(&points, p));
            assert!((a - b).abs() < 1e-12, "{p:?}: {a} vs {b}");
        }
        assert_eq!(DrivenPath::new().distance([0.0, 0.0]), f64::INFINITY);
        let mut one = DrivenPath::new();
        one.push([3.0, 4.0]);
        assert_eq!(one.distance([0.0, 0.0]), 5.0);
    }

    #[test]
    fn a_lead_at_rest_adds_nothing_and_changes_no_distance() {
        // A winding drive with stops of 400 frames; against a path that keeps every repeat.
        let (mut path, mut every) = (DrivenPath::new(), DrivenPath::new());
        let mut p = [0.0, 0.0];
        let mut moving = 0;
        for k in 0..3000 {
            if k % 700 < 300 {
                let s = k as f64 * 0.5;
                p = [s, 5.0 * (s / 20.0).sin()];
                moving += 1;
            }
            path.push(p);
            every.extend(p);
            if k % 25 == 0 {
                for q in [[p[0], 0.3], [p[0] - 3.0, 2.5], [p[0] * 0.5, -4.0], p] {
                    assert_eq!(path.distance(q).to_bits(), every.distance(q).to_bits());
                }
            }
        }
        // Each of the four stops leaves one repeat of its point.
        assert_eq!(path.len(), moving + 4);
        assert_eq!(every.len(), 3000);
    }

    #[test]
    fn a_stopped_chase_stays_on_the_path_however_far_the_lead_drives() {
        // The lead drives 2 km with right-angle turns at 15 Hz and 7 m/s (over 4 minutes);
        // the chase stopped on its path 20 m from the start.
        let mut path = DrivenPath::new();
        let step = 7.0 / 15.0;
        let legs = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, 1.0], [1.0, 0.0]];
        let mut p = [0.0, 0.0];
        path.push(p);
        for leg in legs {
            for _ in 0..(400.0 / step) as usize {
                p = [p[0] + leg[0] * step, p[1] + leg[1] * step];
                path.push(p);
                if path.len() * 7 > 20 * 15 + 7 {
                    // Once the lead has passed it, the chase stands on its path.
                    assert!(path.distance([20.0, 0.0]) < 1e-9);
                    // A chase 0.4 m to the side of the path keeps 0.4 m.
                    assert!((path.distance([20.0, 0.4]) - 0.4).abs() < 1e-9);
                }
            }
        }
        assert!(path.len() > 4000);
    }
}

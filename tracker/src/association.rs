//! Stage 2: data association (paper 2.4, eq. 5–11).
//!
//! Each classified edge point is compared with the predicted features of its class whose
//! extent spans it (eq. 8, 10). Its distance to each is the difference of intercepts (eq. 9,
//! 11); it goes to the nearest, if nearer than ζ.

use crate::edges::{EdgeDiagnostic, EdgeFate, Edges};
use crate::model::Orientation;
use crate::prediction::PredictedFeature;

/// An edge point associated with a feature.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Association {
    /// Index of the feature in the predicted-feature list (the model's segment order).
    pub feature: usize,
    /// The point's coordinate across the feature: y for a horizontal line, x for a
    /// vertical one (the x_ij or y_ij of eq. 12).
    pub across: f32,
    /// Image x.
    pub x: f32,
    /// Image y.
    pub y: f32,
}

/// Stage 2: associates the points of `edges` with `predicted` features, into `out`
/// (cleared first). Records each point's fate in `diagnostics` when given.
pub fn associate(
    edges: &Edges,
    predicted: &[PredictedFeature],
    zeta_px: f64,
    out: &mut Vec<Association>,
    mut diagnostics: Option<&mut Vec<EdgeDiagnostic>>,
) {
    out.clear();
    let zeta = zeta_px as f32;
    for class in [Orientation::Horizontal, Orientation::Vertical] {
        // This class's features, with their numbers in the points' precision.
        let features: Vec<(usize, f32, f32, f32)> = predicted
            .iter()
            .enumerate()
            .filter(|(_, f)| f.orientation == class)
            .map(|(j, f)| {
                (
                    j,
                    f.extent[0] as f32,
                    f.extent[1] as f32,
                    f.intercept as f32,
                )
            })
            .collect();
        for p in edges.of(class) {
            // (along, across) the line: a horizontal line y = b_y spans x (eq. 8, 9).
            let (along, across) = match class {
                Orientation::Horizontal => (p.x, p.y),
                Orientation::Vertical => (p.y, p.x),
            };
            let mut best: Option<(usize, f32)> = None;
            for &(j, lo, hi, intercept) in &features {
                if !(lo < along && along < hi) {
                    continue;
                }
                let d = (intercept - across).abs();
                if best.is_none_or(|(_, bd)| d < bd) {
                    best = Some((j, d));
                }
            }
            let fate = match best {
                Some((j, d)) if d < zeta => {
                    out.push(Association {
                        feature: j,
                        across,
                        x: p.x,
                        y: p.y,
                    });
                    EdgeFate::Associated(predicted[j].segment)
                }
                _ => EdgeFate::TooFar,
            };
            if let Some(d) = diagnostics.as_deref_mut() {
                d.push(EdgeDiagnostic {
                    x: p.x,
                    y: p.y,
                    class: Some(class),
                    fate,
                });
            }
        }
    }
}

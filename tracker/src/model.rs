//! The static target model (paper 2.1.1) and its features at nominal range (2.2).
//!
//! The model is a list of corner points and a list of line segments, each segment
//! cross-referencing two corners (2.1.1). Corners are in metres from the target centre,
//! x right and y up, as the target is seen from the chase camera at `nominal_range_m`.
//! Every segment is horizontal or vertical (2.4: "a target was chosen that only contained
//! vertical and horizontal lines"); each becomes one [`Feature`].

use crate::camera::Camera;
use thiserror::Error;

/// How far (metres) two corner coordinates may differ and still count as equal when deciding
/// whether a segment is horizontal or vertical. A tenth of a millimetre is far below what the
/// camera resolves at any range, and well above float noise in hand-written files.
pub const AXIS_TOLERANCE_M: f64 = 1e-4;

/// A segment's orientation in the image (eq. 5 and 6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Orientation {
    /// A horizontal line `y = b_y` (eq. 5): its intercept is measured along the image y axis.
    Horizontal,
    /// A vertical line `x = b_x` (eq. 6): its intercept is measured along the image x axis.
    Vertical,
}

impl Orientation {
    /// A short lower-case name, for tables and logs.
    pub fn as_str(self) -> &'static str {
        match self {
            Orientation::Horizontal => "horizontal",
            Orientation::Vertical => "vertical",
        }
    }
}

/// The target model: corners and segments in metres, as read from a target file. (With the
/// `serde` feature it goes on the wire as its name, nominal range, corners, segments and
/// paint, and is checked again as [`TargetModel::new`] checks it.)
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(into = "TargetWire", try_from = "TargetWire")
)]
pub struct TargetModel {
    name: String,
    nominal_range_m: f64,
    corners_m: Vec<[f64; 2]>,
    segments: Vec<[usize; 2]>,
    features: Vec<FeatureM>,
    paint: Paint,
}

/// A target model on the wire.
#[cfg(feature = "serde")]
#[derive(serde::Serialize, serde::Deserialize)]
struct TargetWire {
    name: String,
    nominal_range_m: f64,
    corners_m: Vec<[f64; 2]>,
    segments: Vec<[usize; 2]>,
    stripes: bool,
}

#[cfg(feature = "serde")]
impl From<TargetModel> for TargetWire {
    fn from(t: TargetModel) -> TargetWire {
        TargetWire {
            stripes: t.paint == Paint::Stripes,
            name: t.name,
            nominal_range_m: t.nominal_range_m,
            corners_m: t.corners_m,
            segments: t.segments,
        }
    }
}

#[cfg(feature = "serde")]
impl TryFrom<TargetWire> for TargetModel {
    type Error = TargetError;

    fn try_from(w: TargetWire) -> Result<TargetModel, TargetError> {
        let paint = if w.stripes {
            Paint::Stripes
        } else {
            Paint::Steps
        };
        TargetModel::new(w.name, w.nominal_range_m, w.corners_m, w.segments)
            .map(|t| t.with_paint(paint))
    }
}

/// One segment of the model in metres, with its orientation resolved.
#[derive(Clone, Copy, Debug, PartialEq)]
struct FeatureM {
    orientation: Orientation,
    /// Offset of the line from the target centre across the line (metres; y up for
    /// horizontal lines, x right for vertical lines).
    offset_m: f64,
    /// Extent along the line (metres, sorted).
    extent_m: [f64; 2],
}

/// Why a target model was refused. Each names the segment (by index) it concerns.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum TargetError {
    /// `nominal_range_m` must be a positive, finite number of metres.
    #[error("nominal_range_m must be positive and finite, got {0}")]
    BadNominalRange(f64),
    /// A corner coordinate is not finite.
    #[error("corner {index} is not finite: [{x}, {y}]")]
    NonFiniteCorner {
        /// Corner index.
        index: usize,
        /// Its x.
        x: f64,
        /// Its y.
        y: f64,
    },
    /// A segment refers to a corner that does not exist.
    #[error("segment {segment} refers to corner {corner}, but there are only {corners} corners (indices 0..{corners})")]
    IndexOutOfRange {
        /// Segment index.
        segment: usize,
        /// The offending corner index.
        corner: usize,
        /// How many corners the model has.
        corners: usize,
    },
    /// A segment joins a corner to itself.
    #[error("segment {segment} joins corner {corner} to itself")]
    Degenerate {
        /// Segment index.
        segment: usize,
        /// The corner.
        corner: usize,
    },
    /// A segment's two corners lie at one point: it has no length, so no edge to find.
    #[error(
        "segment {segment} from corner {a} to corner {b} has no length (the corners are within \
         {AXIS_TOLERANCE_M} m of each other)"
    )]
    NoLength {
        /// Segment index.
        segment: usize,
        /// First corner.
        a: usize,
        /// Second corner.
        b: usize,
    },
    /// A segment is neither horizontal nor vertical.
    #[error("segment {segment} from corner {a} ({ax}, {ay}) to corner {b} ({bx}, {by}) is neither horizontal nor vertical")]
    NotAxisAligned {
        /// Segment index.
        segment: usize,
        /// First corner index.
        a: usize,
        /// Second corner index.
        b: usize,
        /// First corner x.
        ax: f64,
        /// First corner y.
        ay: f64,
        /// Second corner x.
        bx: f64,
        /// Second corner y.
        by: f64,
    },
    /// Two segments join the same pair of corners.
    #[error("segment {segment} duplicates segment {first} (corners {a} and {b})")]
    Duplicate {
        /// The later segment.
        segment: usize,
        /// The earlier one it repeats.
        first: usize,
        /// Corner a.
        a: usize,
        /// Corner b.
        b: usize,
    },
    /// Two segments lie on one line and share a stretch of it: one boundary would be two
    /// features (2.1.1: each feature is a strong edge of its own), measured twice over.
    #[error(
        "segment {segment} overlaps segment {first}: both lie on the {orientation} line at \
         {offset_m} m and share it from {from_m} m to {to_m} m (segments may meet at a \
         corner, not run along each other)"
    )]
    Overlap {
        /// The later segment.
        segment: usize,
        /// The earlier one it overlaps.
        first: usize,
        /// `horizontal` or `vertical`.
        orientation: &'static str,
        /// The line's offset from the centre, metres (y for horizontal, x for vertical).
        offset_m: f64,
        /// Where the shared stretch starts along the line, metres.
        from_m: f64,
        /// Where it ends.
        to_m: f64,
    },
    /// The model cannot determine (c_x, c_y, scale).
    #[error("the model needs at least one horizontal and one vertical segment, and two parallel segments at distinct offsets so that scale can be measured (eq. 16 must have rank 3); it has {horizontal} horizontal and {vertical} vertical segments{detail}")]
    Underdetermined {
        /// Horizontal segment count.
        horizontal: usize,
        /// Vertical segment count.
        vertical: usize,
        /// Extra explanation.
        detail: String,
    },
}

impl TargetModel {
    /// Builds and validates a model. `corners_m` are `[x, y]` in metres from the target
    /// centre (x right, y up); `segments` are pairs of corner indices.
    pub fn new(
        name: impl Into<String>,
        nominal_range_m: f64,
        corners_m: Vec<[f64; 2]>,
        segments: Vec<[usize; 2]>,
    ) -> Result<Self, TargetError> {
        if !(nominal_range_m.is_finite() && nominal_range_m > 0.0) {
            return Err(TargetError::BadNominalRange(nominal_range_m));
        }
        for (index, &[x, y]) in corners_m.iter().enumerate() {
            if !(x.is_finite() && y.is_finite()) {
                return Err(TargetError::NonFiniteCorner { index, x, y });
            }
        }
        let mut features = Vec::with_capacity(segments.len());
        for (segment, &[a, b]) in segments.iter().enumerate() {
            for corner in [a, b] {
                if corner >= corners_m.len() {
                    return Err(TargetError::IndexOutOfRange {
                        segment,
                        corner,
                        corners: corners_m.len(),
                    });
                }
            }
            if a == b {
                return Err(TargetError::Degenerate { segment, corner: a });
            }
            if let Some(first) = segments[..segment]
                .iter()
                .position(|&[c, d]| (c, d) == (a, b) || (c, d) == (b, a))
            {
                return Err(TargetError::Duplicate {
                    segment,
                    first,
                    a,
                    b,
                });
            }
            let [ax, ay] = corners_m[a];
            let [bx, by] = corners_m[b];
            if (ax - bx).abs() <= AXIS_TOLERANCE_M && (ay - by).abs() <= AXIS_TOLERANCE_M {
                return Err(TargetError::NoLength { segment, a, b });
            }
            let feature = if (ay - by).abs() <= AXIS_TOLERANCE_M {
                FeatureM {
                    orientation: Orientation::Horizontal,
                    offset_m: 0.5 * (ay + by),
                    extent_m: [ax.min(bx), ax.max(bx)],
                }
            } else if (ax - bx).abs() <= AXIS_TOLERANCE_M {
                FeatureM {
                    orientation: Orientation::Vertical,
                    offset_m: 0.5 * (ax + bx),
                    extent_m: [ay.min(by), ay.max(by)],
                }
            } else {
                return Err(TargetError::NotAxisAligned {
                    segment,
                    a,
                    b,
                    ax,
                    ay,
                    bx,
                    by,
                });
            };
            if let Some((first, from_m, to_m)) =
                features
                    .iter()
                    .enumerate()
                    .find_map(|(first, f): (usize, &FeatureM)| {
                        let from_m = f.extent_m[0].max(feature.extent_m[0]);
                        let to_m = f.extent_m[1].min(feature.extent_m[1]);
                        (f.orientation == feature.orientation
                            && (f.offset_m - feature.offset_m).abs() <= AXIS_TOLERANCE_M
                            && to_m - from_m > AXIS_TOLERANCE_M)
                            .then_some((first, from_m, to_m))
                    })
            {
                return Err(TargetError::Overlap {
                    segment,
                    first,
                    orientation: feature.orientation.as_str(),
                    offset_m: feature.offset_m,
                    from_m,
                    to_m,
                });
            }
            features.push(feature);
        }
        check_rank(&features)?;
        Ok(TargetModel {
            name: name.into(),
            nominal_range_m,
            corners_m,
            segments,
            features,
            paint: Paint::Steps,
        })
    }

    /// The model with another paint rule ([`Paint::Steps`] by default). Whether a model can
    /// be painted with steps is checked by `paint::layout`.
    pub fn with_paint(mut self, paint: Paint) -> Self {
        self.paint = paint;
        self
    }

    /// How the model's segments are painted on the board.
    pub fn paint(&self) -> Paint {
        self.paint
    }

    /// The model's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Range (metres) at which the image scale is 1 (2.1.1).
    pub fn nominal_range_m(&self) -> f64 {
        self.nominal_range_m
    }

    /// Corner points, metres, x right and y up from the target centre.
    pub fn corners_m(&self) -> &[[f64; 2]] {
        &self.corners_m
    }

    /// Segments as corner-index pairs, in file order (feature j is segment j).
    pub fn segments(&self) -> &[[usize; 2]] {
        &self.segments
    }

    /// The physical size of the target (metres): width and height of the corners' bounding
    /// box. Stage 8 (eq. 36) uses the width as `TargetSize`.
    pub fn size_m(&self) -> [f64; 2] {
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for &[x, y] in &self.corners_m {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
        [x1 - x0, y1 - y0]
    }

    /// Segment `j`'s line, metres from the target centre across it: y (up) for a horizontal
    /// segment, x (right) for a vertical one. `None` past the last segment.
    pub fn line_m(&self, j: usize) -> Option<f64> {
        self.features.get(j).map(|f| f.offset_m)
    }

    /// Each segment's orientation, in segment order.
    pub fn orientations(&self) -> impl Iterator<Item = Orientation> + '_ {
        self.features.iter().map(|f| f.orientation)
    }

    /// The model's features in pixels at nominal range (scale 1) for a camera: each
    /// feature's offset (u, v) from the object centre (2.1.1, 2.6) and its extent along the
    /// line. Image y points down, so the model's y (up) changes sign.
    pub fn features_px(&self, camera: &Camera) -> Vec<Feature> {
        let [fx, fy] = camera.focal_px();
        let kx = fx / self.nominal_range_m;
        let ky = fy / self.nominal_range_m;
        self.features
            .iter()
            .enumerate()
            .map(|(segment, f)| match f.orientation {
                Orientation::Horizontal => Feature {
                    segment,
                    orientation: Orientation::Horizontal,
                    offset_px: -f.offset_m * ky,
                    extent_px: [f.extent_m[0] * kx, f.extent_m[1] * kx],
                },
                Orientation::Vertical => Feature {
                    segment,
                    orientation: Orientation::Vertical,
                    offset_px: f.offset_m * kx,
                    extent_px: [-f.extent_m[1] * ky, -f.extent_m[0] * ky],
                },
            })
            .collect()
    }
}

/// One model feature in image pixels at nominal range (scale 1), relative to the object
/// centre. Image x right, y down.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Feature {
    /// The segment this feature is (its index in the model file).
    pub segment: usize,
    /// Horizontal (`y = b_y`, eq. 5) or vertical (`x = b_x`, eq. 6).
    pub orientation: Orientation,
    /// Offset of the line from the object centre across it: `v` for a horizontal line
    /// (image y), `u` for a vertical line (image x), pixels at scale 1 (eq. 15, 35).
    pub offset_px: f64,
    /// Extent along the line, pixels at scale 1, sorted: x range for a horizontal line,
    /// y range for a vertical one (the end points of eq. 8 and 10).
    pub extent_px: [f64; 2],
}

impl Feature {
    /// Length of the feature at scale 1, pixels.
    pub fn length_px(&self) -> f64 {
        self.extent_px[1] - self.extent_px[0]
    }
}

/// Refuses a model whose features cannot determine (c_x, c_y, scale): the design matrix of
/// eq. 16, with unit weights, must have rank 3.
fn check_rank(features: &[FeatureM]) -> Result<(), TargetError> {
    let count = |o| features.iter().filter(|f| f.orientation == o).count();
    let horizontal = count(Orientation::Horizontal);
    let vertical = count(Orientation::Vertical);
    let distinct = |o| {
        let mut offsets: Vec<f64> = features
            .iter()
            .filter(|f| f.orientation == o)
            .map(|f| f.offset_m)
            .collect();
        offsets.sort_by(f64::total_cmp);
        offsets.dedup_by(|a, b| (*a - *b).abs() <= AXIS_TOLERANCE_M);
        offsets.len()
    };
    let spread = distinct(Orientation::Horizontal) >= 2 || distinct(Orientation::Vertical) >= 2;
    if horizontal == 0 || vertical == 0 || !spread {
        let detail = if horizontal > 0 && vertical > 0 {
            ", but all parallel segments share one offset".to_string()
        } else {
            String::new()
        };
        return Err(TargetError::Underdetermined {
            horizontal,
            vertical,
            detail,
        });
    }
    Ok(())
}

/// How the segments of a target are painted (see the `paint` module for what each rule
/// puts on the board).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Paint {
    /// Each segment is one step edge between filled regions of different tone (the paper's
    /// physical features).
    #[default]
    Steps,
    /// Each segment is a thin dark stripe with two edges (not the paper's).
    Stripes,
}

impl Paint {
    /// Lower-case name, as written in target files.
    pub fn as_str(self) -> &'static str {
        match self {
            Paint::Steps => "steps",
            Paint::Stripes => "stripes",
        }
    }

    /// Parses `steps` or `stripes`.
    pub fn parse(text: &str) -> Option<Paint> {
        match text {
            "steps" => Some(Paint::Steps),
            "stripes" => Some(Paint::Stripes),
            _ => None,
        }
    }
}

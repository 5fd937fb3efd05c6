//! The road file as read: the elements carfollow reads, each with its [`Place`] in the
//! file, so that whatever is refused later is named where it stands.

use super::OpenDriveError;
use std::path::PathBuf;

/// Where an element stands: its line and how it is written.
#[derive(Clone, Debug, PartialEq)]
pub struct Place {
    /// 1-based line of the element's start.
    pub line: u32,
    /// The element's start tag, its attributes shortened (`<arc curvature="0.01">`).
    pub element: String,
}

impl Place {
    /// The error refusing this element in file `path`, saying `reason`.
    pub fn refuse(&self, path: &std::path::Path, reason: impl Into<String>) -> OpenDriveError {
        OpenDriveError::Refused {
            path: path.to_owned(),
            line: self.line,
            element: self.element.clone(),
            reason: reason.into(),
        }
    }
}

/// A whole file: its roads in file order (junctions, controllers and the like are refused
/// while reading).
#[derive(Clone, Debug, PartialEq)]
pub struct OpenDrive {
    /// The file, as errors name it.
    pub path: PathBuf,
    /// The `<road>` elements.
    pub roads: Vec<Road>,
}

/// A `<road>`.
#[derive(Clone, Debug, PartialEq)]
pub struct Road {
    /// Its `id`.
    pub id: String,
    /// Its `length`, metres.
    pub length: f64,
    /// Its `junction` (`-1` when the road is in none).
    pub junction: String,
    /// Its `rule` (`RHT` when not given).
    pub rule: String,
    /// Its `link`'s predecessor and successor.
    pub links: Vec<RoadLink>,
    /// The reference line's `<geometry>` records, in file order.
    pub geometries: Vec<Geometry>,
    /// `<laneOffset>` records.
    pub lane_offsets: Vec<Poly3Record>,
    /// `<elevation>` records.
    pub elevations: Vec<Poly3Record>,
    /// `<superelevation>` records.
    pub superelevations: Vec<Poly3Record>,
    /// `<laneSection>`s, in file order.
    pub lane_sections: Vec<LaneSection>,
    /// The first object, signal or surface description the road holds, if any (carfollow
    /// places and draws its own: refused on import).
    pub scenery: Option<Place>,
    /// Where it stands.
    pub at: Place,
}

/// A road's `<predecessor>` or `<successor>`.
#[derive(Clone, Debug, PartialEq)]
pub struct RoadLink {
    /// Whether it is the `<successor>` (else the `<predecessor>`).
    pub successor: bool,
    /// `road` or `junction`.
    pub element_type: String,
    /// The id it links to.
    pub element_id: String,
    /// Which end of the road linked to meets this one (`start` or `end`), if given.
    pub contact_point: Option<String>,
    /// Where it stands.
    pub at: Place,
}

/// A `<geometry>` of the plan view.
#[derive(Clone, Debug, PartialEq)]
pub struct Geometry {
    /// Station of its start, metres.
    pub s: f64,
    /// Start, inertial x, metres.
    pub x: f64,
    /// Start, inertial y, metres.
    pub y: f64,
    /// Heading at the start, radians (counter-clockwise from x).
    pub hdg: f64,
    /// Length, metres.
    pub length: f64,
    /// Its shape.
    pub kind: GeometryKind,
    /// Where the `<geometry>` stands.
    pub at: Place,
    /// Where its shape's element stands (`<spiral ...>`).
    pub shape_at: Place,
}

/// The shape of a `<geometry>`.
#[derive(Clone, Debug, PartialEq)]
pub enum GeometryKind {
    /// `<line/>`.
    Line,
    /// `<arc curvature>`, 1/metres, positive left.
    Arc(f64),
    /// `<spiral curvStart curvEnd>`, 1/metres.
    Spiral(f64, f64),
    /// `<poly3 a b c d>`.
    Poly3([f64; 4]),
    /// `<paramPoly3 aU..dU aV..dV pRange>`.
    ParamPoly3 {
        /// `[aU, bU, cU, dU]`.
        u: [f64; 4],
        /// `[aV, bV, cV, dV]`.
        v: [f64; 4],
        /// `pRange="normalized"` (else `arcLength`, the default).
        normalized: bool,
    },
}

/// A cubic record of the road (`laneOffset`, `elevation`, `superelevation`, a lane's
/// `width`): `a + b·ds + c·ds² + d·ds³` from station (or offset) `s`.
#[derive(Clone, Debug, PartialEq)]
pub struct Poly3Record {
    /// Where it starts: `s`, or a width's `sOffset`.
    pub s: f64,
    /// `[a, b, c, d]`.
    pub coefficients: [f64; 4],
    /// Where it stands.
    pub at: Place,
}

/// A `<laneSection>`.
#[derive(Clone, Debug, PartialEq)]
pub struct LaneSection {
    /// Its station, metres.
    pub s: f64,
    /// Its `singleSide`.
    pub single_side: bool,
    /// The lanes of `<left>` (positive ids).
    pub left: Vec<Lane>,
    /// The lanes of `<right>` (negative ids).
    pub right: Vec<Lane>,
    /// Where it stands.
    pub at: Place,
}

/// A `<lane>` of the left or right side.
#[derive(Clone, Debug, PartialEq)]
pub struct Lane {
    /// Its id.
    pub id: i32,
    /// Its `type` (`driving`, `border`, `shoulder`, ...).
    pub kind: String,
    /// Its `<width>` records.
    pub widths: Vec<Poly3Record>,
    /// Where it stands.
    pub at: Place,
}

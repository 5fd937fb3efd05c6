//! OpenDRIVE road files (ASAM OpenDRIVE 1.4–1.8): the subset carfollow can drive, read into
//! a model of the file ([`OpenDrive`], every element with its line) and turned into a
//! route ([`import`]). Whatever the subset cannot follow is refused, naming the file, the
//! line and the element; nothing is dropped silently. The scenario field
//! `route.opendrive` uses it; an OpenSCENARIO reader's `RoadNetwork/LogicFile` can too.

mod chain;
mod error;
mod geometry;
mod lanes;
mod model;
mod parse;
mod road;
mod write;

pub use chain::ChainedRoad;
pub use error::OpenDriveError;
pub use geometry::geometry_end;
pub use model::{
    Geometry, GeometryKind, Lane, LaneSection, OpenDrive, Place, Poly3Record, Road, RoadLink,
};
pub use parse::{load, parse};
pub use road::{import, ImportedRoad, JOIN_HEADING_RAD, JOIN_POSITION_M};
pub use write::{inner_lanes, write_road, ROAD_ID};

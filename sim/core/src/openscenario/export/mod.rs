//! A scenario written as ASAM OpenSCENARIO 1.2 (`.xosc`) on its route written as an
//! OpenDRIVE 1.7 road (`.xodr`), as `carfollow export` writes them.
//!
//! The mapping, the inverse of the importer's (the book's "OpenSCENARIO" page has the table):
//! - the chase is the entity `Ego`, the lead `Lead`, each actor an entity of its own name,
//!   each a `Vehicle` whose bounding box, axles and performance are its kind's;
//! - `Init` places each on its lane (`LanePosition`) with its speed (a step `SpeedAction`),
//!   the chase its camera `chase.initial_gap_m` behind the lead's back, and sets the sun,
//!   the fog and the rain (`EnvironmentAction`);
//! - one story holds a maneuver group for the lead and each actor: its speed profile as
//!   `SpeedAction`s at the profile's keys, then its events, each an `Event` whose trigger is
//!   the condition carfollow's trigger is (`SimulationTime`, `TraveledDistance`,
//!   `RelativeDistance`, `TimeHeadway`, `TimeToCollision`, `StoryboardElementState`, with
//!   its `delay`), whose action a `SpeedAction` or a `LaneChangeAction`; an event judged
//!   once a latched condition holds (an `all` whose first member is latched, as the
//!   importer reads an act that starts on a condition) in an act of its own, which that
//!   condition starts;
//! - the `StopTrigger` is the duration, and a condition group for each event whose action
//!   ends the run (`end_run`), its trigger's conditions about that event's vehicle.
//!
//! What the standard has no element for (the camera, the tracker, the chase's controller,
//! the loop, the scenery, the sensor, `[expect]`), and whatever the elements above do not
//! say exactly as carfollow reads them back, is carried as parameters named
//! `carfollow.<field>` ([`carried`]): declared at the root, unused by the storyboard, so
//! other readers pass them by, and carfollow's importer applies them as `--set` would.

mod act_start;
pub mod carried;
mod storyboard;
pub(crate) mod xml_out;

use crate::Scenario;
use storyboard::Story;
use xml_out::{a, n, XmlOut};

pub use carried::{Carried, CARRIED_PREFIX};

/// The files of one scenario.
#[derive(Clone, Debug)]
pub struct ExportedFiles {
    /// The `.xosc` text.
    pub xosc: String,
    /// The `.xodr` text.
    pub xodr: String,
    /// Whether carfollow reads the `.xodr` back as the route's very segments (else the
    /// route is to be carried whole, [`carried::route`]).
    pub road_exact: bool,
}

/// The entity names of carfollow's chase and lead.
pub const EGO: &str = "Ego";
/// The lead's entity name.
pub const LEAD: &str = "Lead";

/// The entity a carfollow vehicle name (`chase`, `lead`, an actor's) is.
pub(crate) fn entity(name: &str) -> &str {
    match name {
        "chase" => EGO,
        "lead" => LEAD,
        other => other,
    }
}

/// `scenario` as OpenSCENARIO (its road file named `xodr_file`, beside it) with the
/// parameters `carried`, and its route as OpenDRIVE.
pub fn write_files(scenario: &Scenario, xodr_file: &str, carried: &[Carried]) -> ExportedFiles {
    let (xodr, road_exact) = crate::opendrive::write_road(&scenario.route, &scenario.name);
    let mut x = XmlOut::new();
    x.open("OpenSCENARIO", &[]);
    x.empty(
        "FileHeader",
        &[
            a("revMajor", 1),
            a("revMinor", 2),
            // The epoch, so that the same scenario writes the same file.
            a("date", "1970-01-01T00:00:00"),
            a("description", &scenario.description),
            a("author", "carfollow export"),
        ],
    );
    x.comment(&format!(
        "Written by carfollow export from the scenario `{}`. Parameters named {CARRIED_PREFIX}* \
         carry carfollow's own settings, which OpenSCENARIO has no element for; carfollow's \
         importer applies them, other readers ignore them.",
        scenario.name
    ));
    if carried.is_empty() {
        x.empty("ParameterDeclarations", &[]);
    } else {
        x.open("ParameterDeclarations", &[]);
        for c in carried {
            x.empty(
                "ParameterDeclaration",
                &[
                    a("name", format!("{CARRIED_PREFIX}{}", c.path)),
                    a("parameterType", "string"),
                    a("value", &c.value),
                ],
            );
        }
        x.close();
    }
    x.empty("CatalogLocations", &[]);
    x.open("RoadNetwork", &[]);
    x.empty("LogicFile", &[a("filepath", xodr_file)]);
    x.close();
    entities(&mut x, scenario);
    let story = Story::new(scenario);
    x.open("Storyboard", &[]);
    storyboard::init(&mut x, scenario);
    story.write(&mut x);
    x.open("StopTrigger", &[]);
    storyboard::time_condition(&mut x, "end", scenario.duration_s, "greaterThan");
    story.write_stops(&mut x);
    x.close();
    x.close();
    ExportedFiles {
        xosc: x.finish(),
        xodr,
        road_exact,
    }
}

/// `Entities`: the chase, the lead (when there is one) and the actors.
fn entities(x: &mut XmlOut, s: &Scenario) {
    x.open("Entities", &[]);
    // A chase without a lead says so, or an importer would take a vehicle ahead for one.
    let no_lead = [(super::entities::LEAD_PROPERTY, super::write::NO_LEAD)];
    let ego_properties: &[(&str, &str)] = if s.has_lead { &[] } else { &no_lead };
    vehicle(
        x,
        EGO,
        ("hmmwv-m998", "car"),
        &vehicle::VehicleParams::hmmwv_m998(),
        ego_properties,
    );
    if s.has_lead {
        vehicle(
            x,
            LEAD,
            ("pickup", "car"),
            &vehicle::VehicleParams::pickup(),
            &[],
        );
    }
    for actor in &s.actors {
        let kind = actor.kind;
        // The categories the importer reads back as this kind (`entities::kind_of`).
        let category = match kind {
            sim_render::VehicleKind::Van => "van",
            sim_render::VehicleKind::Truck => "truck",
            _ => "car",
        };
        let params = crate::scenario::kind_params(kind);
        vehicle(x, &actor.name, (kind.as_str(), category), &params, &[]);
    }
    x.close();
}

/// One `ScenarioObject` with its `Vehicle`: the box about the body (x from the rear axle,
/// the entity's reference point), the axles, and what it can do.
fn vehicle(
    x: &mut XmlOut,
    name: &str,
    (model, category): (&str, &str),
    p: &vehicle::VehicleParams,
    properties: &[(&str, &str)],
) {
    let f = |v: f32| f64::from(v);
    x.open("ScenarioObject", &[a("name", name)]);
    x.open(
        "Vehicle",
        &[a("name", model), a("vehicleCategory", category)],
    );
    x.empty("ParameterDeclarations", &[]);
    x.open("BoundingBox", &[]);
    x.empty(
        "Center",
        &[
            n("x", f(p.body_centre_x_m())),
            n("y", 0.0),
            n("z", f(p.height_m) / 2.0),
        ],
    );
    x.empty(
        "Dimensions",
        &[
            n("width", f(p.width_m)),
            n("length", f(p.length_m)),
            n("height", f(p.height_m)),
        ],
    );
    x.close();
    x.empty(
        "Performance",
        &[
            n("maxSpeed", crate::openscenario::init::MAX_SPEED_MPS),
            n("maxAcceleration", f(p.max_drive_force_n) / f(p.mass_kg)),
            n("maxDeceleration", f(p.max_brake_force_n) / f(p.mass_kg)),
        ],
    );
    x.open("Axles", &[]);
    for (axle, position_x) in [("FrontAxle", f(p.wheelbase_m)), ("RearAxle", 0.0)] {
        x.empty(
            axle,
            &[
                n(
                    "maxSteering",
                    if position_x > 0.0 {
                        f(p.max_steer_rad)
                    } else {
                        0.0
                    },
                ),
                n("wheelDiameter", 2.0 * f(p.wheel_radius_m)),
                n("trackWidth", f(p.track_m)),
                n("positionX", position_x),
                n("positionZ", f(p.wheel_radius_m)),
            ],
        );
    }
    x.close();
    if properties.is_empty() {
        x.empty("Properties", &[]);
    } else {
        x.open("Properties", &[]);
        for (name, value) in properties {
            x.empty("Property", &[a("name", *name), a("value", *value)]);
        }
        x.close();
    }
    x.close();
    x.close();
}

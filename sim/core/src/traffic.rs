//! The run's vehicles in one list, and the traffic's truth: where each vehicle is on the
//! road, which one is in the chase's path, how far and how soon, and what the chase
//! touched.
//!
//! The list ([`Vehicles`]) names every vehicle of the run, in a fixed order: the follower
//! that carries the camera and the tracker (`chase`), the vehicle it follows (`lead`, in a
//! scenario that has one), then the actors in the scenario file's order. A vehicle's index
//! in the list is its index everywhere (the truth's `vehicles`, the render's actor poses
//! from [`Vehicles::first_actor`]). The list says each one's role rather than assuming two, so that a run may later
//! carry more than one follower (a platoon), each with its own camera and tracker.

use crate::plugin::LaneAhead;
use crate::record::{Contact, TrafficFrame, VehicleTruth};
use vehicle::{Route, VehicleId, VehicleParams, VehicleState};

/// How far either side of its last station a vehicle is looked for on the road, metres.
const PROJECTION_WINDOW_M: f32 = 25.0;
/// How much of its width a vehicle must have inside the chase's lane corridor to be in
/// its path, metres: a car astride the lane line is in it, one that has crossed is not.
const PATH_OVERLAP_M: f64 = 0.3;

/// How far ahead of the follower its lane is given to its tracker, metres: beyond the
/// range at which the smallest target a whole-image search can find (scale 0.4 of a 10 m
/// nominal range) stands.
const LANE_AHEAD_M: f32 = 150.0;
/// The spacing of the lane's points given to the tracker, metres.
const LANE_AHEAD_STEP_M: f32 = 2.0;

/// What part a vehicle plays in the run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// It carries the camera and the tracker, and its controller follows what the tracker
    /// sees.
    Follower,
    /// The vehicle the follower is set to follow, driven by its script.
    Lead,
    /// Another vehicle of the traffic, driven by its script.
    Actor,
}

/// One vehicle of the run.
#[derive(Clone, Debug)]
pub struct Member {
    /// Its name: `chase`, `lead`, or the actor's.
    pub name: String,
    /// What it is: `hmmwv`, `pickup`, or the actor's kind.
    pub kind: String,
    /// Its part in the run.
    pub role: Role,
    /// Its physics.
    pub params: VehicleParams,
    /// Its body centre in its physics frame (the rear axle), metres along x: where the
    /// renderer's body-centred shape sits.
    pub centre_x_m: f64,
}

/// Every vehicle of the run, in order: the follower, the lead (if there is one), then the
/// actors.
#[derive(Clone, Debug, Default)]
pub struct Vehicles {
    members: Vec<Member>,
}

impl Vehicles {
    /// The list of a run with these members (the follower first, then the lead if there is
    /// one, then the actors).
    pub(crate) fn new(members: Vec<Member>) -> Vehicles {
        debug_assert!(!members.is_empty() && members[0].role == Role::Follower);
        Vehicles { members }
    }

    /// The lead's index, when the run has a lead.
    pub fn lead(&self) -> Option<usize> {
        self.members.iter().position(|m| m.role == Role::Lead)
    }

    /// The first actor's index: the actors are the members from here on.
    pub fn first_actor(&self) -> usize {
        1 + usize::from(self.lead().is_some())
    }

    /// Every member, in order.
    pub fn members(&self) -> &[Member] {
        &self.members
    }

    /// The member called `name`, and its index.
    pub fn named(&self, name: &str) -> Option<(usize, &Member)> {
        self.members
            .iter()
            .enumerate()
            .find(|(_, m)| m.name == name)
    }
}

/// A vehicle on the road: its station and its offset from lane 1's centre, its speed, and
/// its bumpers' stations.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Place {
    /// Its rear axle's station along the route, metres.
    pub station_m: f64,
    /// Its offset from lane 1's centre, metres (positive left).
    pub offset_m: f64,
    /// Its forward speed, m/s.
    pub speed_mps: f64,
    /// Its front bumper's station, metres.
    pub front_m: f64,
    /// Its rear bumper's station, metres.
    pub rear_m: f64,
}

/// Where the vehicles are on the road, followed step by step (each one is looked for near
/// where it was last).
#[derive(Clone, Debug)]
pub(crate) struct Road {
    /// Lane 1's centre: the drivers' route.
    route: Route,
    lane_width_m: f64,
    /// Lanes each way.
    lanes: u32,
    /// Each lane's centre, metres right of lane 1's, and its width, when the lanes differ
    /// in width (else empty: lane k is `k − 1` widths right of lane 1).
    own_lanes: Vec<[f64; 2]>,
    hints: Vec<f32>,
}

impl Road {
    /// The road of `route` (lane 1's centre) with the lanes of `spec`, for vehicles
    /// starting at these stations.
    pub(crate) fn new(route: Route, spec: &sim_render::RouteSpec, stations_m: &[f64]) -> Road {
        let own_lanes = if spec.lane_widths_m.is_empty() {
            Vec::new()
        } else {
            (1..=spec.lanes)
                .map(|k| {
                    [
                        spec.lane_centre_m(k) - spec.lane_centre_m(1),
                        spec.lane_width_of(k),
                    ]
                })
                .collect()
        };
        Road {
            route,
            lane_width_m: spec.lane_width_m,
            lanes: spec.lanes,
            own_lanes,
            hints: stations_m.iter().map(|&s| s as f32).collect(),
        }
    }

    /// The lane whose centre is nearest `right_m` metres right of lane 1's, with its
    /// centre there and its width, metres.
    fn lane_near(&self, right_m: f64) -> (u32, f64, f64) {
        if self.own_lanes.is_empty() {
            let w = self.lane_width_m;
            let lane = (1.0 + right_m / w)
                .round()
                .clamp(1.0, f64::from(self.lanes));
            // Lane k's centre is (k − 1) lane widths right of lane 1's.
            return (lane as u32, (lane - 1.0) * w, w);
        }
        let (k, [centre, w]) = self
            .own_lanes
            .iter()
            .enumerate()
            .min_by(|a, b| {
                (a.1[0] - right_m)
                    .abs()
                    .total_cmp(&(b.1[0] - right_m).abs())
            })
            .expect("a road has a lane");
        (k as u32 + 1, *centre, *w)
    }

    /// Where each vehicle is, from its state (in the list's order).
    pub(crate) fn places(&mut self, vehicles: &Vehicles, states: &[VehicleState]) -> Vec<Place> {
        states
            .iter()
            .zip(&vehicles.members)
            .zip(&mut self.hints)
            .map(|((state, member), hint)| {
                let p = self.route.project_near(
                    state.world_from_vehicle.translation,
                    *hint,
                    PROJECTION_WINDOW_M,
                );
                *hint = p.s_m;
                let station_m = f64::from(p.s_m);
                Place {
                    station_m,
                    offset_m: f64::from(p.left_offset_m),
                    speed_mps: f64::from(state.forward_speed_mps),
                    front_m: station_m + f64::from(member.params.front_bumper_x_m()),
                    rear_m: station_m + f64::from(member.params.rear_bumper_x_m()),
                }
            })
            .collect()
    }

    /// Whether vehicle `i` at `places` reaches [`PATH_OVERLAP_M`] into the lane corridor of
    /// the follower `me` (a lane's width, centred on it), whether ahead of it or not.
    pub(crate) fn in_corridor(
        &self,
        vehicles: &Vehicles,
        places: &[Place],
        me: usize,
        i: usize,
    ) -> bool {
        let half_width = 0.5 * f64::from(vehicles.members[i].params.width_m);
        let (_, _, lane_width_m) = self.lane_near(-places[me].offset_m);
        (places[i].offset_m - places[me].offset_m).abs()
            < 0.5 * lane_width_m + half_width - PATH_OVERLAP_M
    }

    /// The lane the follower at `position` is in (the one whose centre is nearest), ahead
    /// of it to [`LANE_AHEAD_M`], in the frame of the camera at `world_from_camera`: what
    /// the follower's tracker is told of its lane. Looked for near the follower's station
    /// at the last [`Road::places`].
    pub(crate) fn lane_ahead(
        &self,
        position: vehicle::Vector,
        world_from_camera: &nalgebra::Isometry3<f64>,
    ) -> LaneAhead {
        let here = self
            .route
            .project_near(position, self.hints[0], PROJECTION_WINDOW_M);
        let (_, right_m, w) = self.lane_near(-f64::from(here.left_offset_m));
        let camera_from_world = world_from_camera.inverse();
        let end_m = self.route.length_m();
        let mut centre_m = Vec::new();
        let mut s = here.s_m;
        while s <= (here.s_m + LANE_AHEAD_M).min(end_m) {
            let p = self.route.point_at(s) - self.route.left_at(s) * right_m as f32;
            let c = camera_from_world * nalgebra::Point3::new(f64::from(p.x), 0.0, f64::from(p.z));
            if c.z > 0.0 && centre_m.last().is_none_or(|l: &[f64; 3]| c.z > l[2]) {
                centre_m.push([c.x, c.y, c.z]);
            }
            s += LANE_AHEAD_STEP_M;
        }
        LaneAhead {
            centre_m,
            half_width_m: 0.5 * w,
        }
    }

    /// The vehicle in the path of the follower at `me`: the nearest ahead of it whose body
    /// reaches [`PATH_OVERLAP_M`] into its lane corridor (a lane's width, centred on the
    /// follower), and the gap to it, bumper to bumper.
    pub(crate) fn in_path(
        &self,
        vehicles: &Vehicles,
        places: &[Place],
        me: usize,
    ) -> Option<(usize, f64)> {
        let mine = places[me];
        places
            .iter()
            .enumerate()
            .filter(|&(i, p)| {
                i != me && p.rear_m > mine.station_m && self.in_corridor(vehicles, places, me, i)
            })
            .map(|(i, p)| (i, p.rear_m - mine.front_m))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }
}

/// The traffic's truth at a frame, and the index of the vehicle in the chase's path and
/// every vehicle's place, from which it was made.
pub(crate) struct FrameTruth {
    pub(crate) frame: TrafficFrame,
    pub(crate) path: Option<usize>,
    pub(crate) places: Vec<Place>,
}

/// The traffic's truth at a frame: the vehicle in the chase's path, the gap and the time to
/// collision, every vehicle's place, and what `tracked` (the vehicle whose target the
/// estimate is on) is; `log` holds the events and contacts since the frame before.
pub(crate) fn truth(
    road: &mut Road,
    vehicles: &Vehicles,
    states: &[VehicleState],
    tracked: Option<usize>,
    log: (Vec<String>, Vec<Contact>),
) -> FrameTruth {
    let places = road.places(vehicles, states);
    let path = road.in_path(vehicles, &places, 0);
    let (gap, closing) = path.map_or((f64::NAN, f64::NAN), |(i, gap)| {
        (gap, places[0].speed_mps - places[i].speed_mps)
    });
    let ttc = if path.is_none() {
        f64::NAN
    } else if closing > 0.0 {
        gap.max(0.0) / closing
    } else {
        f64::INFINITY
    };
    let name = |i: usize| vehicles.members[i].name.clone();
    let frame = TrafficFrame {
        path_vehicle: path.map(|(i, _)| name(i)),
        path_gap_m: gap,
        path_closing_mps: closing,
        path_ttc_s: ttc,
        // The camera's truth, which the loop's judgement has (`closed_loop::traffic_truth`).
        path_range_m: f64::NAN,
        tracked_vehicle: tracked.map(name),
        events: log.0,
        contacts: log.1,
        vehicles: vehicles
            .members
            .iter()
            .zip(states)
            .zip(&places)
            .map(|((m, s), p)| {
                let t = s.world_from_vehicle.translation;
                let forward = s.world_from_vehicle.rotation * vehicle::Vector::X;
                VehicleTruth {
                    name: m.name.clone(),
                    kind: m.kind.clone(),
                    xz: [f64::from(t.x), f64::from(t.z)],
                    heading_rad: f64::from(vehicle::direction_heading(forward)),
                    speed_mps: p.speed_mps,
                    station_m: p.station_m,
                    offset_m: p.offset_m,
                }
            })
            .collect(),
    };
    FrameTruth {
        frame,
        path: path.map(|(i, _)| i),
        places,
    }
}

/// The contacts of the follower (the first vehicle of the list) with the others: each
/// vehicle it touches after a physics step and did not after the step before, with the
/// speed it was closing at as it came into contact: the speeds before that step, since the
/// step's contact solver has already taken most of the closing speed away (a chase hitting
/// a standing car at 43 km/h leaves that step closing at less than nothing).
pub(crate) struct Contacts {
    touching: Vec<bool>,
    /// Each vehicle's forward speed after the step before, m/s (`None` before the first).
    speeds_before: Option<Vec<f32>>,
    /// The contacts not yet taken into a frame's record.
    pub(crate) log: Vec<Contact>,
}

impl Contacts {
    /// No contact yet among `vehicles` vehicles.
    pub(crate) fn new(vehicles: usize) -> Contacts {
        Contacts {
            touching: vec![false; vehicles],
            speeds_before: None,
            log: Vec::new(),
        }
    }

    /// Checks the world after a step (`ids` in the list's order); returns whether the
    /// follower touches any vehicle.
    pub(crate) fn check(
        &mut self,
        world: &vehicle::World,
        ids: &[VehicleId],
        vehicles: &Vehicles,
    ) -> bool {
        let mut any = false;
        let speeds: Vec<f32> = ids
            .iter()
            .map(|&id| world.vehicle_state(id).forward_speed_mps)
            .collect();
        let before = self.speeds_before.take().unwrap_or_else(|| speeds.clone());
        for (i, &id) in ids.iter().enumerate().skip(1) {
            let touch = world.vehicles_touch(ids[0], id);
            if touch && !self.touching[i] {
                let mine = before[0];
                let theirs = before[i];
                self.log.push(Contact {
                    vehicle: vehicles.members[i].name.clone(),
                    t_s: world.now().seconds(),
                    closing_mps: f64::from(mine - theirs),
                });
            }
            self.touching[i] = touch;
            any |= touch;
        }
        self.speeds_before = Some(speeds);
        any
    }
}

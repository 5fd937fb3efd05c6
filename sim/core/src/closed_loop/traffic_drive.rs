//! The traffic's side of the physics: at every step the lead's events and the actors'
//! drivers (each with its events) run on the traffic as it stands, and after the step the
//! chase's contacts with every other vehicle are checked. What happened goes into the log
//! that the frame's record takes.

use crate::plan::PlannedTraffic;
use crate::plugin::LaneAhead;
use crate::record::Contact;
use crate::traffic::{Contacts, Road, Vehicles};
use nalgebra::{Isometry3, Translation3};
use vehicle::{
    ActorDriver, Controls, Events, Fired, FiredKind, LeadDriver, Step, VehicleId, VehicleState,
    VehicleView, World,
};

/// The traffic's drivers and what they did.
pub(super) struct TrafficDrive {
    pub(super) vehicles: Vehicles,
    /// Every vehicle's physics, in the list's order.
    pub(super) ids: Vec<VehicleId>,
    actors: Vec<ActorDriver>,
    lead_events: Events,
    road: Road,
    contacts: Contacts,
    /// The pairs of vehicles (indices in the list) whose contact a trigger watches, each
    /// once: checked before every step, for the view's `touching`.
    watched_contacts: Vec<(usize, usize)>,
    /// Events started and ended since the log was last taken.
    events: Vec<String>,
    /// The first event whose action ended the run, if one has.
    pub(super) ended: Option<RunEnd>,
}

/// An event that ended the run (its action `end_run`).
#[derive(Clone, Debug, PartialEq)]
pub struct RunEnd {
    /// The physics step its action started at.
    pub step: Step,
    /// The vehicle whose event it is.
    pub vehicle: String,
    /// The event's name.
    pub event: String,
}

impl TrafficDrive {
    /// The traffic of a plan whose chase and lead are `chase_id` and `lead_id` (a run
    /// without a lead has none).
    pub(super) fn new(
        planned: PlannedTraffic,
        chase_id: VehicleId,
        lead_id: Option<VehicleId>,
    ) -> Self {
        let mut ids = vec![chase_id];
        ids.extend(lead_id);
        ids.extend(planned.actor_ids);
        let first = planned.vehicles.first_actor();
        let lead = planned.vehicles.lead().map(|me| (me, &planned.lead_events));
        let actors = (planned.actors.iter().enumerate()).map(|(k, a)| (first + k, a.events()));
        let mut watched_contacts: Vec<(usize, usize)> = lead
            .into_iter()
            .chain(actors)
            .flat_map(|(me, events)| {
                let watched = events.contacts_watched().into_iter();
                watched.map(move |j| (me.min(j), me.max(j)))
            })
            .collect();
        watched_contacts.sort_unstable();
        watched_contacts.dedup();
        TrafficDrive {
            contacts: Contacts::new(ids.len()),
            watched_contacts,
            ids,
            vehicles: planned.vehicles,
            actors: planned.actors,
            lead_events: planned.lead_events,
            road: planned.road,
            events: Vec::new(),
            ended: None,
        }
    }

    /// The chase's lane ahead, seen from the camera at `world_from_camera`, the chase in
    /// state `chase` (see [`Road::lane_ahead`]).
    pub(super) fn lane_ahead(
        &self,
        chase: &VehicleState,
        world_from_camera: &Isometry3<f64>,
    ) -> LaneAhead {
        self.road
            .lane_ahead(chase.world_from_vehicle.translation, world_from_camera)
    }

    /// Step `now`'s drivers: the lead's events steer `lead` (when the run has one), whose
    /// controls are returned for its vehicle in state `lead_state`; each actor's driver
    /// sets its controls.
    pub(super) fn drive(
        &mut self,
        world: &mut World,
        lead: Option<(&mut LeadDriver, &VehicleState)>,
        now: Step,
    ) -> Option<Controls> {
        let states: Vec<VehicleState> =
            self.ids.iter().map(|&id| world.vehicle_state(id)).collect();
        let mut view: Vec<VehicleView> = self
            .road
            .places(&self.vehicles, &states)
            .iter()
            .map(|p| VehicleView {
                station_m: p.station_m,
                left_offset_m: p.offset_m,
                speed_mps: p.speed_mps,
                front_m: p.front_m,
                rear_m: p.rear_m,
                touching: 0,
            })
            .collect();
        // The contacts a trigger watches, as the last step left them.
        for &(a, b) in &self.watched_contacts {
            let fits = b < u64::BITS as usize;
            if a != b && fits && world.vehicles_touch(self.ids[a], self.ids[b]) {
                view[a].touching |= 1 << b;
                view[b].touching |= 1 << a;
            }
        }
        let lead_controls = match (lead, self.vehicles.lead()) {
            (Some((lead, lead_state)), Some(me)) => {
                if !self.lead_events.is_empty() {
                    let fired = self.lead_events.update(now, &view, me);
                    lead.set_lateral_offset_m(self.lead_events.lateral_offset_m() as f32);
                    lead.set_speed_override(self.lead_events.speed_override());
                    self.log(me, fired);
                    self.note_end(me, self.lead_events.run_ended());
                }
                Some(lead.update(now, lead_state))
            }
            _ => None,
        };
        let first = self.vehicles.first_actor();
        for k in 0..self.actors.len() {
            let me = first + k;
            let (controls, fired) = self.actors[k].update(now, &states[me], &view, me);
            world.set_controls(self.ids[me], controls);
            self.log(me, fired);
            self.note_end(me, self.actors[k].events().run_ended());
        }
        lead_controls
    }

    /// Notes that vehicle `me`'s event `ended` (step, index) ended the run, unless one did
    /// before (the first in the list's order, at one step).
    fn note_end(&mut self, me: usize, ended: Option<(Step, usize)>) {
        if self.ended.is_some() {
            return;
        }
        if let Some((step, i)) = ended {
            let first = self.vehicles.first_actor();
            let events = if me < first {
                &self.lead_events
            } else {
                self.actors[me - first].events()
            };
            self.ended = Some(RunEnd {
                step,
                vehicle: self.vehicles.members()[me].name.clone(),
                event: events.name(i).to_string(),
            });
        }
    }

    /// Checks the world after a step: whether the chase touches any other vehicle.
    pub(super) fn touching(&mut self, world: &World) -> bool {
        self.contacts.check(world, &self.ids, &self.vehicles)
    }

    /// The events and the contacts since the log was last taken, emptied.
    pub(super) fn take_log(&mut self) -> (Vec<String>, Vec<Contact>) {
        (
            std::mem::take(&mut self.events),
            std::mem::take(&mut self.contacts.log),
        )
    }

    /// Every vehicle's state now, in the list's order.
    pub(super) fn states(&self, world: &World) -> Vec<VehicleState> {
        self.ids.iter().map(|&id| world.vehicle_state(id)).collect()
    }

    /// The actors' poses as the renderer draws them (their bodies' centres), from every
    /// vehicle's `states`.
    pub(super) fn actor_poses(&self, states: &[VehicleState]) -> Vec<Isometry3<f64>> {
        let first = self.vehicles.first_actor();
        self.actor_states(states)
            .iter()
            .zip(&self.vehicles.members()[first..])
            .map(|(s, m)| {
                crate::plan::iso(&s.world_from_vehicle) * Translation3::new(m.centre_x_m, 0.0, 0.0)
            })
            .collect()
    }

    /// The actors' part of every vehicle's `states` (the list's order).
    pub(super) fn actor_states<'a>(&self, states: &'a [VehicleState]) -> &'a [VehicleState] {
        &states[self.vehicles.first_actor()..]
    }

    /// Logs what vehicle `me`'s events did.
    fn log(&mut self, me: usize, fired: Vec<Fired>) {
        let name = &self.vehicles.members()[me].name;
        for f in fired {
            let what = match f.kind {
                FiredKind::Started => "started",
                FiredKind::Ended => "ended",
            };
            self.events.push(format!("{name}/{}:{what}", f.name));
        }
    }
}

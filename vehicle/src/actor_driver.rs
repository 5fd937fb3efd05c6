//! A scripted vehicle's driver: the lead's driver ([`LeadDriver`]) steered by the vehicle's
//! events ([`Events`]).

use crate::clock::Step;
use crate::controls::Controls;
use crate::events::{Events, Fired, TrafficView};
use crate::lead_driver::LeadDriver;
use crate::ray_cast_vehicle::VehicleState;

/// Drives one vehicle of the traffic (or the lead, when its scenario scripts events): at
/// each step its events run first, then the driver follows the lateral offset and the
/// speed they ask for (the profile's speed until a speed action starts).
///
/// With no events it drives exactly as its [`LeadDriver`] alone does. A vehicle that
/// stands still is a driver whose profile is a constant 0 ([`crate::SpeedProfile::constant`]):
/// its speed loop holds the brake.
#[derive(Clone, Debug)]
pub struct ActorDriver {
    driver: LeadDriver,
    events: Events,
}

impl ActorDriver {
    /// `driver` steered by `events`.
    pub fn new(driver: LeadDriver, events: Events) -> ActorDriver {
        ActorDriver { driver, events }
    }

    /// Commands for step `now` from the vehicle's true `state`, the traffic `view` and the
    /// vehicle's own index `me` in it; with the events that started and ended at `now`.
    pub fn update(
        &mut self,
        now: Step,
        state: &VehicleState,
        view: &TrafficView,
        me: usize,
    ) -> (Controls, Vec<Fired>) {
        let fired = self.events.update(now, view, me);
        if !self.events.is_empty() {
            self.driver
                .set_lateral_offset_m(self.events.lateral_offset_m() as f32);
            self.driver.set_speed_override(self.events.speed_override());
        }
        (self.driver.update(now, state), fired)
    }

    /// The driver.
    pub fn driver(&self) -> &LeadDriver {
        &self.driver
    }

    /// The events.
    pub fn events(&self) -> &Events {
        &self.events
    }
}

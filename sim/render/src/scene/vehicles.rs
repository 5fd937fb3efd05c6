//! The moving objects, each in its own frame and slot: the chase vehicle's hood, the lead
//! with its board, the oncoming traffic, and the actors the description places.

use super::car::{car, CarBody};
use super::description::ChaseVehicle;
use super::dynamic_object::{DynamicObject, Motion};
use super::lead::lead_vehicle;
use super::mesh::Mesh;
use super::object_slot::ObjectSlot;
use super::site::Site;
use super::tail_lamps::TailLamps;
use super::vehicle_kind::vehicle;
use rand::Rng;

/// Appends the moving objects to `mesh`, in this order: the chase hood, the lead with its
/// board (unless the description has none), the oncoming vehicles (as many as the description's density puts on the
/// route and the next minute's driving, at most [`ObjectSlot::MAX_ONCOMING`]), and the
/// description's actors.
pub(super) fn lay_objects(site: &Site<'_>, mesh: &mut Mesh) -> Vec<DynamicObject> {
    let description = site.description;
    let mut objects = vec![DynamicObject::appended(
        mesh,
        hood(&description.chase),
        ObjectSlot::CHASE,
        false,
        Motion::Chase,
    )];
    if !description.without_lead {
        objects.push(DynamicObject::appended(
            mesh,
            lead_vehicle(description),
            ObjectSlot::LEAD,
            true,
            Motion::Lead,
        ));
    }
    lay_oncoming(site, mesh, &mut objects);
    lay_actors(site, mesh, &mut objects);
    objects
}

/// Appends the description's actors, actor k in slot [`ObjectSlot::FIRST_ACTOR`] + k,
/// casting shadows, moved by [`Motion::Actor`].
fn lay_actors(site: &Site<'_>, mesh: &mut Mesh, objects: &mut Vec<DynamicObject>) {
    for (k, actor) in site.description.actors.iter().enumerate() {
        let slot = ObjectSlot::FIRST_ACTOR + k as u32;
        let mut part = Mesh::default();
        vehicle(&mut part, slot, actor.albedo, actor.kind);
        if actor.tail_lamps {
            TailLamps::add_to_kind(&mut part, slot, actor.kind);
        }
        let motion = Motion::Actor(k);
        objects.push(DynamicObject::appended(mesh, part, slot, true, motion));
    }
}

/// The chase vehicle's hood, in the chase's frame.
fn hood(chase: &ChaseVehicle) -> Mesh {
    let mut hood = Mesh::default();
    hood.aabb(
        [
            chase.hood_back_m,
            chase.hood_height_m - 0.6,
            -0.5 * chase.hood_width_m,
        ],
        [
            chase.hood_front_m,
            chase.hood_height_m,
            0.5 * chase.hood_width_m,
        ],
        0.45,
        ObjectSlot::CHASE,
    );
    hood
}

/// Appends the oncoming cars, each in a slot of its own, drawn from the scene's
/// `"oncoming-vehicles"` stream, their bodies from `"oncoming-vehicle-bodies"`.
fn lay_oncoming(site: &Site<'_>, mesh: &mut Mesh, objects: &mut Vec<DynamicObject>) {
    let d = &site.description.densities;
    let mut oncoming = site.stream("oncoming-vehicles");
    let mut oncoming_bodies = site.stream("oncoming-vehicle-bodies");
    let span = site.length + d.oncoming_speed_m_s * 60.0;
    let n = Site::count(d.oncoming_vehicles_per_km, span).min(ObjectSlot::MAX_ONCOMING as usize);
    for k in 0..n {
        let slot = ObjectSlot::FIRST_ONCOMING + k as u32;
        let mut part = Mesh::default();
        car(
            &mut part,
            slot,
            oncoming.random_range(0.1..0.8),
            CarBody::pick(oncoming_bodies.random_range(0.0..1.0)),
        );
        let start_m = oncoming.random_range(0.0..span);
        let motion = Motion::Oncoming {
            start_m,
            speed_m_s: d.oncoming_speed_m_s,
        };
        objects.push(DynamicObject::appended(mesh, part, slot, true, motion));
    }
}

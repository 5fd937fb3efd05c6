//! Parked vehicles on the right shoulder.

use super::bins::Bins;
use super::car::{car, CarBody};
use super::layer::Layer;
use super::mesh::Mesh;
use super::object_slot::ObjectSlot;
use super::site::Site;
use super::standing::stand;
use nalgebra::{Point3, Vector3};
use rand::Rng;

/// Lays the parked cars along the right shoulder, clear of intersections, drawn from the
/// scene's `"parked-vehicles"` stream, their bodies from `"parked-vehicle-bodies"`: each
/// built in its own frame, moved to its place on the route, and stood on the ground.
pub(super) fn lay_row(site: &Site<'_>, bins: &mut Bins) {
    let (route, road_half, length) = (site.route, site.road_half, site.length);
    let mut parked = site.stream("parked-vehicles");
    let mut parked_bodies = site.stream("parked-vehicle-bodies");
    for _ in 0..Site::count(site.description.densities.parked_vehicles_per_km, length) {
        let s = parked.random_range(0.0..length);
        if route.near_intersection(s, road_half + 8.0) {
            continue;
        }
        let pose = route.pose_at(s, road_half + 1.3);
        let mut car_mesh = Mesh::default();
        car(
            &mut car_mesh,
            ObjectSlot::WORLD,
            parked.random_range(0.1..0.8),
            CarBody::pick(parked_bodies.random_range(0.0..1.0)),
        );
        for v in &mut car_mesh.vertices {
            let p = pose
                * Point3::new(
                    f64::from(v.position[0]),
                    f64::from(v.position[1]),
                    f64::from(v.position[2]),
                );
            let n = pose.rotation
                * Vector3::new(
                    f64::from(v.normal[0]),
                    f64::from(v.normal[1]),
                    f64::from(v.normal[2]),
                );
            v.position = [p.x as f32, p.y as f32, p.z as f32];
            v.normal = [n.x as f32, n.y as f32, n.z as f32];
        }
        stand(site.terrain, &mut car_mesh);
        let t = pose.translation.vector;
        bins.at(t.x, t.z, Layer::Clutter).append(&car_mesh);
    }
}

//! Where the builders lay the scene: the route, the ground's height field and the road's
//! frame along the route, in which strips of surface are laid.

use super::description::SceneDescription;
use super::mesh::{Mesh, Vertex};
use super::rng::stream;
use super::route::Route;
use super::terrain::Terrain;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Width of the paved shoulder beyond each lane, metres.
pub(super) const SHOULDER_M: f64 = 0.5;
/// How far the road continues straight past either end of the route, metres, so the camera
/// never sees the road end.
pub(super) const ROAD_RUNOUT_M: f64 = 250.0;

/// What every builder lays against: the description, the route, the ground, and the
/// road's frame, in which a point is a station along the centreline and a lateral offset
/// (right).
pub(super) struct Site<'a> {
    /// The description being built.
    pub description: &'a SceneDescription,
    /// The route the road follows.
    pub route: &'a Route,
    /// The ground's height field, if it has bumps: strips over it are cut into cells.
    pub terrain: Option<&'a Terrain>,
    /// The width of one direction's lanes together, metres (`lanes` lanes): the edge line
    /// runs just beyond it.
    pub lanes_width: f64,
    /// Half the paved road's width (one direction's lanes and its shoulder), metres.
    pub road_half: f64,
    /// The route's length, metres.
    pub length: f64,
}

impl<'a> Site<'a> {
    /// The site of `description`'s scene, along `route`, over `terrain`.
    pub fn new(
        description: &'a SceneDescription,
        route: &'a Route,
        terrain: Option<&'a Terrain>,
    ) -> Site<'a> {
        let lanes_width = description.route.lanes_width_m();
        Site {
            description,
            route,
            terrain,
            lanes_width,
            road_half: lanes_width + SHOULDER_M,
            length: route.length_m(),
        }
    }

    /// The scene's random stream `name` (see [`stream`]).
    pub fn stream(&self, name: &str) -> ChaCha8Rng {
        stream(self.description.seed, name)
    }

    /// A station for a roadside item, drawn from `rng` between 50 m before the route's
    /// start and 100 m past its end; `None` within `margin_m` of an intersection.
    pub fn clear_station(&self, rng: &mut ChaCha8Rng, margin_m: f64) -> Option<f64> {
        let s = rng.random_range(-50.0..self.length + 100.0);
        (!self.route.near_intersection(s, margin_m)).then_some(s)
    }

    /// How many items `per_km` make over `span_m` metres.
    pub fn count(per_km: f64, span_m: f64) -> usize {
        (per_km * span_m / 1000.0).round() as usize
    }

    /// The world point at station `s`, `lateral` metres right of the centreline, `y` up.
    pub fn world(&self, s: f64, lateral: f64, y: f64) -> [f64; 3] {
        let [x, z] = self.route.point(s, lateral);
        [x, y, z]
    }

    /// A strip of road-parallel surface from station `s0` to `s1`, lateral `l0` to `l1`
    /// (`[s0, s1, l0, l1]`), static, its vertices' `object` being `object` (the world's slot
    /// and a [`Material`](crate::scene::Material)).
    pub fn strip(
        &self,
        mesh: &mut Mesh,
        [s0, s1, l0, l1]: [f64; 4],
        y: f64,
        albedo: f64,
        object: u32,
    ) {
        let corners = [
            self.world(s0, l0, y),
            self.world(s1, l0, y),
            self.world(s1, l1, y),
            self.world(s0, l1, y),
        ];
        let pitch = self
            .terrain
            .filter(|t| corners.iter().any(|c| t.covers(c[0], c[2])))
            .map(|t| t.cell_m());
        let Some(pitch) = pitch else {
            mesh.polygon(&corners, albedo, object);
            return;
        };
        // Over bumps, a grid of pieces no longer than a cell, sharing vertices, for
        // `Terrain::drape` to raise.
        let (ns, nl) = (
            ((s1 - s0) / pitch).ceil().max(1.0) as usize,
            ((l1 - l0).abs() / pitch).ceil().max(1.0) as usize,
        );
        let base = mesh.vertices.len() as u32;
        for i in 0..=ns {
            for j in 0..=nl {
                let p = self.world(
                    s0 + (s1 - s0) * i as f64 / ns as f64,
                    l0 + (l1 - l0) * j as f64 / nl as f64,
                    y,
                );
                mesh.vertices.push(Vertex {
                    position: p.map(|x| x as f32),
                    normal: [0.0, 1.0, 0.0],
                    albedo: albedo as f32,
                    object,
                });
            }
        }
        let at = |i: usize, j: usize| base + (i * (nl + 1) + j) as u32;
        for i in 0..ns {
            for j in 0..nl {
                // The winding of the polygon above: (s0, l0), (s1, l0), (s1, l1), (s0, l1).
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                mesh.indices.extend_from_slice(&[a, b, c, a, c, d]);
            }
        }
    }
}

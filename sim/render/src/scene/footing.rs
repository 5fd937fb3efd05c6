//! The frame of an object standing on the ground: where it stands and which way it faces.

use super::mesh::Mesh;
use super::object_slot::ObjectSlot;

/// Axes of a ground-standing object with the given heading: forward, up, right.
fn axes(heading: f64) -> [[f64; 3]; 3] {
    let (s, c) = heading.sin_cos();
    [[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]]
}

/// A ground-standing object's frame: its centre on the ground plane, its axes forward (u)
/// and right (w), and the height of its base.
pub(super) struct Footing {
    at: [f64; 2],
    u: [f64; 3],
    w: [f64; 3],
}

impl Footing {
    /// The frame of an object standing at `at` on the ground plane, facing `heading`.
    pub(super) fn new(at: [f64; 2], heading: f64) -> Footing {
        let [u, _, w] = axes(heading);
        Footing { at, u, w }
    }

    /// The world point `a` along u, `y` up, `b` along w.
    pub(super) fn p(&self, a: f64, y: f64, b: f64) -> [f64; 3] {
        [
            self.at[0] + a * self.u[0] + b * self.w[0],
            y,
            self.at[1] + a * self.u[2] + b * self.w[2],
        ]
    }

    /// The world direction `a` along u plus `b` along w.
    pub(super) fn dir(&self, a: f64, b: f64) -> [f64; 3] {
        [
            a * self.u[0] + b * self.w[0],
            0.0,
            a * self.u[2] + b * self.w[2],
        ]
    }

    /// The box axes: u, up, w.
    pub(super) fn axes(&self) -> [[f64; 3]; 3] {
        [self.u, [0.0, 1.0, 0.0], self.w]
    }

    /// The object's body: a box standing on the ground, `half` its half length (along u)
    /// and width (along w), `height` tall, static.
    pub(super) fn body(&self, mesh: &mut Mesh, half: [f64; 2], height: f64, albedo: f64) {
        let [h0, h1] = half;
        mesh.standing_box(
            self.p(0.0, 0.5 * height, 0.0),
            self.axes(),
            [h0, 0.5 * height, h1],
            albedo,
            ObjectSlot::WORLD,
        );
    }
}

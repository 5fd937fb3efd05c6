//! The car: the shape of a parked or oncoming car, in its own frame, in one of a few
//! bodies.

use super::mesh::Mesh;

/// Albedo of a car's glass: darker than any body paint, bumper or tyre.
pub(super) const CAR_GLASS_ALBEDO: f64 = 0.07;
/// Albedo of a car's bumpers.
pub(super) const CAR_BUMPER_ALBEDO: f64 = 0.10;
/// Albedo of a car's tyres.
const TYRE_ALBEDO: f64 = 0.04;
/// Albedo of a car's wheel hubs.
const HUB_ALBEDO: f64 = 0.55;
/// Albedo of a car's head lamps and tail lamps (lens glass catching the light).
const LAMP_ALBEDO: f64 = 0.85;
/// Half the length of a car over its bumpers, metres.
pub(super) const CAR_HALF_LENGTH_M: f64 = 2.2;
/// Half the width of a car over its wheels, metres.
pub(super) const CAR_HALF_WIDTH_M: f64 = 0.9;
/// The bumpers' bottom and top above the ground, metres.
const BUMPER_Y_M: [f64; 2] = [0.26, 0.55];
/// How far inside the body's sides the bumpers end, metres.
const BUMPER_INSET_M: f64 = 0.05;
/// The tail lamps' bottom and top above the ground, metres.
const TAIL_LAMP_Y_M: [f64; 2] = [0.68, 0.86];
/// The head lamps' bottom and top above the ground, metres.
const HEAD_LAMP_Y_M: [f64; 2] = [0.66, 0.80];
/// How far inside the body's side each lamp's inner and outer edges are, metres.
const LAMP_INSET_M: [f64; 2] = [0.32, 0.06];
/// How far inside the body's side the cabin's bottom and its roof are, metres.
const CABIN_INSET_M: [f64; 2] = [0.06, 0.16];
/// The windscreen's and the rear window's glass: its inset from the face's bottom and top,
/// as a share of the face's height, and from its sides, metres.
const GLASS_INSET: (f64, f64) = (0.1, 0.08);

/// The shapes of car body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum CarBody {
    /// A saloon: bonnet, cabin, boot.
    Sedan,
    /// A hatchback: bonnet, a cabin reaching to the tail.
    Hatchback,
    /// A van: a short bonnet and a tall box to the tail.
    Van,
}

impl CarBody {
    /// The body for a draw of a uniform number in [0, 1): sedans most often, then
    /// hatchbacks, then vans.
    pub(super) fn pick(u: f64) -> CarBody {
        if u < 0.5 {
            CarBody::Sedan
        } else if u < 0.8 {
            CarBody::Hatchback
        } else {
            CarBody::Van
        }
    }
}

/// What a car's back shows the camera behind it, metres in the car's frame (heights above
/// the ground; half widths from the centre line, z): the numbers the car is built from,
/// for the target model of its back (`back_model`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct CarBack {
    /// The body's back face (x, negative), inside the bumper.
    pub face_x: f64,
    /// The body's half width.
    pub side: f64,
    /// The top of the body, where the cabin stands (the belt line).
    pub belt: f64,
    /// Whether the cabin's back stands on the body's back face (a van's): the belt line is
    /// then only a change of paint, and none where the pillars' paint is the body's.
    pub cabin_on_face: bool,
    /// The roof's height.
    pub roof: f64,
    /// The cabin's half width at the belt and at the roof.
    pub cabin: [f64; 2],
    /// The rear window's glass: its bottom and top.
    pub glass_y: [f64; 2],
    /// Its half width at its bottom and at its top.
    pub glass_half: [f64; 2],
    /// The tail lamps' bottom and top.
    pub lamp_y: [f64; 2],
    /// Their inner and outer edges (half widths).
    pub lamp_z: [f64; 2],
    /// The bumper's bottom and top.
    pub bumper_y: [f64; 2],
    /// Its half width.
    pub bumper_half: f64,
}

impl CarBack {
    /// The back of `body`, from the shape [`car`] builds.
    pub(super) fn of(body: CarBody) -> CarBack {
        let shape = Shape::of(body, 0, 0.0);
        let (cw0, cw1) = shape.cabin_widths();
        let (v, inset) = GLASS_INSET;
        let at = |t: f64| shape.belt + t * (shape.roof - shape.belt);
        let half = |t: f64| cw0 + t * (cw1 - cw0) - inset;
        CarBack {
            face_x: -shape.end,
            side: shape.side,
            belt: shape.belt,
            cabin_on_face: shape.rear0 <= -shape.end,
            roof: shape.roof,
            cabin: [cw0, cw1],
            glass_y: [at(v), at(1.0 - v)],
            glass_half: [half(v), half(1.0 - v)],
            lamp_y: TAIL_LAMP_Y_M,
            lamp_z: LAMP_INSET_M.map(|d| shape.side - d),
            bumper_y: BUMPER_Y_M,
            bumper_half: shape.side - BUMPER_INSET_M,
        }
    }
}

impl CarBody {
    /// The drawn body's height over the ground (its roof), metres.
    pub(super) fn height_m(self) -> f64 {
        Shape::of(self, 0, 0.0).roof
    }
}

/// A car in its own frame (x forward, y up, z right, origin on the ground under its
/// centre), within ±[`CAR_HALF_LENGTH_M`] × ±[`CAR_HALF_WIDTH_M`]: a lower body in its
/// paint, a cabin with a sloped windscreen and rear window of dark glass and side windows
/// between lighter pillars, dark bumpers at both ends, head and tail lamps, and wheels
/// with light hubs. About a hundred triangles.
pub(super) fn car(mesh: &mut Mesh, slot: u32, albedo: f64, body: CarBody) {
    let shape = Shape::of(body, slot, albedo);
    shape.lower_body(mesh);
    shape.lamps(mesh);
    shape.cabin(mesh);
    shape.wheels(mesh);
}

/// Half a car's length over its bumpers, metres.
const HL: f64 = CAR_HALF_LENGTH_M;
/// Half a car's width over its wheels, metres.
const HW: f64 = CAR_HALF_WIDTH_M;

/// A car's body, its sizes and its colour, in its own frame.
struct Shape {
    /// Which body.
    body: CarBody,
    /// Its vertices' slot.
    slot: u32,
    /// Its paint.
    albedo: f64,
    /// The body's ends, inside the bumpers (±x).
    end: f64,
    /// The body's sides, just inside the wheels (±z).
    side: f64,
    /// Side profile: the body's top (y).
    belt: f64,
    /// The cabin's bottom rear (x).
    rear0: f64,
    /// Its top rear (x).
    rear1: f64,
    /// Its top front (x).
    front1: f64,
    /// Its bottom front (x).
    front0: f64,
    /// The roof's height.
    roof: f64,
    /// Where the axles are (±x).
    wheel_x: f64,
}

impl Shape {
    /// The shape of `body` in `slot`, painted `albedo`.
    fn of(body: CarBody, slot: u32, albedo: f64) -> Shape {
        // The body's ends, inside the bumpers; its sides, just inside the wheels.
        let end = HL - 0.15;
        let side = HW - 0.03;
        // Side profile: the body's top, the cabin's bottom rear and front, its top rear and
        // front (x), and the roof's height.
        let (belt, rear0, rear1, front1, front0, roof) = match body {
            CarBody::Sedan => (0.95, -1.35, -0.95, 0.45, 1.05, 1.45),
            CarBody::Hatchback => (0.95, -1.95, -1.72, 0.30, 1.00, 1.50),
            CarBody::Van => (1.05, -end, -end, 1.00, 1.70, 1.95),
        };
        let wheel_x = if body == CarBody::Van { 1.45 } else { 1.35 };
        Shape {
            body,
            slot,
            albedo,
            end,
            side,
            belt,
            rear0,
            rear1,
            front1,
            front0,
            roof,
            wheel_x,
        }
    }

    /// A box standing from `min` to `max` along the car's axes.
    fn standing(&self, mesh: &mut Mesh, min: [f64; 3], max: [f64; 3], albedo: f64) {
        let axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        mesh.standing_box(
            [
                0.5 * (min[0] + max[0]),
                0.5 * (min[1] + max[1]),
                0.5 * (min[2] + max[2]),
            ],
            axes,
            [
                0.5 * (max[0] - min[0]),
                0.5 * (max[1] - min[1]),
                0.5 * (max[2] - min[2]),
            ],
            albedo,
            self.slot,
        );
    }

    /// Lower body and bumpers.
    fn lower_body(&self, mesh: &mut Mesh) {
        let (end, side) = (self.end, self.side);
        self.standing(
            mesh,
            [-end, 0.32, -side],
            [end, self.belt, side],
            self.albedo,
        );
        for sx in [-1.0, 1.0] {
            let (a, b) = if sx > 0.0 { (end, HL) } else { (-HL, -end) };
            let [y0, y1] = BUMPER_Y_M;
            let half = side - BUMPER_INSET_M;
            self.standing(mesh, [a, y0, -half], [b, y1, half], CAR_BUMPER_ALBEDO);
        }
    }

    /// Lamps on the body's ends, above the bumpers: head lamps in front, tail lamps behind.
    fn lamps(&self, mesh: &mut Mesh) {
        for (sx, [y0, y1]) in [(1.0, HEAD_LAMP_Y_M), (-1.0, TAIL_LAMP_Y_M)] {
            for sz in [-1.0, 1.0] {
                let x = sx * (self.end + 0.005);
                let [inner, outer] = LAMP_INSET_M;
                let (z0, z1) = (sz * (self.side - inner), sz * (self.side - outer));
                mesh.quad_with_normal(
                    [[x, y0, z0], [x, y0, z1], [x, y1, z1], [x, y1, z0]],
                    [sx, 0.0, 0.0],
                    LAMP_ALBEDO,
                    self.slot,
                );
            }
        }
    }

    /// The cabin's half widths at its bottom and at the roof.
    fn cabin_widths(&self) -> (f64, f64) {
        (self.side - CABIN_INSET_M[0], self.side - CABIN_INSET_M[1])
    }

    /// The colour of the cabin's pillars.
    fn pillar(&self) -> f64 {
        self.albedo.max(0.35)
    }

    /// The cabin: a prism of trapezoid section, narrowing towards the roof; its roof, its
    /// windscreen and rear window, and its sides.
    fn cabin(&self, mesh: &mut Mesh) {
        let (rear1, front1, roof) = (self.rear1, self.front1, self.roof);
        let (_, cw1) = self.cabin_widths();
        let roof_quad = [
            [rear1, roof, -cw1],
            [front1, roof, -cw1],
            [front1, roof, cw1],
            [rear1, roof, cw1],
        ];
        mesh.quad_with_normal(roof_quad, [0.0, 1.0, 0.0], self.albedo, self.slot);
        self.windows(mesh);
        self.cabin_sides(mesh);
    }

    /// Windscreen and rear window: the sloped faces in the pillars' colour, the glass just
    /// proud of them with a frame all round.
    fn windows(&self, mesh: &mut Mesh) {
        let (belt, roof) = (self.belt, self.roof);
        let (cw0, cw1) = self.cabin_widths();
        for (x_low, x_high, sx) in [
            (self.front0, self.front1, 1.0),
            (self.rear0, self.rear1, -1.0),
        ] {
            let face = [
                [x_low, belt, -cw0],
                [x_low, belt, cw0],
                [x_high, roof, cw1],
                [x_high, roof, -cw1],
            ];
            let normal = outward(face, [sx, 0.0, 0.0]);
            mesh.quad_with_normal(face, normal, self.pillar(), self.slot);
            let lerp = |a: [f64; 3], b: [f64; 3], t: f64| {
                [
                    a[0] + t * (b[0] - a[0]),
                    a[1] + t * (b[1] - a[1]),
                    a[2] + t * (b[2] - a[2]),
                ]
            };
            // Inset: 10 % of the height at top and bottom, 8 cm at the sides.
            let (v, side) = GLASS_INSET;
            let lo = [lerp(face[0], face[3], v), lerp(face[1], face[2], v)];
            let hi = [
                lerp(face[0], face[3], 1.0 - v),
                lerp(face[1], face[2], 1.0 - v),
            ];
            let squeeze = |p: [f64; 3]| [p[0], p[1], p[2] - p[2].signum() * side];
            let glass = [
                squeeze(lo[0]),
                squeeze(lo[1]),
                squeeze(hi[1]),
                squeeze(hi[0]),
            ];
            mesh.quad_with_normal(
                glass.map(|p| proud(p, normal, 0.008)),
                normal,
                CAR_GLASS_ALBEDO,
                self.slot,
            );
        }
    }

    /// The cabin's side `sz` at height fraction v: its point at fraction t from rear to
    /// front.
    fn cabin_at(&self, v: f64, sz: f64) -> impl Fn(f64) -> [f64; 3] + '_ {
        let (cw0, cw1) = self.cabin_widths();
        move |t: f64| -> [f64; 3] {
            let xr = self.rear0 + v * (self.rear1 - self.rear0);
            let xf = self.front0 + v * (self.front1 - self.front0);
            [
                xr + t * (xf - xr),
                self.belt + v * (self.roof - self.belt),
                sz * (cw0 + v * (cw1 - cw0)),
            ]
        }
    }

    /// The sides: pillars' colour, with two side windows (one for a van's cab) between the
    /// pillars.
    fn cabin_sides(&self, mesh: &mut Mesh) {
        for sz in [-1.0, 1.0] {
            let bottom = self.cabin_at(0.0, sz);
            let top = self.cabin_at(1.0, sz);
            let face = [bottom(0.0), bottom(1.0), top(1.0), top(0.0)];
            let normal = outward(face, [0.0, 0.0, sz]);
            mesh.quad_with_normal(face, normal, self.pillar(), self.slot);
            let (v0, v1) = (0.12, 0.86);
            let lo = self.cabin_at(v0, sz);
            let hi = self.cabin_at(v1, sz);
            let spans: &[(f64, f64)] = match self.body {
                CarBody::Van => &[(0.62, 0.93)],
                _ => &[(0.06, 0.47), (0.53, 0.94)],
            };
            for &(t0, t1) in spans {
                let glass = [lo(t0), lo(t1), hi(t1), hi(t0)];
                mesh.quad_with_normal(
                    glass.map(|p| proud(p, normal, 0.008)),
                    normal,
                    CAR_GLASS_ALBEDO,
                    self.slot,
                );
            }
        }
    }

    /// Wheels: dark tyres standing on the ground, light hubs on their outer faces.
    fn wheels(&self, mesh: &mut Mesh) {
        for x in [-self.wheel_x, self.wheel_x] {
            for sz in [-1.0, 1.0] {
                let (z_in, z_out) = (sz * (HW - 0.22), sz * HW);
                self.standing(
                    mesh,
                    [x - 0.33, 0.0, z_in.min(z_out)],
                    [x + 0.33, 0.64, z_in.max(z_out)],
                    TYRE_ALBEDO,
                );
                let z = sz * (HW + 0.004);
                mesh.quad_with_normal(
                    [
                        [x - 0.15, 0.17, z],
                        [x + 0.15, 0.17, z],
                        [x + 0.15, 0.47, z],
                        [x - 0.15, 0.47, z],
                    ],
                    [0.0, 0.0, sz],
                    HUB_ALBEDO,
                    self.slot,
                );
            }
        }
    }
}

/// The unit normal of the flat quad `corners`, turned to agree with `towards`.
fn outward(corners: [[f64; 3]; 4], towards: [f64; 3]) -> [f64; 3] {
    let d1 = sub(corners[1], corners[0]);
    let d2 = sub(corners[3], corners[0]);
    let n = [
        d1[1] * d2[2] - d1[2] * d2[1],
        d1[2] * d2[0] - d1[0] * d2[2],
        d1[0] * d2[1] - d1[1] * d2[0],
    ];
    let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let sign = if n[0] * towards[0] + n[1] * towards[1] + n[2] * towards[2] < 0.0 {
        -1.0
    } else {
        1.0
    };
    n.map(|c| sign * c / length)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `p` moved `d` metres along `normal`.
fn proud(p: [f64; 3], normal: [f64; 3], d: f64) -> [f64; 3] {
    [
        p[0] + d * normal[0],
        p[1] + d * normal[1],
        p[2] + d * normal[2],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::test_support::{quads_of, triangles};

    #[test]
    fn a_car_fits_its_footprint_with_bumpers_lamps_wheels_and_glass() {
        let mut shapes = Vec::new();
        for body in [CarBody::Sedan, CarBody::Hatchback, CarBody::Van] {
            let mut mesh = Mesh::default();
            car(&mut mesh, 5, 0.45, body);
            assert!(mesh.vertices.iter().all(|v| v.object == 5), "slot");
            let extent = |k: usize, f: fn(f64, f64) -> f64, start: f64| {
                mesh.vertices
                    .iter()
                    .map(|v| f64::from(v.position[k]))
                    .fold(start, f)
            };
            let tol = 1e-5;
            assert!(extent(0, f64::max, f64::MIN) <= CAR_HALF_LENGTH_M + tol);
            assert!(extent(0, f64::min, f64::MAX) >= -CAR_HALF_LENGTH_M - tol);
            assert!(extent(2, f64::max, f64::MIN) <= CAR_HALF_WIDTH_M + 0.005 + tol);
            assert!(extent(2, f64::min, f64::MAX) >= -CAR_HALF_WIDTH_M - 0.005 - tol);
            assert_eq!(extent(1, f64::min, f64::MAX), 0.0, "{body:?} on the ground");
            // Bumper faces at both ends, facing out.
            for sx in [-1.0f64, 1.0] {
                assert!(
                    quads_of(&mesh, CAR_BUMPER_ALBEDO).iter().any(|q| q
                        .iter()
                        .all(|p| (p[0] - sx * CAR_HALF_LENGTH_M).abs() < tol)),
                    "{body:?}: bumper at {sx}"
                );
                // A lamp on each corner of each end.
                let lamps = quads_of(&mesh, LAMP_ALBEDO)
                    .into_iter()
                    .filter(|q| q[0][0] * sx > 0.0)
                    .count();
                assert_eq!(lamps, 2, "{body:?}: lamps at {sx}");
            }
            // Glass facing forward, backward and to both sides, in an albedo nothing else
            // of the car has.
            let glass = quads_of(&mesh, CAR_GLASS_ALBEDO);
            let facing = |d: [f32; 3]| {
                mesh.vertices.iter().any(|v| {
                    (f64::from(v.albedo) - CAR_GLASS_ALBEDO).abs() < 1e-6
                        && v.normal[0] * d[0] + v.normal[1] * d[1] + v.normal[2] * d[2] > 0.5
                })
            };
            for d in [
                [1.0, 0.0, 0.0],
                [-1.0, 0.0, 0.0],
                [0.0, 0.0, 1.0],
                [0.0, 0.0, -1.0],
            ] {
                assert!(facing(d), "{body:?}: glass facing {d:?}");
            }
            let glass_vertices = 4 * glass.len();
            let dark_as_glass = mesh
                .vertices
                .iter()
                .filter(|v| (f64::from(v.albedo) - CAR_GLASS_ALBEDO).abs() < 0.02)
                .count();
            assert_eq!(dark_as_glass, glass_vertices, "{body:?}: glass is distinct");
            // Four hubs, lighter than the tyres, on the wheels' outer faces.
            let hubs = quads_of(&mesh, HUB_ALBEDO);
            assert_eq!(hubs.len(), 4);
            eprintln!("{body:?}: {} triangles", triangles(&mesh));
            assert!(
                triangles(&mesh) < 160,
                "{body:?}: {} triangles",
                triangles(&mesh)
            );
            shapes.push(extent(1, f64::max, f64::MIN));
        }
        assert!(shapes[2] > shapes[0] + 0.3, "a van is taller: {shapes:?}");
    }
}

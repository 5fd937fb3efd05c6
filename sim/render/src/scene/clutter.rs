//! The standing clutter's shapes: houses, flat-roofed buildings, cars (parked and
//! oncoming), and the overpass, each built in its own frame or placed by its footprint.

use super::build::{Bins, Layer, ObjectSlot};
use super::mesh::Mesh;
use super::route::Route;
use super::terrain::Terrain;

/// An overpass across the route at `station_m`: a deck 1 m thick, `deck_m` wide along the
/// route and reaching 12 m beyond the road's edges, on two abutment walls that stand on the
/// ground (over bumps, from the lowest ground under each up to the deck).
#[allow(clippy::too_many_arguments)]
pub(super) fn overpass(
    bins: &mut Bins,
    route: &Route,
    terrain: Option<&Terrain>,
    road_half: f64,
    station_m: f64,
    deck_m: f64,
    height_m: f64,
) {
    let [x, z, heading] = route.at(station_m);
    let along = [heading.cos(), 0.0, -heading.sin()];
    let across = [heading.sin(), 0.0, heading.cos()];
    let reach = road_half + 12.0;
    let mesh = bins.at(x, z, Layer::Clutter);
    mesh.oriented_box(
        [x, height_m + 0.5, z],
        [along, [0.0, 1.0, 0.0], across],
        [0.5 * deck_m, 0.5, reach],
        0.5,
        ObjectSlot::WORLD,
    );
    for side in [-1.0, 1.0] {
        let l = side * (road_half + 4.0);
        let c = [x + l * across[0], z + l * across[2]];
        let corner = |a: f64, b: f64| {
            [
                c[0] + a * along[0] + b * across[0],
                c[1] + a * along[2] + b * across[2],
            ]
        };
        let (ha, hb) = (0.5 * deck_m, 0.4);
        let base = ground_under(
            terrain,
            &[
                corner(-ha, -hb),
                corner(ha, -hb),
                corner(ha, hb),
                corner(-ha, hb),
            ],
        );
        mesh.oriented_box(
            [c[0], 0.5 * (base + height_m), c[1]],
            [along, [0.0, 1.0, 0.0], across],
            [ha, 0.5 * (height_m - base), hb],
            0.55,
            ObjectSlot::WORLD,
        );
    }
}

/// The lowest height of the ground under a footprint (world plan points: its corners, or
/// any points it spans): sampled at the corners and at the terrain's cells over their
/// bounding box, so that nothing standing at that height leaves a gap under it. 0 on flat
/// ground.
pub(super) fn ground_under(terrain: Option<&Terrain>, footprint: &[[f64; 2]]) -> f64 {
    let Some(t) = terrain else {
        return 0.0;
    };
    let (mut min, mut max) = ([f64::MAX; 2], [f64::MIN; 2]);
    let mut lowest = f64::MAX;
    for &[x, z] in footprint {
        min = [min[0].min(x), min[1].min(z)];
        max = [max[0].max(x), max[1].max(z)];
        lowest = lowest.min(t.height_m(x, z));
    }
    if footprint.is_empty() {
        return 0.0;
    }
    let pitch = t.cell_m();
    let n = [
        ((max[0] - min[0]) / pitch).ceil() as usize,
        ((max[1] - min[1]) / pitch).ceil() as usize,
    ];
    for i in 0..=n[0] {
        for j in 0..=n[1] {
            let x = (min[0] + i as f64 * pitch).min(max[0]);
            let z = (min[1] + j as f64 * pitch).min(max[1]);
            lowest = lowest.min(t.height_m(x, z));
        }
    }
    lowest
}

/// Stands an item built on flat ground (world frame, its footprint the vertices at y = 0)
/// on the terrain: raises (or lowers) all of it to the lowest ground under its footprint,
/// so that its base meets the ground there and sinks into it elsewhere, never floating.
/// Returns the height it was moved by (0 with no terrain, leaving it untouched).
pub(super) fn stand(terrain: Option<&Terrain>, mesh: &mut Mesh) -> f64 {
    if terrain.is_none() {
        return 0.0;
    }
    let footprint: Vec<[f64; 2]> = mesh
        .vertices
        .iter()
        .filter(|v| v.position[1].abs() < 1e-4)
        .map(|v| [f64::from(v.position[0]), f64::from(v.position[2])])
        .collect();
    let base = ground_under(terrain, &footprint);
    if base != 0.0 {
        for v in &mut mesh.vertices {
            v.position[1] = (f64::from(v.position[1]) + base) as f32;
        }
    }
    base
}

/// Height of a telephone pole's top, metres.
pub(super) const POLE_TOP_M: f64 = 9.0;
/// Height of a pole's cross-arm, metres.
const ARM_Y_M: f64 = 8.4;
/// Height of a pole's lower cross-arm, metres.
const LOWER_ARM_Y_M: f64 = 7.6;
/// Albedo of a telephone pole.
pub(super) const POLE_ALBEDO: f64 = 0.30;
/// Albedo of insulators (glazed porcelain).
const INSULATOR_ALBEDO: f64 = 0.78;

/// What a telephone pole carries besides its cross-arm and insulators.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum PoleFittings {
    /// Nothing more.
    Plain,
    /// A second, shorter cross-arm below the first, with its own insulators.
    LowerArm,
    /// A transformer can hung on the side away from the road.
    Transformer,
}

impl PoleFittings {
    /// The fittings for a draw of a uniform number in [0, 1): half the poles are plain.
    pub(super) fn pick(u: f64) -> PoleFittings {
        if u < 0.5 {
            PoleFittings::Plain
        } else if u < 0.75 {
            PoleFittings::LowerArm
        } else {
            PoleFittings::Transformer
        }
    }
}

/// A telephone pole on flat ground at `at`, its cross-arm across `heading` (along its
/// right), with an insulator near each end of the arm and its fittings. Returns the tops
/// of the two outer insulators, where the wires hang from.
pub(super) fn pole(
    mesh: &mut Mesh,
    at: [f64; 2],
    heading: f64,
    fittings: PoleFittings,
) -> [[f64; 3]; 2] {
    let f = Footing::new(at, heading);
    mesh.upright_box(
        at[0],
        at[1],
        heading,
        0.13,
        0.13,
        0.0,
        POLE_TOP_M,
        POLE_ALBEDO,
    );
    let arm = |mesh: &mut Mesh, y: f64, reach: f64, insulators: &[f64]| {
        mesh.beam(f.p(0.0, y, -reach), f.p(0.0, y, reach), 0.06, 0.28);
        for &b in insulators {
            mesh.standing_box(
                f.p(0.0, y + 0.06 + 0.1, b),
                f.axes(),
                [0.045, 0.1, 0.045],
                INSULATOR_ALBEDO,
                ObjectSlot::WORLD,
            );
        }
    };
    arm(mesh, ARM_Y_M, 1.0, &[-0.9, -0.35, 0.9]);
    match fittings {
        PoleFittings::Plain => {}
        PoleFittings::LowerArm => arm(mesh, LOWER_ARM_Y_M, 0.7, &[-0.6, 0.6]),
        PoleFittings::Transformer => {
            // A can on a bracket, on the pole's side away from the road.
            mesh.beam(f.p(0.0, 6.9, 0.0), f.p(0.0, 6.9, 0.45), 0.04, POLE_ALBEDO);
            mesh.oriented_box(
                f.p(0.0, 6.4, 0.45),
                f.axes(),
                [0.27, 0.45, 0.27],
                0.42,
                ObjectSlot::WORLD,
            );
        }
    }
    let top = ARM_Y_M + 0.06 + 0.2;
    [f.p(0.0, top, -0.9), f.p(0.0, top, 0.9)]
}

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

/// A car in its own frame (x forward, y up, z right, origin on the ground under its
/// centre), within ±[`CAR_HALF_LENGTH_M`] × ±[`CAR_HALF_WIDTH_M`]: a lower body in its
/// paint, a cabin with a sloped windscreen and rear window of dark glass and side windows
/// between lighter pillars, dark bumpers at both ends, head and tail lamps, and wheels
/// with light hubs. About a hundred triangles.
pub(super) fn car(mesh: &mut Mesh, slot: u32, albedo: f64, body: CarBody) {
    const HL: f64 = CAR_HALF_LENGTH_M;
    const HW: f64 = CAR_HALF_WIDTH_M;
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
    let axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let standing = |mesh: &mut Mesh, min: [f64; 3], max: [f64; 3], albedo: f64| {
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
            slot,
        );
    };
    // Lower body and bumpers.
    standing(mesh, [-end, 0.32, -side], [end, belt, side], albedo);
    for sx in [-1.0, 1.0] {
        let (a, b) = if sx > 0.0 { (end, HL) } else { (-HL, -end) };
        standing(
            mesh,
            [a, 0.26, -side + 0.05],
            [b, 0.55, side - 0.05],
            CAR_BUMPER_ALBEDO,
        );
    }
    // Lamps on the body's ends, above the bumpers: head lamps in front, tail lamps behind.
    for (sx, y0, y1) in [(1.0, 0.66, 0.80), (-1.0, 0.68, 0.86)] {
        for sz in [-1.0, 1.0] {
            let x = sx * (end + 0.005);
            let (z0, z1) = (sz * (side - 0.32), sz * (side - 0.06));
            mesh.quad_with_normal(
                [[x, y0, z0], [x, y0, z1], [x, y1, z1], [x, y1, z0]],
                [sx, 0.0, 0.0],
                LAMP_ALBEDO,
                slot,
            );
        }
    }
    // The cabin: a prism of trapezoid section, narrowing towards the roof.
    let pillar = albedo.max(0.35);
    let (cw0, cw1) = (side - 0.06, side - 0.16);
    // The cabin's side `sz` at height fraction v: its point at fraction t from rear to front.
    let at = |v: f64, sz: f64| {
        move |t: f64| -> [f64; 3] {
            let xr = rear0 + v * (rear1 - rear0);
            let xf = front0 + v * (front1 - front0);
            [
                xr + t * (xf - xr),
                belt + v * (roof - belt),
                sz * (cw0 + v * (cw1 - cw0)),
            ]
        }
    };
    let roof_quad = [
        [rear1, roof, -cw1],
        [front1, roof, -cw1],
        [front1, roof, cw1],
        [rear1, roof, cw1],
    ];
    mesh.quad_with_normal(roof_quad, [0.0, 1.0, 0.0], albedo, slot);
    // Windscreen and rear window: the sloped faces in the pillars' colour, the glass just
    // proud of them with a frame all round.
    for (x_low, x_high, sx) in [(front0, front1, 1.0), (rear0, rear1, -1.0)] {
        let face = [
            [x_low, belt, -cw0],
            [x_low, belt, cw0],
            [x_high, roof, cw1],
            [x_high, roof, -cw1],
        ];
        let normal = outward(face, [sx, 0.0, 0.0]);
        mesh.quad_with_normal(face, normal, pillar, slot);
        let lerp = |a: [f64; 3], b: [f64; 3], t: f64| {
            [
                a[0] + t * (b[0] - a[0]),
                a[1] + t * (b[1] - a[1]),
                a[2] + t * (b[2] - a[2]),
            ]
        };
        // Inset: 10 % of the height at top and bottom, 8 cm at the sides.
        let lo = [lerp(face[0], face[3], 0.1), lerp(face[1], face[2], 0.1)];
        let hi = [lerp(face[0], face[3], 0.9), lerp(face[1], face[2], 0.9)];
        let squeeze = |p: [f64; 3]| [p[0], p[1], p[2] - p[2].signum() * 0.08];
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
            slot,
        );
    }
    // The sides: pillars' colour, with two side windows (one for a van's cab) between the
    // pillars.
    for sz in [-1.0, 1.0] {
        let bottom = at(0.0, sz);
        let top = at(1.0, sz);
        let face = [bottom(0.0), bottom(1.0), top(1.0), top(0.0)];
        let normal = outward(face, [0.0, 0.0, sz]);
        mesh.quad_with_normal(face, normal, pillar, slot);
        let (v0, v1) = (0.12, 0.86);
        let lo = at(v0, sz);
        let hi = at(v1, sz);
        let spans: &[(f64, f64)] = match body {
            CarBody::Van => &[(0.62, 0.93)],
            _ => &[(0.06, 0.47), (0.53, 0.94)],
        };
        for &(t0, t1) in spans {
            let glass = [lo(t0), lo(t1), hi(t1), hi(t0)];
            mesh.quad_with_normal(
                glass.map(|p| proud(p, normal, 0.008)),
                normal,
                CAR_GLASS_ALBEDO,
                slot,
            );
        }
    }
    // Wheels: dark tyres standing on the ground, light hubs on their outer faces.
    for x in [-wheel_x, wheel_x] {
        for sz in [-1.0, 1.0] {
            let (z_in, z_out) = (sz * (HW - 0.22), sz * HW);
            standing(
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
                slot,
            );
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

/// Axes of a ground-standing object with the given heading: forward, up, right.
fn axes(heading: f64) -> [[f64; 3]; 3] {
    let (s, c) = heading.sin_cos();
    [[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]]
}

/// A ground-standing object's frame: its centre on the ground plane, its axes forward (u)
/// and right (w), and the height of its base.
struct Footing {
    at: [f64; 2],
    u: [f64; 3],
    w: [f64; 3],
}

impl Footing {
    fn new(at: [f64; 2], heading: f64) -> Footing {
        let [u, _, w] = axes(heading);
        Footing { at, u, w }
    }

    /// The world point `a` along u, `y` up, `b` along w.
    fn p(&self, a: f64, y: f64, b: f64) -> [f64; 3] {
        [
            self.at[0] + a * self.u[0] + b * self.w[0],
            y,
            self.at[1] + a * self.u[2] + b * self.w[2],
        ]
    }

    /// The world direction `a` along u plus `b` along w.
    fn dir(&self, a: f64, b: f64) -> [f64; 3] {
        [
            a * self.u[0] + b * self.w[0],
            0.0,
            a * self.u[2] + b * self.w[2],
        ]
    }

    /// The box axes: u, up, w.
    fn axes(&self) -> [[f64; 3]; 3] {
        [self.u, [0.0, 1.0, 0.0], self.w]
    }
}

/// One outer wall of a box-shaped object: `across` is 0 for a wall facing ±w (running
/// along u), 1 for one facing ±u; `side` the sign of its outward normal; `offset` its
/// distance from the centre.
#[derive(Clone, Copy)]
struct Wall {
    across: usize,
    side: f64,
    offset: f64,
}

impl Wall {
    /// The point at `along` metres along the wall, height `y`, `proud` metres out of it.
    fn p(self, f: &Footing, along: f64, y: f64, proud: f64) -> [f64; 3] {
        let out = self.side * (self.offset + proud);
        if self.across == 0 {
            f.p(along, y, out)
        } else {
            f.p(out, y, along)
        }
    }

    fn normal(self, f: &Footing) -> [f64; 3] {
        if self.across == 0 {
            f.dir(0.0, self.side)
        } else {
            f.dir(self.side, 0.0)
        }
    }

    /// A flat rectangle on the wall, `along` and `y` ranges, `proud` metres out of it.
    fn rect(
        self,
        mesh: &mut Mesh,
        f: &Footing,
        along: [f64; 2],
        y: [f64; 2],
        proud: f64,
        albedo: f64,
    ) {
        mesh.quad_with_normal(
            [
                self.p(f, along[0], y[0], proud),
                self.p(f, along[1], y[0], proud),
                self.p(f, along[1], y[1], proud),
                self.p(f, along[0], y[1], proud),
            ],
            self.normal(f),
            albedo,
            ObjectSlot::WORLD,
        );
    }

    /// A window or door `width` × `height` from `y0`, centred `along` the wall: a frame
    /// `frame` metres wide around a dark pane (each with its own edges), and for a window
    /// a sill under it that stands out of the wall.
    #[allow(clippy::too_many_arguments)]
    fn opening(
        self,
        mesh: &mut Mesh,
        f: &Footing,
        along: f64,
        y0: f64,
        size: [f64; 2],
        frame: f64,
        frame_albedo: f64,
        pane_albedo: f64,
        sill: bool,
    ) {
        let [hw, h] = [0.5 * size[0], size[1]];
        let bottom_frame = if sill { frame } else { 0.0 };
        self.rect(
            mesh,
            f,
            [along - hw - frame, along + hw + frame],
            [y0 - bottom_frame, y0 + h + frame],
            OPENING_FRAME_PROUD_M,
            frame_albedo,
        );
        self.rect(
            mesh,
            f,
            [along - hw, along + hw],
            [y0, y0 + h],
            OPENING_PANE_PROUD_M,
            pane_albedo,
        );
        if sill {
            // The sill: its top and front, 12 cm out of the wall, under the frame.
            let (a0, a1) = (along - hw - frame - 0.05, along + hw + frame + 0.05);
            let (y_lo, y_hi) = (y0 - frame - 0.06, y0 - frame);
            mesh.quad_with_normal(
                [
                    self.p(f, a0, y_hi, 0.0),
                    self.p(f, a1, y_hi, 0.0),
                    self.p(f, a1, y_hi, SILL_M),
                    self.p(f, a0, y_hi, SILL_M),
                ],
                [0.0, 1.0, 0.0],
                frame_albedo,
                ObjectSlot::WORLD,
            );
            self.rect(mesh, f, [a0, a1], [y_lo, y_hi], SILL_M, frame_albedo);
        }
    }
}

/// How far a window's or door's frame stands out of its wall, metres.
const OPENING_FRAME_PROUD_M: f64 = 0.03;
/// How far its pane or leaf stands out of the wall, metres (in front of the frame).
const OPENING_PANE_PROUD_M: f64 = 0.045;
/// How far a window sill stands out of its wall, metres.
const SILL_M: f64 = 0.12;
/// Albedo of window panes and door leaves.
pub(super) const PANE_ALBEDO: f64 = 0.08;
/// Size of a house's door, metres (width, height).
pub(super) const DOOR_M: [f64; 2] = [1.0, 2.1];

/// Frames lighter than a dark wall, darker than a light one, so they always show.
fn frame_albedo(wall_albedo: f64) -> f64 {
    if wall_albedo < 0.62 {
        0.88
    } else {
        0.32
    }
}

/// A house's shape: its size, its walls' height, its colours, which wall faces the road
/// (the door's), and the seeded details.
pub(super) struct HouseSpec {
    /// Half its length (along its heading) and width, metres.
    pub half: [f64; 2],
    /// Height of its walls under the eaves, metres.
    pub walls: f64,
    /// Albedo of its walls.
    pub wall_albedo: f64,
    /// Albedo of its roof.
    pub roof_albedo: f64,
    /// The side (±1 along its right) of the long wall that faces the road.
    pub road_side: f64,
    /// Where the door is along that wall, as a share of it in [0, 1).
    pub door_at: f64,
    /// Where a chimney stands along the ridge, as a share in [0, 1), if it has one.
    pub chimney_at: Option<f64>,
}

/// A gabled house: walls, a roof with eaves, framed windows with sills on its long walls
/// and one in each gable end, a framed door with a step on the wall facing the road, and
/// maybe a chimney.
pub(super) fn house(mesh: &mut Mesh, at: [f64; 2], heading: f64, spec: &HouseSpec) {
    let f = Footing::new(at, heading);
    let [h0, h1] = spec.half;
    let walls = spec.walls;
    let slot = ObjectSlot::WORLD;
    mesh.standing_box(
        f.p(0.0, 0.5 * walls, 0.0),
        f.axes(),
        [h0, 0.5 * walls, h1],
        spec.wall_albedo,
        slot,
    );
    let ridge = walls + 2.5;
    let eave = h1 + 0.3;
    for side in [-1.0, 1.0] {
        mesh.polygon(
            &[
                f.p(-h0 - 0.3, walls, side * eave),
                f.p(h0 + 0.3, walls, side * eave),
                f.p(h0 + 0.3, ridge, 0.0),
                f.p(-h0 - 0.3, ridge, 0.0),
            ],
            spec.roof_albedo,
            slot,
        );
        // The gable, wound so that its normal points out of the house.
        let (b0, b1) = (side * h1, -side * h1);
        mesh.polygon(
            &[
                f.p(side * h0, walls, b0),
                f.p(side * h0, walls, b1),
                f.p(side * h0, ridge, 0.0),
            ],
            spec.wall_albedo,
            slot,
        );
    }
    if let Some(c) = spec.chimney_at {
        // On the slope away from the road, from below the roof to above the ridge.
        let a = -h0 + 1.0 + c * (2.0 * h0 - 2.0);
        let b = -spec.road_side * 0.45 * h1;
        let low = walls + 2.5 * (1.0 - (b.abs() + 0.35) / eave) - 0.1;
        mesh.standing_box(
            f.p(a, 0.5 * (low + ridge + 0.8), b),
            f.axes(),
            [0.35, 0.5 * (ridge + 0.8 - low), 0.35],
            0.5 * spec.wall_albedo + 0.1,
            slot,
        );
    }
    let frame = frame_albedo(spec.wall_albedo);
    let floors = if walls > 4.0 { 2 } else { 1 };
    let windows = ((2.0 * h0) / 3.0).floor() as usize;
    let door = ((spec.door_at * windows as f64) as usize).min(windows - 1);
    for side in [-1.0, 1.0] {
        let wall = Wall {
            across: 0,
            side,
            offset: h1,
        };
        for floor in 0..floors {
            let y0 = 1.0 + 2.8 * floor as f64;
            for k in 0..windows {
                let a = -h0 + (k as f64 + 0.5) * 2.0 * h0 / windows as f64;
                if floor == 0 && side == spec.road_side && k == door {
                    // The door, in a frame, with a step before it.
                    wall.opening(mesh, &f, a, 0.15, DOOR_M, 0.1, frame, PANE_ALBEDO, false);
                    mesh.standing_box(
                        wall.p(&f, a, 0.075, 0.25),
                        f.axes(),
                        [0.8, 0.075, 0.25],
                        0.55,
                        slot,
                    );
                    continue;
                }
                wall.opening(mesh, &f, a, y0, [1.0, 1.2], 0.08, frame, PANE_ALBEDO, true);
            }
        }
    }
    for side in [-1.0, 1.0] {
        let wall = Wall {
            across: 1,
            side,
            offset: h0,
        };
        wall.opening(
            mesh,
            &f,
            0.0,
            1.0,
            [1.0, 1.2],
            0.08,
            frame,
            PANE_ALBEDO,
            true,
        );
    }
}

/// A flat-roofed building's shape.
pub(super) struct BuildingSpec {
    /// Half its length (along its heading) and width, metres.
    pub half: [f64; 2],
    /// Height of its roof, metres.
    pub height: f64,
    /// Albedo of its walls.
    pub albedo: f64,
    /// The side (±1 along its right) of the long wall that faces the road.
    pub road_side: f64,
    /// Where its entrance is along that wall, as a share of it in [0, 1).
    pub entrance_at: f64,
}

/// A flat-roofed building: walls, a cornice round the top standing above the roof as a
/// parapet, a grid of framed windows on all four walls, and a glazed, framed entrance
/// under a canopy on the wall facing the road.
pub(super) fn building(mesh: &mut Mesh, at: [f64; 2], heading: f64, spec: &BuildingSpec) {
    let f = Footing::new(at, heading);
    let [h0, h1] = spec.half;
    let height = spec.height;
    let slot = ObjectSlot::WORLD;
    mesh.standing_box(
        f.p(0.0, 0.5 * height, 0.0),
        f.axes(),
        [h0, 0.5 * height, h1],
        spec.albedo,
        slot,
    );
    let trim = (spec.albedo + 0.2).min(0.92);
    // The cornice: a band 15 cm proud of the walls, from 40 cm under the roof to 60 cm
    // above it (the parapet; the roof behind it is never seen from the road).
    mesh.oriented_box(
        f.p(0.0, height + 0.1, 0.0),
        f.axes(),
        [h0 + 0.15, 0.5, h1 + 0.15],
        trim,
        slot,
    );
    let frame = frame_albedo(spec.albedo);
    // The entrance: glazed doors in a frame, under a canopy.
    let entrance = -h0 + 2.5 + spec.entrance_at * (2.0 * h0 - 5.0);
    let front = Wall {
        across: 0,
        side: spec.road_side,
        offset: h1,
    };
    front.opening(
        mesh,
        &f,
        entrance,
        0.0,
        [2.4, 2.5],
        0.15,
        frame,
        PANE_ALBEDO,
        false,
    );
    mesh.oriented_box(
        front.p(&f, entrance, 2.85, 0.6),
        f.axes(),
        [1.6, 0.08, 0.6],
        trim,
        slot,
    );
    let floors = (height / 3.0).floor() as usize;
    for (across, extent, offset) in [(0usize, h0, h1), (1, h1, h0)] {
        let columns = (2.0 * extent / 2.5).floor() as usize;
        for side in [-1.0, 1.0] {
            let wall = Wall {
                across,
                side,
                offset,
            };
            for floor in 0..floors {
                let y0 = 0.9 + 3.0 * floor as f64;
                if y0 + 1.4 > height - 0.5 {
                    break;
                }
                for k in 0..columns {
                    let a = -extent + (k as f64 + 0.5) * 2.0 * extent / columns as f64;
                    if floor == 0
                        && across == 0
                        && side == spec.road_side
                        && (a - entrance).abs() < 2.1
                    {
                        continue;
                    }
                    wall.opening(mesh, &f, a, y0, [1.2, 1.4], 0.08, frame, PANE_ALBEDO, false);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangles(mesh: &Mesh) -> usize {
        mesh.indices.len() / 3
    }

    /// The quads (as `Mesh::quad_with_normal` indexes them) of `mesh` in one albedo.
    fn quads_of(mesh: &Mesh, albedo: f64) -> Vec<[[f64; 3]; 4]> {
        let mut quads = Vec::new();
        for six in mesh.indices.chunks_exact(6) {
            let b = six[0];
            if six != [b, b + 1, b + 2, b, b + 2, b + 3] {
                continue;
            }
            let q = [0, 1, 2, 3].map(|k| mesh.vertices[(b + k) as usize]);
            if q.iter()
                .all(|v| (f64::from(v.albedo) - albedo).abs() < 1e-6)
            {
                quads.push(q.map(|v| v.position.map(f64::from)));
            }
        }
        quads
    }

    fn spec(road_side: f64) -> HouseSpec {
        HouseSpec {
            half: [5.5, 4.0],
            walls: 3.0,
            wall_albedo: 0.5,
            roof_albedo: 0.2,
            road_side,
            door_at: 0.4,
            chimney_at: Some(0.3),
        }
    }

    #[test]
    fn a_house_has_a_framed_door_with_a_step_on_the_wall_facing_the_road() {
        for road_side in [-1.0, 1.0] {
            let mut mesh = Mesh::default();
            // Heading 0: the house's right (w) is world +z.
            house(&mut mesh, [10.0, 20.0], 0.0, &spec(road_side));
            let wall_z = 20.0 + road_side * 4.0;
            // Dark leaves reaching down to the step: doors; on the road's side only.
            let doors: Vec<_> = quads_of(&mesh, PANE_ALBEDO)
                .into_iter()
                .filter(|q| q.iter().map(|p| p[1]).fold(f64::MAX, f64::min) < 0.2)
                .collect();
            assert_eq!(doors.len(), 1, "one door");
            let door = doors[0];
            for p in door {
                assert!(
                    (p[2] - (wall_z + road_side * OPENING_PANE_PROUD_M)).abs() < 1e-4,
                    "on the wall facing the road: {p:?}"
                );
            }
            let height = door.iter().map(|p| p[1]).fold(f64::MIN, f64::max)
                - door.iter().map(|p| p[1]).fold(f64::MAX, f64::min);
            assert!((height - DOOR_M[1]).abs() < 1e-4, "door height {height}");
            // Its frame: a lighter quad just behind it, larger all round but at the foot.
            let frame = frame_albedo(0.5);
            assert!(quads_of(&mesh, frame).iter().any(|q| {
                q.iter()
                    .all(|p| (p[2] - (wall_z + road_side * OPENING_FRAME_PROUD_M)).abs() < 1e-4)
                    && q.iter().map(|p| p[1]).fold(f64::MIN, f64::max) > 0.15 + DOOR_M[1]
            }));
            // The step: something standing on the ground in front of the door.
            assert!(mesh.vertices.iter().any(|v| {
                v.position[1] == 0.0
                    && (f64::from(v.position[2]) - (wall_z + road_side * 0.5)).abs() < 1e-3
            }));
        }
    }

    #[test]
    fn every_window_has_a_frame_and_a_pane() {
        let mut mesh = Mesh::default();
        house(&mut mesh, [0.0, 0.0], 0.3, &spec(-1.0));
        let panes = quads_of(&mesh, PANE_ALBEDO).len();
        // Three windows on each long wall (one of them the door), one in each gable end.
        assert_eq!(panes, 3 + 3 + 2);
        // Each pane's frame and (but for the door) its sill's front.
        let frames = quads_of(&mesh, frame_albedo(0.5)).len();
        assert_eq!(
            frames,
            panes + 2 * (panes - 1),
            "frames, and sills but under the door"
        );
    }

    #[test]
    fn a_building_has_an_entrance_a_cornice_and_framed_windows() {
        let mut mesh = Mesh::default();
        let spec = BuildingSpec {
            half: [9.0, 7.0],
            height: 14.0,
            albedo: 0.5,
            road_side: 1.0,
            entrance_at: 0.5,
        };
        building(&mut mesh, [0.0, 0.0], 0.0, &spec);
        // The entrance: a dark pane 2.5 m tall from the ground on the +z wall.
        let panes = quads_of(&mesh, PANE_ALBEDO);
        assert!(panes.iter().any(|q| {
            q.iter()
                .all(|p| (p[2] - (7.0 + OPENING_PANE_PROUD_M)).abs() < 1e-4)
                && q.iter().map(|p| p[1]).fold(f64::MAX, f64::min) == 0.0
                && q.iter().map(|p| p[1]).fold(f64::MIN, f64::max) == 2.5
        }));
        // The cornice and parapet stand proud of the walls and above the roof.
        let top = mesh
            .vertices
            .iter()
            .map(|v| f64::from(v.position[1]))
            .fold(f64::MIN, f64::max);
        assert!((top - 14.6).abs() < 1e-4, "parapet top {top}");
        let widest = mesh
            .vertices
            .iter()
            .map(|v| f64::from(v.position[0]).abs())
            .fold(0.0, f64::max);
        assert!((widest - 9.15).abs() < 1e-4, "cornice {widest}");
        assert!(panes.len() > 50, "{} windows", panes.len());
    }

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

    #[test]
    fn poles_carry_insulators_and_their_fittings() {
        let count = |fittings| {
            let mut mesh = Mesh::default();
            let ends = pole(&mut mesh, [0.0, 0.0], 0.0, fittings);
            for end in ends {
                // The wires hang from the insulators' tops.
                assert!(mesh.vertices.iter().any(|v| f64::from(v.albedo)
                    == f64::from(INSULATOR_ALBEDO as f32)
                    && (f64::from(v.position[1]) - end[1]).abs() < 1e-4
                    && (f64::from(v.position[2]) - end[2]).abs() < 0.05));
            }
            let insulators = mesh
                .vertices
                .iter()
                .filter(|v| f64::from(v.albedo) == f64::from(INSULATOR_ALBEDO as f32))
                .count()
                / 20;
            (insulators, triangles(&mesh))
        };
        let (plain, plain_triangles) = count(PoleFittings::Plain);
        eprintln!("plain pole: {plain_triangles} triangles");
        assert_eq!(plain, 3);
        assert_eq!(count(PoleFittings::LowerArm).0, 5);
        let (with_can, can_triangles) = count(PoleFittings::Transformer);
        assert_eq!(with_can, 3);
        assert_eq!(can_triangles, plain_triangles + 8 + 12, "bracket and can");
    }

    fn bumpy() -> Terrain {
        Terrain::new(&super::super::terrain::tests::bumpy_ground())
            .unwrap()
            .unwrap()
    }

    #[test]
    fn standing_puts_an_item_on_the_lowest_ground_under_it() {
        let t = bumpy();
        for (k, heading) in [0.0, 0.4, 1.3].into_iter().enumerate() {
            let at = [-20.0 + 17.0 * k as f64, 11.0 - 9.0 * k as f64];
            let mut flat = Mesh::default();
            house(&mut flat, at, heading, &spec(1.0));
            let mut item = flat.clone();
            let base = stand(Some(&t), &mut item);
            // Its base, at the lowest ground under its plan within a centimetre: sampled
            // every 5 cm over the footprint's bounding box.
            let footprint: Vec<[f64; 2]> = flat
                .vertices
                .iter()
                .filter(|v| v.position[1] == 0.0)
                .map(|v| [f64::from(v.position[0]), f64::from(v.position[2])])
                .collect();
            let lo = |k: usize| footprint.iter().map(|p| p[k]).fold(f64::MAX, f64::min);
            let hi = |k: usize| footprint.iter().map(|p| p[k]).fold(f64::MIN, f64::max);
            let mut lowest = f64::MAX;
            let mut x = lo(0);
            while x <= hi(0) {
                let mut z = lo(1);
                while z <= hi(1) {
                    lowest = lowest.min(t.height_m(x, z));
                    z += 0.05;
                }
                x += 0.05;
            }
            assert!((base - lowest).abs() < 0.01, "base {base}, lowest {lowest}");
            assert!(base.abs() > 0.005, "it moved: {base}");
            // Nowhere does its foot float above the ground; all of it moved by `base`.
            for (v, w) in flat.vertices.iter().zip(&item.vertices) {
                let [x, y, z] = w.position.map(f64::from);
                assert!((y - f64::from(v.position[1]) - base).abs() < 1e-4);
                if v.position[1] == 0.0 {
                    assert!(y <= t.height_m(x, z) + 0.01, "floats at ({x}, {z})");
                }
            }
            // No terrain: untouched.
            let mut same = flat.clone();
            assert_eq!(stand(None, &mut same), 0.0);
            assert_eq!(same, flat);
        }
    }

    #[test]
    fn clutter_keeps_to_a_modest_triangle_budget() {
        let mut mesh = Mesh::default();
        house(&mut mesh, [0.0, 0.0], 0.0, &spec(1.0));
        eprintln!("house: {} triangles", triangles(&mesh));
        assert!(triangles(&mesh) < 200, "house: {}", triangles(&mesh));
        let mut mesh = Mesh::default();
        building(
            &mut mesh,
            [0.0, 0.0],
            0.0,
            &BuildingSpec {
                half: [9.0, 7.0],
                height: 14.0,
                albedo: 0.5,
                road_side: 1.0,
                entrance_at: 0.5,
            },
        );
        eprintln!("building: {} triangles", triangles(&mesh));
        assert!(triangles(&mesh) < 500, "building: {}", triangles(&mesh));
    }
}

//! Triangle meshes in the layout the renderer uploads, and the few primitives the scene is
//! made of (boxes, flat quads on the ground, octahedra for canopy clumps, beams for wires).

use bytemuck::{Pod, Zeroable};
use std::ops::Range;

/// One vertex: position and normal in the owning object's frame, a grey albedo, and the
/// object slot whose transform places it in the world (see [`crate::scene::ObjectSlot`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    /// Position, metres, in the object's frame.
    pub position: [f32; 3],
    /// Unit normal, object frame.
    pub normal: [f32; 3],
    /// Diffuse reflectance, 0 (black) to 1 (white).
    pub albedo: f32,
    /// Index of the object transform (0 = world) in the low bits
    /// ([`crate::scene::ObjectSlot::MASK`]), or-ed with the ground material of a road or
    /// grass surface ([`crate::scene::Material`]) in the bits above.
    pub object: u32,
}

/// An indexed triangle list.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertices.
    pub vertices: Vec<Vertex>,
    /// Triangle indices into `vertices`.
    pub indices: Vec<u32>,
}

/// Part of a mesh: vertices, and indices naming them less `base` (index `i`
/// names `vertices[(i - base) as usize]`).
#[derive(Clone, Copy, Debug)]
pub struct MeshPiece<'a> {
    /// The vertices.
    pub vertices: &'a [Vertex],
    /// The triangles' indices, in order.
    pub indices: &'a [u32],
    /// What an index names the first of `vertices` by.
    pub base: u32,
}

type P = [f64; 3];

fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: P, b: P) -> P {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalize(a: P) -> P {
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    if n == 0.0 {
        return [0.0, 1.0, 0.0];
    }
    [a[0] / n, a[1] / n, a[2] / n]
}

fn f32x3(a: P) -> [f32; 3] {
    [a[0] as f32, a[1] as f32, a[2] as f32]
}

impl Mesh {
    /// Appends a flat polygon (convex, corners in order) with one normal, fanned into
    /// triangles. The normal is the polygon's, oriented to have a non-negative y where the
    /// polygon is horizontal-ish, else as the winding gives.
    pub fn polygon(&mut self, corners: &[P], albedo: f64, object: u32) {
        if corners.len() < 3 {
            return;
        }
        let mut n = normalize(cross(
            sub(corners[1], corners[0]),
            sub(corners[2], corners[0]),
        ));
        if n[1] < -0.5 {
            n = [-n[0], -n[1], -n[2]];
        }
        let base = self.vertices.len() as u32;
        for &c in corners {
            self.vertices.push(Vertex {
                position: f32x3(c),
                normal: f32x3(n),
                albedo: albedo as f32,
                object,
            });
        }
        for i in 1..corners.len() as u32 - 1 {
            self.indices
                .extend_from_slice(&[base, base + i, base + i + 1]);
        }
    }

    /// Appends a quad with an explicit normal (used for walls, whose winding varies).
    pub fn quad_with_normal(&mut self, corners: [P; 4], normal: P, albedo: f64, object: u32) {
        let base = self.vertices.len() as u32;
        for c in corners {
            self.vertices.push(Vertex {
                position: f32x3(c),
                normal: f32x3(normalize(normal)),
                albedo: albedo as f32,
                object,
            });
        }
        self.indices
            .extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    }

    /// Appends an oriented box: centre, half extents along its own axes `u`, `v` (up), `w`,
    /// where `u` and `w` are unit vectors in the ground plane.
    pub fn oriented_box(
        &mut self,
        centre: P,
        axes: [P; 3],
        half: [f64; 3],
        albedo: f64,
        object: u32,
    ) {
        self.box_faces(centre, axes, half, albedo, object, [false; 3]);
    }

    /// Appends an oriented box without its bottom (−`v`) face: it stands on the ground or
    /// on another part, so its bottom can never be seen nor cast a shadow (ten triangles).
    pub fn standing_box(
        &mut self,
        centre: P,
        axes: [P; 3],
        half: [f64; 3],
        albedo: f64,
        object: u32,
    ) {
        self.box_faces(centre, axes, half, albedo, object, [false, true, false]);
    }

    /// The faces of an oriented box, leaving out those `skip` names: `[ends, bottom, _]`
    /// drops both ±`u` faces (a beam's ends) and the −`v` face (what stands on the ground).
    fn box_faces(
        &mut self,
        centre: P,
        axes: [P; 3],
        half: [f64; 3],
        albedo: f64,
        object: u32,
        skip: [bool; 3],
    ) {
        let corner = |su: f64, sv: f64, sw: f64| -> P {
            let mut p = centre;
            for k in 0..3 {
                p[k] += su * half[0] * axes[0][k]
                    + sv * half[1] * axes[1][k]
                    + sw * half[2] * axes[2][k];
            }
            p
        };
        for axis in 0..3 {
            for sign in [-1.0, 1.0] {
                if (axis == 0 && skip[0]) || (axis == 1 && sign < 0.0 && skip[1]) {
                    continue;
                }
                let n = [
                    sign * axes[axis][0],
                    sign * axes[axis][1],
                    sign * axes[axis][2],
                ];
                let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
                let mut s = [0.0; 3];
                s[axis] = sign;
                let mut quad = [[0.0; 3]; 4];
                for (i, (sa, sb)) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                    .into_iter()
                    .enumerate()
                {
                    s[a] = sa;
                    s[b] = sb;
                    quad[i] = corner(s[0], s[1], s[2]);
                }
                self.quad_with_normal(quad, n, albedo, object);
            }
        }
    }

    /// Appends an axis-aligned box, `min` to `max`, in the object's frame.
    pub fn aabb(&mut self, min: P, max: P, albedo: f64, object: u32) {
        let centre = [
            0.5 * (min[0] + max[0]),
            0.5 * (min[1] + max[1]),
            0.5 * (min[2] + max[2]),
        ];
        let half = [
            0.5 * (max[0] - min[0]),
            0.5 * (max[1] - min[1]),
            0.5 * (max[2] - min[2]),
        ];
        self.oriented_box(
            centre,
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            half,
            albedo,
            object,
        );
    }

    /// Appends a box standing on the ground at `(x, z)`, from height `bottom` (the ground's
    /// there) to `top`, rotated by `heading` about +y, without a bottom face.
    #[allow(clippy::too_many_arguments)]
    pub fn upright_box(
        &mut self,
        x: f64,
        z: f64,
        heading: f64,
        half_length: f64,
        half_width: f64,
        bottom: f64,
        top: f64,
        albedo: f64,
    ) {
        let (s, c) = heading.sin_cos();
        // Standing on the ground, its bottom face can never be seen nor cast a shadow.
        self.box_faces(
            [x, 0.5 * (bottom + top), z],
            [[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]],
            [half_length, 0.5 * (top - bottom), half_width],
            albedo,
            0,
            [false, true, false],
        );
    }

    /// Appends an octahedron (a canopy clump): centre and radii along x, y, z.
    pub fn octahedron(&mut self, centre: P, radii: P, albedo: f64) {
        let tip = |k: usize, s: f64| {
            let mut p = centre;
            p[k] += s * radii[k];
            p
        };
        for sy in [-1.0, 1.0] {
            for (sx, sz) in [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)] {
                let a = tip(0, sx);
                let b = tip(1, sy);
                let c = tip(2, sz);
                let n = normalize([sx / radii[0], sy / radii[1], sz / radii[2]]);
                let base = self.vertices.len() as u32;
                for p in [a, b, c] {
                    self.vertices.push(Vertex {
                        position: f32x3(p),
                        normal: f32x3(n),
                        albedo: albedo as f32,
                        object: 0,
                    });
                }
                self.indices.extend_from_slice(&[base, base + 1, base + 2]);
            }
        }
    }

    /// Appends a thin square beam from `a` to `b` (wires, cross-arms), `half` metres thick,
    /// without end faces (eight triangles).
    pub fn beam(&mut self, a: P, b: P, half: f64, albedo: f64) {
        let d = sub(b, a);
        let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let u = normalize(d);
        let side = if u[1].abs() > 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            normalize(cross(u, [0.0, 1.0, 0.0]))
        };
        let up = cross(side, u);
        let centre = [
            0.5 * (a[0] + b[0]),
            0.5 * (a[1] + b[1]),
            0.5 * (a[2] + b[2]),
        ];
        // Open-ended: a beam's ends are a few square centimetres nobody sees.
        self.box_faces(
            centre,
            [u, up, side],
            [0.5 * length, half, half],
            albedo,
            0,
            [true, false, false],
        );
    }

    /// Appends a vertical ribbon from `a` to `b`, `half` metres either side vertically: a
    /// wire seen from the road, two-sided (four triangles, one face lit from each side), so
    /// it survives back-face culling from wherever it is seen.
    pub fn ribbon(&mut self, a: P, b: P, half: f64, albedo: f64) {
        let d = sub(b, a);
        let normal = normalize(cross(d, [0.0, 1.0, 0.0]));
        let corners = [
            [a[0], a[1] - half, a[2]],
            [b[0], b[1] - half, b[2]],
            [b[0], b[1] + half, b[2]],
            [a[0], a[1] + half, a[2]],
        ];
        self.quad_with_normal(corners, normal, albedo, 0);
        let back = [-normal[0], -normal[1], -normal[2]];
        self.quad_with_normal(corners, back, albedo, 0);
    }

    /// Winds every triangle counter-clockwise about its vertices' normal (right-handed, seen
    /// from the side the normal points to), so the renderer can cull back faces. Every
    /// primitive here is flat-shaded, so a triangle's first vertex normal is its face's.
    pub fn orient_faces(&mut self) {
        for triangle in self.indices.chunks_exact_mut(3) {
            let [a, b, c] =
                [triangle[0], triangle[1], triangle[2]].map(|i| self.vertices[i as usize]);
            let p = |v: Vertex| v.position.map(f64::from);
            let geometric = cross(sub(p(b), p(a)), sub(p(c), p(a)));
            let n = a.normal.map(f64::from);
            if geometric[0] * n[0] + geometric[1] * n[1] + geometric[2] * n[2] < 0.0 {
                triangle.swap(1, 2);
            }
        }
    }

    /// Appends another mesh, re-basing its indices.
    pub fn append(&mut self, other: &Mesh) {
        self.append_piece(MeshPiece {
            vertices: &other.vertices,
            indices: &other.indices,
            base: 0,
        });
    }

    /// Appends part of a mesh, re-basing its indices onto this mesh's vertices.
    pub fn append_piece(&mut self, piece: MeshPiece<'_>) {
        let first = self.vertices.len() as u32;
        self.vertices.extend_from_slice(piece.vertices);
        (self.indices).extend(piece.indices.iter().map(|&i| i - piece.base + first));
    }

    /// Centre and radius of a sphere holding every vertex (object frame).
    pub fn bounding_sphere(&self) -> ([f64; 3], f64) {
        sphere_around(self.vertices.iter())
    }

    /// Centre and radius of a sphere holding every vertex that the indices `indices` (a
    /// range of [`Mesh::indices`]) use.
    pub fn bounding_sphere_of(&self, indices: Range<usize>) -> ([f64; 3], f64) {
        sphere_around(
            self.indices[indices]
                .iter()
                .map(|&i| &self.vertices[i as usize]),
        )
    }
}

/// The sphere around `vertices` whose centre is the middle of their bounding box.
fn sphere_around<'a>(vertices: impl Iterator<Item = &'a Vertex> + Clone) -> ([f64; 3], f64) {
    let position = |v: &Vertex| v.position.map(f64::from);
    let mut min = [f64::MAX; 3];
    let mut max = [f64::MIN; 3];
    for p in vertices.clone().map(position) {
        for k in 0..3 {
            min[k] = min[k].min(p[k]);
            max[k] = max[k].max(p[k]);
        }
    }
    if min[0] > max[0] {
        return ([0.0; 3], 0.0);
    }
    let centre = [0, 1, 2].map(|k| 0.5 * (min[k] + max[k]));
    let radius = vertices
        .map(|v| {
            let d = sub(position(v), centre);
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
        })
        .fold(0.0, f64::max);
    (centre, radius)
}

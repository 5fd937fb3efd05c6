//! Helpers the scene's unit tests share: counting and finding the shapes in a mesh.

use super::mesh::Mesh;

/// How many triangles `mesh` has.
pub(super) fn triangles(mesh: &Mesh) -> usize {
    mesh.indices.len() / 3
}

/// The quads (as `Mesh::quad_with_normal` indexes them) of `mesh` in one albedo.
pub(super) fn quads_of(mesh: &Mesh, albedo: f64) -> Vec<[[f64; 3]; 4]> {
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

//! A closed mesh's signed distance (issue #29: every scene object is a
//! solid of the liquid, meshes by a signed distance field built once): the
//! distance to the nearest triangle, negative inside, the inside told by
//! the generalised winding number (Jacobson, Kavan & Sorkine-Hornung 2013:
//! the triangles' solid angles, van Oosterom & Strackee 1983, summed over
//! 4π — 1 inside a closed mesh, 0 outside, either winding). Sampled once on
//! the liquid's cell centres where the mesh reaches.

use super::Mesh;
use glam::{DVec3, Mat4};
use std::collections::HashMap;

/// A mesh's triangles in world space.
pub struct Triangles(pub Vec<[DVec3; 3]>);

impl Triangles {
    /// `mesh`'s triangles placed by `transform`.
    pub fn of(mesh: &Mesh, transform: &Mat4) -> Self {
        let world: Vec<DVec3> =
            mesh.positions.iter().map(|p| transform.transform_point3(*p).as_dvec3()).collect();
        Triangles(
            mesh.indices
                .chunks_exact(3)
                .map(|t| [world[t[0] as usize], world[t[1] as usize], world[t[2] as usize]])
                .collect(),
        )
    }

    /// The box around them.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for p in self.0.iter().flatten() {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        (lo, hi)
    }

    /// Σ of the triangles' solid angles at `p` over 4π.
    pub fn winding_number(&self, p: DVec3) -> f64 {
        let mut sum = 0.0;
        for [a, b, c] in &self.0 {
            let (a, b, c) = (*a - p, *b - p, *c - p);
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let det = a.dot(b.cross(c));
            let div = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
            sum += 2.0 * det.atan2(div);
        }
        sum / (4.0 * std::f64::consts::PI)
    }

    /// Signed distance (m) to the surface from `p`: negative inside.
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        let d = self.0.iter().map(|t| point_triangle_distance(p, t)).fold(f64::INFINITY, f64::min);
        if self.winding_number(p).abs() > 0.5 { -d } else { d }
    }
}

/// Distance from `p` to triangle `t` (Ericson, *Real-Time Collision
/// Detection*, §5.1.5: the nearest point by Voronoi regions).
pub fn point_triangle_distance(p: DVec3, t: &[DVec3; 3]) -> f64 {
    let [a, b, c] = *t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.length();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.length();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (p - (a + ab * (d1 / (d1 - d3)))).length();
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.length();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (p - (a + ac * (d2 / (d2 - d6)))).length();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (p - (b + (c - b) * w)).length();
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    (p - (a + ab * v + ac * w)).length()
}

/// Edges of `mesh` (its vertices welded where they coincide, as files
/// split them along seams of normals and texture coordinates) that are not
/// shared by exactly two triangles: 0 for a closed mesh.
pub fn open_edges(mesh: &Mesh) -> usize {
    let size = mesh
        .positions
        .iter()
        .fold(0.0f32, |m, p| m.max(p.abs().max_element()))
        .max(f32::MIN_POSITIVE);
    let step = size as f64 * 1e-6;
    let mut welded: HashMap<[i64; 3], u32> = HashMap::new();
    let ids: Vec<u32> = mesh
        .positions
        .iter()
        .map(|p| {
            let key = p.to_array().map(|c| (c as f64 / step).round() as i64);
            let next = welded.len() as u32;
            *welded.entry(key).or_insert(next)
        })
        .collect();
    let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
    for t in mesh.indices.chunks_exact(3) {
        for k in 0..3 {
            let (a, b) = (ids[t[k] as usize], ids[t[(k + 1) % 3] as usize]);
            if a != b {
                *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
    }
    edges.values().filter(|n| **n != 2).count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives;
    use crate::rng::SplitMix64;

    #[test]
    fn a_cube_mesh_has_the_box_signed_distance() {
        let t = Triangles::of(&primitives::cube(), &Mat4::IDENTITY);
        let mut rng = SplitMix64::new(3);
        for _ in 0..500 {
            let p = DVec3::new(rng.unit(), rng.unit(), rng.unit()) * 2.0 - 1.0;
            let q = p.abs() - 0.5;
            let exact = q.max(DVec3::ZERO).length() + q.max_element().min(0.0);
            let d = t.signed_distance(p);
            assert!((d - exact).abs() < 1e-9, "at {p}: {d} against {exact}");
        }
    }

    #[test]
    fn a_sphere_mesh_is_as_far_as_its_tessellation_allows() {
        // 64 × 32 facets: the chords sag r(1 − cos(π/32)) ≈ 0.0024 r.
        let t = Triangles::of(&primitives::sphere(64, 32), &Mat4::IDENTITY);
        let mut rng = SplitMix64::new(5);
        for _ in 0..200 {
            let p = DVec3::new(rng.unit(), rng.unit(), rng.unit()) * 1.6 - 0.8;
            let exact = p.length() - 0.5;
            let d = t.signed_distance(p);
            assert!((d - exact).abs() < 0.003 * 0.5, "at {p}: {d} against {exact}");
        }
    }

    #[test]
    fn closed_meshes_have_no_open_edges_and_a_plane_has_four() {
        assert_eq!(open_edges(&primitives::cube()), 0);
        assert_eq!(open_edges(&primitives::sphere(16, 8)), 0);
        assert_eq!(open_edges(&primitives::cylinder(16)), 0);
        assert_eq!(open_edges(&crate::geometry::load::builtin_mesh("bunny").unwrap()), 0);
        assert_eq!(open_edges(&primitives::plane()), 4);
    }
}

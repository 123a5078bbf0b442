//! Scene geometry without a GPU: indexed triangle meshes, the built-in
//! primitives, mesh files (OBJ, glTF) and terrain floors. The renderer
//! uploads these as they are; tests and CPU references read them directly.

pub mod load;
pub mod primitives;
pub mod sdf;
pub mod terrain;

use glam::{Mat4, Vec2, Vec3};

/// An indexed triangle mesh with per-vertex normals and texture coordinates.
/// Triangles wind counter-clockwise seen from the side the normal faces.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub indices: Vec<u32>,
}

impl Mesh {
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Drop triangles with a repeated vertex or (numerically) zero area;
    /// returns how many were dropped.
    pub fn remove_degenerate_triangles(&mut self) -> usize {
        let before = self.triangle_count();
        let p = &self.positions;
        let kept: Vec<u32> = self
            .indices
            .chunks_exact(3)
            .filter(|t| {
                let (a, b, c) = (t[0] as usize, t[1] as usize, t[2] as usize);
                if a == b || b == c || a == c {
                    return false;
                }
                let (e1, e2) = (p[b] - p[a], p[c] - p[a]);
                let scale = e1.length_squared().max(e2.length_squared());
                e1.cross(e2).length_squared() > 1e-12 * scale * scale && scale > 0.0
            })
            .flatten()
            .copied()
            .collect();
        self.indices = kept;
        before - self.triangle_count()
    }

    /// Area-weighted vertex normals from the triangles (for meshes without normals).
    pub fn compute_normals(&mut self) {
        let mut n = vec![Vec3::ZERO; self.positions.len()];
        for t in self.indices.chunks_exact(3) {
            let (a, b, c) = (t[0] as usize, t[1] as usize, t[2] as usize);
            let face = (self.positions[b] - self.positions[a])
                .cross(self.positions[c] - self.positions[a]);
            n[a] += face;
            n[b] += face;
            n[c] += face;
        }
        self.normals = n.into_iter().map(|v| v.try_normalize().unwrap_or(Vec3::Y)).collect();
    }

    /// Axis-aligned bounds (min, max) after `transform`; `None` when empty.
    pub fn bounds(&self, transform: &Mat4) -> Option<(Vec3, Vec3)> {
        let mut it = self.positions.iter().map(|p| transform.transform_point3(*p));
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
    }

    /// The eight corners of box `(lo, hi)`.
    pub fn box_corners((lo, hi): (Vec3, Vec3)) -> [Vec3; 8] {
        std::array::from_fn(|k| {
            Vec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            )
        })
    }

    /// The box around box `(lo, hi)` once `transform` has moved it (its
    /// eight corners': a moving body's shadow caster where it is now).
    pub fn moved_bounds(transform: &Mat4, bounds: (Vec3, Vec3)) -> (Vec3, Vec3) {
        Self::box_corners(bounds)
            .into_iter()
            .map(|c| transform.transform_point3(c))
            .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(a, b), p| (a.min(p), b.max(p)))
    }

    /// Append `other`, shifting its indices.
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.uvs.extend_from_slice(&other.uvs);
        self.indices.extend(other.indices.iter().map(|i| i + base));
    }

    /// Check the invariants the renderer relies on.
    pub fn is_consistent(&self) -> bool {
        let n = self.positions.len();
        self.normals.len() == n
            && self.uvs.len() == n
            && self.indices.len().is_multiple_of(3)
            && self.indices.iter().all(|&i| (i as usize) < n)
            && self.positions.iter().all(|p| p.is_finite())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box moved and turned is the box around its corners where they went.
    #[test]
    fn moved_bounds_hold_the_moved_box() {
        let b = (Vec3::new(-1.0, -0.5, -2.0), Vec3::new(1.0, 0.5, 2.0));
        let shifted = Mesh::moved_bounds(&Mat4::from_translation(Vec3::new(10.0, 0.0, -3.0)), b);
        assert_eq!(shifted, (Vec3::new(9.0, -0.5, -5.0), Vec3::new(11.0, 0.5, -1.0)));
        let turn = Mat4::from_rotation_y(std::f32::consts::FRAC_PI_2);
        let (lo, hi) = Mesh::moved_bounds(&turn, b);
        assert!(
            lo.distance(Vec3::new(-2.0, -0.5, -1.0)) < 1e-6
                && hi.distance(Vec3::new(2.0, 0.5, 1.0)) < 1e-6
        );
    }

    #[test]
    fn degenerate_triangles_are_skipped() {
        let mut m = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Z, Vec3::X * 2.0],
            normals: vec![Vec3::Y; 4],
            uvs: vec![Vec2::ZERO; 4],
            indices: vec![0, 2, 1, 0, 0, 1, 0, 1, 3],
        };
        assert_eq!(m.remove_degenerate_triangles(), 2);
        assert_eq!(m.indices, vec![0, 2, 1]);
    }

    #[test]
    fn computed_normals_face_the_counter_clockwise_side() {
        let mut m = Mesh {
            positions: vec![Vec3::ZERO, Vec3::Z, Vec3::X],
            indices: vec![0, 1, 2],
            ..Default::default()
        };
        m.compute_normals();
        for n in &m.normals {
            assert!((*n - Vec3::Y).length() < 1e-6, "{n}");
        }
    }
}

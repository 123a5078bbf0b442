//! Built-in primitives, all of unit size centred at the origin (scale them
//! with the object's transform): a box of side 1, a sphere and a cylinder of
//! diameter 1 (the cylinder's axis along y, height 1), and a plane of side 1
//! facing +y.

use super::Mesh;
use glam::{Vec2, Vec3};
use std::f32::consts::{PI, TAU};

pub fn plane() -> Mesh {
    let positions = vec![
        Vec3::new(-0.5, 0.0, -0.5),
        Vec3::new(-0.5, 0.0, 0.5),
        Vec3::new(0.5, 0.0, 0.5),
        Vec3::new(0.5, 0.0, -0.5),
    ];
    Mesh {
        uvs: positions.iter().map(|p| Vec2::new(p.x + 0.5, p.z + 0.5)).collect(),
        positions,
        normals: vec![Vec3::Y; 4],
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

pub fn cube() -> Mesh {
    let mut m = Mesh::default();
    // Each face: its normal and two in-plane axes with u × v = normal.
    for n in [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z] {
        let u = if n.y.abs() > 0.5 { Vec3::X } else { Vec3::Y.cross(n) };
        let v = n.cross(u);
        let base = m.positions.len() as u32;
        for (a, b) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
            m.positions.push(0.5 * n + a * u + b * v);
            m.normals.push(n);
            m.uvs.push(Vec2::new(a + 0.5, 0.5 - b));
        }
        m.indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    m
}

pub fn sphere(segments: u32, rings: u32) -> Mesh {
    let mut m = Mesh::default();
    for r in 0..=rings {
        let theta = PI * r as f32 / rings as f32;
        for s in 0..=segments {
            let phi = TAU * s as f32 / segments as f32;
            let n = Vec3::new(theta.sin() * phi.cos(), theta.cos(), -theta.sin() * phi.sin());
            m.positions.push(0.5 * n);
            m.normals.push(n);
            m.uvs.push(Vec2::new(s as f32 / segments as f32, r as f32 / rings as f32));
        }
    }
    let row = segments + 1;
    for r in 0..rings {
        for s in 0..segments {
            let (a, b) = (r * row + s, (r + 1) * row + s);
            m.indices.extend([a, b, a + 1, a + 1, b, b + 1]);
        }
    }
    m.remove_degenerate_triangles();
    m
}

pub fn cylinder(segments: u32) -> Mesh {
    let mut m = Mesh::default();
    for s in 0..=segments {
        let phi = TAU * s as f32 / segments as f32;
        let n = Vec3::new(phi.cos(), 0.0, -phi.sin());
        for y in [-0.5, 0.5] {
            m.positions.push(0.5 * n + Vec3::Y * y);
            m.normals.push(n);
            m.uvs.push(Vec2::new(s as f32 / segments as f32, 0.5 - y));
        }
    }
    for s in 0..segments {
        let a = 2 * s;
        m.indices.extend([a, a + 2, a + 1, a + 1, a + 2, a + 3]);
    }
    for (y, n) in [(0.5f32, Vec3::Y), (-0.5, Vec3::NEG_Y)] {
        let centre = m.positions.len() as u32;
        m.positions.push(Vec3::Y * y);
        m.normals.push(n);
        m.uvs.push(Vec2::splat(0.5));
        for s in 0..=segments {
            let phi = TAU * s as f32 / segments as f32;
            let p = Vec3::new(0.5 * phi.cos(), y, -0.5 * phi.sin());
            m.positions.push(p);
            m.normals.push(n);
            m.uvs.push(Vec2::new(p.x + 0.5, p.z + 0.5));
        }
        for s in 0..segments {
            let (a, b) = (centre + 1 + s, centre + 2 + s);
            if y > 0.0 {
                m.indices.extend([centre, a, b])
            } else {
                m.indices.extend([centre, b, a])
            }
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle's winding agrees with its vertices' normals, and a
    /// closed mesh's signed volume is what the shape's formula says.
    fn check(m: &Mesh, volume: Option<f32>) {
        assert!(m.is_consistent());
        let mut signed = 0.0;
        for t in m.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| m.positions[i as usize]);
            let face = (b - a).cross(c - a);
            let avg_n =
                m.normals[t[0] as usize] + m.normals[t[1] as usize] + m.normals[t[2] as usize];
            assert!(face.dot(avg_n) > 0.0, "triangle {t:?} winds against its normals");
            signed += a.dot(b.cross(c)) / 6.0;
        }
        if let Some(v) = volume {
            assert!((signed - v).abs() < 0.02 * v, "volume {signed}, expected {v}");
        }
    }

    #[test]
    fn primitives_are_closed_and_outward() {
        check(&cube(), Some(1.0));
        check(&sphere(64, 32), Some(PI / 6.0));
        check(&cylinder(64), Some(PI / 4.0));
        check(&plane(), None);
    }
}

//! Terrain floors: a regular heightfield over a square centred at the origin,
//! from procedural noise (a basin whose shore rises out of the water) or from
//! a grey heightmap image. Heights are y in metres (water level y = 0).

use super::Mesh;
use glam::{Vec2, Vec3};

/// A corner-sampled n×n heightfield over [−size/2, size/2]², row = z, col = x.
#[derive(Clone, Debug, PartialEq)]
pub struct Terrain {
    pub size: f32,
    pub n: usize,
    pub heights: Vec<f32>,
}

/// Parameters of the procedural basin.
#[derive(Clone, Copy, Debug)]
pub struct BasinParams {
    pub size: f32,
    pub resolution: usize,
    /// Depth of the basin floor below the water (m).
    pub depth: f32,
    /// Distance from the centre where the shore reaches its full height (m).
    pub shore_radius: f32,
    /// Height of the land above the water beyond the shore (m).
    pub shore_height: f32,
    /// Amplitude of the fractal relief (m).
    pub relief: f32,
    pub seed: u64,
}

fn hash(ix: i32, iz: i32, seed: u64) -> f32 {
    let mut h = (ix as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (iz as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ seed.wrapping_mul(0x1656_67B1_9E37_79F9);
    h ^= h >> 33;
    h = h.wrapping_mul(0xFF51_AFD7_ED55_8CCD);
    h ^= h >> 33;
    (h >> 40) as f32 / (1u64 << 24) as f32
}

/// Smooth value noise in [0, 1).
pub fn value_noise(p: Vec2, seed: u64) -> f32 {
    let (i, f) = (p.floor(), p - p.floor());
    let u = f * f * (Vec2::splat(3.0) - 2.0 * f);
    let (ix, iz) = (i.x as i32, i.y as i32);
    let a = hash(ix, iz, seed);
    let b = hash(ix + 1, iz, seed);
    let c = hash(ix, iz + 1, seed);
    let d = hash(ix + 1, iz + 1, seed);
    a + (b - a) * u.x + (c - a) * u.y + (a - b - c + d) * u.x * u.y
}

/// Fractal sum of `octaves` of value noise, roughly in [−0.5, 0.5].
pub fn fbm(p: Vec2, octaves: u32, seed: u64) -> f32 {
    let (mut sum, mut amp, mut freq) = (0.0, 0.5, 1.0);
    for o in 0..octaves {
        sum += amp * (value_noise(p * freq, seed.wrapping_add(o as u64)) - 0.5);
        amp *= 0.5;
        freq *= 2.03;
    }
    sum
}

fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl Terrain {
    /// A lake basin: flat-ish floor at −depth, rising past the water line to
    /// +shore_height around `shore_radius`, with a shoreline made irregular
    /// by low-frequency noise and fractal relief on top.
    pub fn basin(p: &BasinParams) -> Terrain {
        let n = p.resolution.max(2);
        let mut heights = Vec::with_capacity(n * n);
        for j in 0..n {
            for i in 0..n {
                let x = (i as f32 / (n - 1) as f32 - 0.5) * p.size;
                let z = (j as f32 / (n - 1) as f32 - 0.5) * p.size;
                let q = Vec2::new(x, z);
                let wobble = 1.0 + 0.6 * fbm(q / p.shore_radius * 1.5, 3, p.seed ^ 0xABCD);
                let r = q.length() / wobble;
                let rise = smoothstep(0.45 * p.shore_radius, p.shore_radius, r);
                // Relief fades out towards the square's edge so the flat skirt meets it smoothly.
                let edge = 1.0 - smoothstep(0.8 * 0.5 * p.size, 0.5 * p.size, x.abs().max(z.abs()));
                let detail = p.relief * fbm(q / 8.0, 5, p.seed) * (0.3 + rise) * edge;
                heights.push(-p.depth + (p.depth + p.shore_height) * rise + detail);
            }
        }
        Terrain { size: p.size, n, heights }
    }

    /// From a heightmap (values in [0, 1], rows top to bottom = −z to +z):
    /// y = −depth + value · relief, resampled to `resolution`².
    pub fn from_heightmap(
        width: u32,
        height: u32,
        values: &[f32],
        size: f32,
        depth: f32,
        relief: f32,
        resolution: usize,
    ) -> Terrain {
        let n = resolution.max(2);
        let (w, h) = (width as usize, height as usize);
        let at = |x: usize, y: usize| values[y.min(h - 1) * w + x.min(w - 1)];
        let mut heights = Vec::with_capacity(n * n);
        for j in 0..n {
            for i in 0..n {
                let fx = i as f32 / (n - 1) as f32 * (w - 1) as f32;
                let fy = j as f32 / (n - 1) as f32 * (h - 1) as f32;
                let (x0, y0) = (fx.floor() as usize, fy.floor() as usize);
                let (tx, ty) = (fx - x0 as f32, fy - y0 as f32);
                let top = at(x0, y0) * (1.0 - tx) + at(x0 + 1, y0) * tx;
                let bottom = at(x0, y0 + 1) * (1.0 - tx) + at(x0 + 1, y0 + 1) * tx;
                heights.push(-depth + relief * (top * (1.0 - ty) + bottom * ty));
            }
        }
        Terrain { size, n, heights }
    }

    fn grid(&self, i: usize, j: usize) -> f32 {
        self.heights[j.min(self.n - 1) * self.n + i.min(self.n - 1)]
    }

    /// Bilinear height at world (x, z); outside the square, the edge height.
    pub fn height_at(&self, x: f32, z: f32) -> f32 {
        let cell = self.size / (self.n - 1) as f32;
        let fx = ((x + 0.5 * self.size) / cell).clamp(0.0, (self.n - 1) as f32);
        let fz = ((z + 0.5 * self.size) / cell).clamp(0.0, (self.n - 1) as f32);
        let (i, j) = (fx.floor() as usize, fz.floor() as usize);
        let (tx, tz) = (fx - i as f32, fz - j as f32);
        let top = self.grid(i, j) * (1.0 - tx) + self.grid(i + 1, j) * tx;
        let bottom = self.grid(i, j + 1) * (1.0 - tx) + self.grid(i + 1, j + 1) * tx;
        top * (1.0 - tz) + bottom * tz
    }

    /// The heightfield as a mesh, plus a flat skirt carrying the edge heights
    /// out to `skirt` metres from the centre so the land does not end in a
    /// cliff at the edge of the square. UVs are world x, z in metres.
    pub fn to_mesh(&self, skirt: f32) -> Mesh {
        let n = self.n;
        let cell = self.size / (n - 1) as f32;
        let mut m = Mesh::default();
        for j in 0..n {
            for i in 0..n {
                let (x, z) = (i as f32 * cell - 0.5 * self.size, j as f32 * cell - 0.5 * self.size);
                let dx = (self.grid(i + 1, j) - self.grid(i.saturating_sub(1), j))
                    / (cell * if i == 0 || i == n - 1 { 1.0 } else { 2.0 });
                let dz = (self.grid(i, j + 1) - self.grid(i, j.saturating_sub(1)))
                    / (cell * if j == 0 || j == n - 1 { 1.0 } else { 2.0 });
                m.positions.push(Vec3::new(x, self.grid(i, j), z));
                m.normals.push(Vec3::new(-dx, 1.0, -dz).normalize());
                m.uvs.push(Vec2::new(x, z));
            }
        }
        let idx = |i: usize, j: usize| (j * n + i) as u32;
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                m.indices.extend([
                    idx(i, j),
                    idx(i, j + 1),
                    idx(i + 1, j + 1),
                    idx(i, j),
                    idx(i + 1, j + 1),
                    idx(i + 1, j),
                ]);
            }
        }
        if skirt > 0.5 * self.size {
            // Walk the border counter-clockwise seen from above and push each
            // border vertex radially out to the skirt's square.
            let mut border = Vec::new();
            border.extend((0..n - 1).map(|i| (i, 0)));
            border.extend((0..n - 1).map(|j| (n - 1, j)));
            border.extend((1..n).rev().map(|i| (i, n - 1)));
            border.extend((1..n).rev().map(|j| (0, j)));
            let base = m.positions.len() as u32;
            for &(i, j) in &border {
                let p = m.positions[j * n + i];
                let dir = Vec2::new(p.x, p.z);
                let out = dir / dir.abs().max_element().max(1e-6) * skirt;
                m.positions.push(Vec3::new(out.x, p.y, out.y));
                m.normals.push(Vec3::Y);
                m.uvs.push(out);
            }
            let k = border.len();
            for a in 0..k {
                let b = (a + 1) % k;
                let (ia, ib) = (idx(border[a].0, border[a].1), idx(border[b].0, border[b].1));
                let (oa, ob) = (base + a as u32, base + b as u32);
                m.indices.extend([ia, ob, oa, ia, ib, ob]);
            }
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basin_is_deep_in_the_middle_and_dry_at_the_shore() {
        let t = Terrain::basin(&BasinParams {
            size: 200.0,
            resolution: 129,
            depth: 8.0,
            shore_radius: 60.0,
            shore_height: 4.0,
            relief: 1.0,
            seed: 3,
        });
        assert!(t.height_at(0.0, 0.0) < -6.0, "{}", t.height_at(0.0, 0.0));
        assert!(t.height_at(95.0, 95.0) > 2.0, "{}", t.height_at(95.0, 95.0));
        let m = t.to_mesh(2000.0);
        assert!(m.is_consistent());
        // Every triangle faces up (a heightfield never overhangs).
        for tri in m.indices.chunks_exact(3) {
            let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| m.positions[i as usize]);
            assert!((b - a).cross(c - a).y > 0.0, "{tri:?}");
        }
    }

    #[test]
    fn heightmap_maps_grey_to_depth_and_relief() {
        let t = Terrain::from_heightmap(2, 2, &[0.0, 1.0, 0.0, 1.0], 10.0, 3.0, 5.0, 3);
        assert_eq!(t.height_at(-5.0, 0.0), -3.0);
        assert_eq!(t.height_at(5.0, 0.0), 2.0);
        assert!((t.height_at(0.0, 2.0) + 0.5).abs() < 1e-6);
    }
}

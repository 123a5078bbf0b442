//! A user-given water surface: heights on a corner-sampled periodic grid
//! (row = z, col = x) over a patch [Lx, Lz] centred at the origin, tiling the
//! plane (`water.model = "heightfield"`). Heights are interpolated
//! bilinearly; slopes are central differences one cell apart; there is no
//! horizontal displacement. CPU twin of the heightfield model in
//! `shaders/surface.wgsl`.

use super::SurfaceSample;

#[derive(Clone, Debug, PartialEq)]
pub struct Heightfield {
    /// Samples per side: x (columns) and z (rows).
    pub nx: usize,
    pub nz: usize,
    /// Patch size [Lx, Lz] (m).
    pub size: [f32; 2],
    pub heights: Vec<f32>,
}

impl Heightfield {
    fn at(&self, i: i64, j: i64) -> f32 {
        let i = i.rem_euclid(self.nx as i64) as usize;
        let j = j.rem_euclid(self.nz as i64) as usize;
        self.heights[j * self.nx + i]
    }

    /// Bilinear height at world (x, z); sample (0, 0) sits at (−Lx/2, −Lz/2).
    pub fn height(&self, x: f32, z: f32) -> f32 {
        let fx = (x / self.size[0] + 0.5) * self.nx as f32;
        let fz = (z / self.size[1] + 0.5) * self.nz as f32;
        let (i, j) = (fx.floor(), fz.floor());
        let (ax, az) = (fx - i, fz - j);
        let (i, j) = (i as i64, j as i64);
        let top = self.at(i, j) * (1.0 - ax) + self.at(i + 1, j) * ax;
        let bottom = self.at(i, j + 1) * (1.0 - ax) + self.at(i + 1, j + 1) * ax;
        top * (1.0 - az) + bottom * az
    }

    pub fn sample(&self, x: f32, z: f32) -> SurfaceSample {
        let (dx, dz) = (self.size[0] / self.nx as f32, self.size[1] / self.nz as f32);
        SurfaceSample {
            displacement: [0.0, self.height(x, z), 0.0],
            slope: [
                (self.height(x + dx, z) - self.height(x - dx, z)) / (2.0 * dx),
                (self.height(x, z + dz) - self.height(x, z - dz)) / (2.0 * dz),
            ],
            ..Default::default()
        }
    }

    /// The largest |height| (for culling bounds).
    pub fn max_abs(&self) -> f32 {
        self.heights.iter().fold(0.0, |m, h| m.max(h.abs()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sampled_sine_is_reproduced_and_tiles() {
        let (n, l) = (64usize, 8.0f32);
        let k = std::f32::consts::TAU / l;
        let heights = (0..n * n)
            .map(|idx| 0.1 * (k * ((idx % n) as f32 / n as f32 - 0.5) * l).sin())
            .collect();
        let h = Heightfield { nx: n, nz: n, size: [l, l], heights };
        for x in [-3.9f32, -1.0, 0.3, 2.5] {
            let s = h.sample(x, 1.0);
            assert!((s.displacement[1] - 0.1 * (k * x).sin()).abs() < 2e-3, "height at {x}");
            assert!((s.slope[0] - 0.1 * k * (k * x).cos()).abs() < 5e-3, "slope at {x}");
            assert!(s.slope[1].abs() < 1e-5);
            assert!((h.height(x + l, 3.0) - h.height(x, 3.0)).abs() < 1e-5, "periodic");
        }
    }
}

//! Surface caustics on the floor by photon splatting from the light (seed 000
//! §3.4, §4.5, after Papadopoulos & Papaioannou 2009): a regular grid of
//! photons over a periodic patch of the surface, each refracted at the
//! displaced surface with Snell's law, weighted by the Fresnel transmittance
//! and by the sunlight its surface cell intercepts, and splatted where it
//! meets the floor plane. CPU reference of `passes/caustics`.
//!
//! Unit: floor irradiance relative to the sun's irradiance on a plane facing
//! its rays, without the water's absorption (receivers apply that along their
//! own depth). Flat water under an overhead sun gives T(0) ≈ 0.98
//! everywhere; with the sun at elevation e, T(θ)·sin e.

use crate::optics::{IOR_AIR, fresnel_exact, refract};
use crate::waves::SurfaceSample;
use glam::{Vec2, Vec3};

#[derive(Clone, Copy, Debug)]
pub struct PhotonSettings {
    /// Photons per side of the patch.
    pub photons_per_side: usize,
    /// Cells per side of the floor map (M).
    pub map_resolution: usize,
    /// Patch size [Lx, Lz] (m), centred at the origin; the map tiles the plane.
    pub patch: [f32; 2],
    /// Depth of the floor below the mean surface (m).
    pub floor_depth: f32,
    pub ior: f32,
    /// Unit direction towards the sun.
    pub sun_dir: Vec3,
}

/// An M×M cell-centred map over the patch, row = z, col = x.
#[derive(Clone, Debug, PartialEq)]
pub struct FloorCaustics {
    pub m: usize,
    pub patch: [f32; 2],
    pub irradiance: Vec<f32>,
}

/// A photon just under the surface: where it enters the water (displaced),
/// the unit direction it travels, and the fraction of the sun's irradiance
/// × area it carries per unit of undisplaced surface area (the area the
/// displaced cell shows the sun, times the Fresnel transmittance). `None`
/// for a back-facing cell or a ray that does not go down.
pub fn refracted_photon(
    s: &SurfaceSample,
    x0: f32,
    z0: f32,
    sun_dir: Vec3,
    ior: f32,
) -> Option<(Vec3, Vec3, f32)> {
    let tx = Vec3::new(1.0 + s.dxx, s.slope[0], s.dxz);
    let tz = Vec3::new(s.dxz, s.slope[1], 1.0 + s.dzz);
    // Unnormalised normal: its length is the displaced cell's area scale,
    // so its dot with the light is the area the cell shows the sun.
    let area_normal = tz.cross(tx);
    let shown = area_normal.dot(sun_dir);
    if shown <= 0.0 {
        return None;
    }
    let n = area_normal.normalize();
    let t = 1.0 - fresnel_exact(n.dot(sun_dir), IOR_AIR, ior);
    let dir = refract(-sun_dir, n, IOR_AIR, ior)?;
    if dir.y > -1e-4 {
        return None;
    }
    let pos = Vec3::new(x0 + s.displacement[0], s.displacement[1], z0 + s.displacement[2]);
    Some((pos, dir, shown * t))
}

/// What one photon brings to the floor: where it lands (x, z) and its
/// contribution in irradiance × cell area, or `None` (back-facing cell,
/// total reflection, a ray that never goes down).
pub fn photon(
    s: &SurfaceSample,
    x0: f32,
    z0: f32,
    cell_area: f32,
    p: &PhotonSettings,
) -> Option<(Vec2, f32)> {
    let (pos, dir, weight) = refracted_photon(s, x0, z0, p.sun_dir, p.ior)?;
    let hit = pos + dir * ((pos.y + p.floor_depth) / -dir.y);
    Some((Vec2::new(hit.x, hit.z), weight * cell_area))
}

impl FloorCaustics {
    pub fn zeros(m: usize, patch: [f32; 2]) -> Self {
        FloorCaustics { m, patch, irradiance: vec![0.0; m * m] }
    }

    pub fn cell_area(&self) -> f32 {
        self.patch[0] * self.patch[1] / (self.m * self.m) as f32
    }

    /// Add `energy` (irradiance × cell area) at world (x, z) with bilinear
    /// (tent) weights over the four nearest cell centres, wrapping around
    /// the periodic patch.
    pub fn splat(&mut self, at: Vec2, energy: f32) {
        let m = self.m as i64;
        let fx = (at.x / self.patch[0] + 0.5) * self.m as f32 - 0.5;
        let fz = (at.y / self.patch[1] + 0.5) * self.m as f32 - 0.5;
        let (i0, j0) = (fx.floor(), fz.floor());
        let (ax, az) = (fx - i0, fz - j0);
        let per_cell = energy / self.cell_area();
        for (di, dj, w) in [
            (0, 0, (1.0 - ax) * (1.0 - az)),
            (1, 0, ax * (1.0 - az)),
            (0, 1, (1.0 - ax) * az),
            (1, 1, ax * az),
        ] {
            let i = (i0 as i64 + di).rem_euclid(m) as usize;
            let j = (j0 as i64 + dj).rem_euclid(m) as usize;
            self.irradiance[j * self.m + i] += per_cell * w;
        }
    }

    /// The 3×3 binomial filter [1 2 1]/4 in each direction, periodic (seed
    /// 000 §4.5 filters with a 3×3 Gaussian).
    pub fn blurred(&self) -> FloorCaustics {
        let m = self.m;
        let at = |v: &Vec<f32>, i: usize, j: usize| v[(j % m) * m + (i % m)];
        let mut rows = vec![0.0; m * m];
        for j in 0..m {
            for i in 0..m {
                rows[j * m + i] = 0.25 * at(&self.irradiance, i + m - 1, j)
                    + 0.5 * at(&self.irradiance, i, j)
                    + 0.25 * at(&self.irradiance, i + 1, j);
            }
        }
        let mut out = vec![0.0; m * m];
        for j in 0..m {
            for i in 0..m {
                out[j * m + i] = 0.25 * at(&rows, i, j + m - 1)
                    + 0.5 * at(&rows, i, j)
                    + 0.25 * at(&rows, i, j + 1);
            }
        }
        FloorCaustics { m, patch: self.patch, irradiance: out }
    }

    pub fn mean(&self) -> f32 {
        self.irradiance.iter().sum::<f32>() / self.irradiance.len() as f32
    }
}

/// Trace a photon grid over the patch (undisplaced coordinates, cell
/// centres) against a surface given by `sample(x, z)`, and splat it on the
/// floor (unfiltered). Returns the map and the total transmitted energy.
pub fn trace_floor_caustics(
    sample: impl Fn(f32, f32) -> SurfaceSample,
    p: &PhotonSettings,
) -> (FloorCaustics, f64) {
    let mut map = FloorCaustics::zeros(p.map_resolution, p.patch);
    let n = p.photons_per_side;
    let cell_area = p.patch[0] * p.patch[1] / (n * n) as f32;
    let mut total = 0.0f64;
    for j in 0..n {
        for i in 0..n {
            let x0 = ((i as f32 + 0.5) / n as f32 - 0.5) * p.patch[0];
            let z0 = ((j as f32 + 0.5) / n as f32 - 0.5) * p.patch[1];
            if let Some((at, energy)) = photon(&sample(x0, z0), x0, z0, cell_area, p) {
                map.splat(at, energy);
                total += energy as f64;
            }
        }
    }
    (map, total)
}

/// The flat-water value of the map: T(θ)·cos θ (θ the sun's zenith angle).
pub fn flat_floor_irradiance(sun_dir: Vec3, ior: f32) -> f32 {
    let cos = sun_dir.y.max(0.0);
    (1.0 - fresnel_exact(cos, IOR_AIR, ior)) * cos
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::waves::ocean::{OceanFields, OceanSettings, OceanSpectrum};
    use crate::waves::spectrum::{SeaState, SpectrumKind};

    fn settings(sun_dir: Vec3, depth: f32) -> PhotonSettings {
        PhotonSettings {
            photons_per_side: 256,
            map_resolution: 64,
            patch: [16.0, 16.0],
            floor_depth: depth,
            ior: 1.333,
            sun_dir,
        }
    }

    #[test]
    fn flat_water_gives_the_fresnel_transmittance_everywhere() {
        for elevation in [90.0f32, 50.0, 25.0] {
            let sun = crate::sky::sun_direction(elevation, 30.0);
            let (map, _) =
                trace_floor_caustics(|_, _| SurfaceSample::default(), &settings(sun, 3.0));
            let want = flat_floor_irradiance(sun, 1.333);
            for v in &map.irradiance {
                assert!((v - want).abs() < 1e-4, "elevation {elevation}: {v} vs {want}");
            }
        }
        assert!((flat_floor_irradiance(Vec3::Y, 1.333) - 0.9796).abs() < 1e-3);
    }

    /// A small choppy FFT ocean over a 16 m patch at time `t` (the caustic
    /// tests' surface, here and in `raytrace::caustics`).
    pub(crate) fn ocean(t: f64) -> OceanFields {
        let s = OceanSettings {
            sea: SeaState {
                kind: SpectrumKind::Jonswap,
                wind_speed: 6.0,
                wind_direction: 0.4,
                fetch: 20_000.0,
                depth: 50.0,
                peak_enhancement: 3.3,
                spreading: 8.0,
            },
            patch_size: 16.0,
            resolution: 64,
            cascades: 1,
            choppiness: 0.5,
            seed: 3,
        };
        OceanFields::evaluate(&OceanSpectrum::new(&s), t)
    }

    #[test]
    fn energy_is_conserved_and_focused_by_waves() {
        let fields = ocean(12.0);
        let sun = crate::sky::sun_direction(60.0, -20.0);
        let p = settings(sun, 6.0);
        let (map, total) = trace_floor_caustics(|x, z| fields.sample(x as f64, z as f64), &p);
        // Every photon lands somewhere on the periodic floor: the map's mean
        // is the transmitted flux per unit area.
        let mean_transmitted = total / (p.patch[0] * p.patch[1]) as f64;
        assert!((map.mean() as f64 - mean_transmitted).abs() < 1e-4 * mean_transmitted);
        let blurred = map.blurred();
        assert!((blurred.mean() - map.mean()).abs() < 1e-4, "the filter keeps the energy");
        // Waves focus light: bright lines well above the mean, dim cells below.
        let max = blurred.irradiance.iter().cloned().fold(0.0, f32::max);
        let min = blurred.irradiance.iter().cloned().fold(f32::MAX, f32::min);
        assert!(
            max > 1.5 * blurred.mean() && min < 0.7 * blurred.mean(),
            "max {max} min {min} mean {}",
            blurred.mean()
        );
        // The mean is close to the flat value (the same sunlight gets in).
        let flat = flat_floor_irradiance(sun, 1.333);
        assert!((blurred.mean() - flat).abs() < 0.05 * flat, "{} vs {flat}", blurred.mean());
    }
}

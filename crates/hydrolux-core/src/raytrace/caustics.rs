//! Caustics on the traced ground (seed 003 §3.3.1, after Baboud & Décoret
//! 2006 §5, "photon texture"): photons of sunlight on a regular grid over
//! the water surface are refracted at the displaced surface, traced to where
//! they first meet the ground heightfield, and splatted there into an
//! illumination map over a window of the ground, which the traced ground
//! reads. Unlike the layered maps of [`crate::caustics`] (a flat floor at a
//! few depths, periodic), every photon lands where it really meets the
//! ground — terrain of any depth, slopes, the sides of hills — and a photon
//! that something blocks (terrain or an object between the sun and the
//! surface, or between the surface and the ground) brings no light: the
//! map also holds the shadows traced through the surface.
//!
//! Unit: the light per unit of horizontal ground area relative to flat
//! water over flat ground (1 where the surface neither focuses nor spreads
//! it; 0 in shadow). Per horizontal area a slope of normal n under the
//! refracted beam b takes n·(−b) / (n_y·(−b_y)) of the flat ground's light,
//! so the map already holds the receiver's cosine: the ground's irradiance
//! is the flat ground's times factor × n_y. CPU twin of
//! `passes/raytrace/caustics.wgsl`.

use super::{Heightfield, MinMaxPyramid, Ray, trace_hierarchical};
use crate::caustics::flat_floor_irradiance;
use crate::optics::{IOR_AIR, refract};
use glam::{Vec2, Vec3};

/// Most photons per side of the emission grid.
pub const MAX_PHOTONS_PER_SIDE: usize = 4096;

/// The square of ground the map covers: `m` × `m` cells of `cell` metres
/// from `origin` (world x, z of its corner), row = z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CausticWindow {
    pub origin: [f32; 2],
    pub cell: f32,
    pub m: usize,
}

impl CausticWindow {
    /// `m` cells over `side` metres, centred as near `center` as the cells
    /// of a map of the same cells centred at the origin allow (so that the
    /// layered maps' cells and these coincide).
    pub fn around(center: [f32; 2], side: f32, m: usize) -> Self {
        let cell = side / m as f32;
        let origin = center.map(|c| {
            let corner = c - 0.5 * side;
            ((corner + 0.5 * side) / cell).round() * cell - 0.5 * side
        });
        CausticWindow { origin, cell, m }
    }

    pub fn side(&self) -> f32 {
        self.cell * self.m as f32
    }

    /// The centre of cell (i, j).
    pub fn cell_center(&self, i: usize, j: usize) -> Vec2 {
        Vec2::new(
            self.origin[0] + (i as f32 + 0.5) * self.cell,
            self.origin[1] + (j as f32 + 0.5) * self.cell,
        )
    }

    /// Whether world (x, z) lies in the window.
    pub fn contains(&self, x: f32, z: f32) -> bool {
        let s = self.side();
        x >= self.origin[0]
            && z >= self.origin[1]
            && x < self.origin[0] + s
            && z < self.origin[1] + s
    }
}

/// The window of `scene`'s traced caustics for a camera at `camera_xz`: the
/// caustic maps' cells over the surface patch, around the camera where the
/// surface repeats (FFT, sines, flat water) and around the origin where it
/// is one patch (a heightfield, the interactive water's domain).
pub fn window_for(scene: &crate::scene::Scene, camera_xz: [f32; 2]) -> CausticWindow {
    use crate::scene::WaterModel;
    let patch = scene.surface_patch();
    let one_patch = scene.water.model == WaterModel::Heightfield
        || (scene.water.model == WaterModel::Flat && scene.water.dynamic);
    let center = if one_patch { [0.0, 0.0] } else { camera_xz };
    CausticWindow::around(center, patch[0].max(patch[1]), scene.caustics.map_resolution as usize)
}

/// Where photons start: a grid of `count` photons `spacing` apart from
/// `origin` (the rest position of the first photon's cell corner).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emission {
    pub origin: [f32; 2],
    pub spacing: f32,
    pub count: [usize; 2],
}

impl Emission {
    /// The photons that can land in `window` on ground down to `depth`
    /// metres under the mean level: the window, widened up-sun by how far a
    /// sunbeam refracted by flat water drifts on its way down, and by a
    /// margin for the waves' bending; the grid aligned to `spacing` in the
    /// world, so that it does not crawl as the window moves.
    pub fn covering(
        window: &CausticWindow,
        spacing: f32,
        sun_dir: Vec3,
        ior: f32,
        depth: f32,
    ) -> Self {
        let travel = sun_travel(sun_dir, ior);
        let drift = Vec2::new(travel.x, travel.z) * (depth.max(0.0) / (-travel.y).max(1e-3));
        let margin = 0.2 * depth.max(0.0) + 2.0 * spacing;
        let lo_w = Vec2::from(window.origin);
        let hi_w = lo_w + Vec2::splat(window.side());
        let lo = lo_w.min(lo_w - drift) - Vec2::splat(margin);
        let hi = hi_w.max(hi_w - drift) + Vec2::splat(margin);
        let lo = (lo / spacing).floor() * spacing;
        let count = ((hi - lo) / spacing).ceil();
        let cap = MAX_PHOTONS_PER_SIDE as f32;
        Emission {
            origin: lo.into(),
            spacing,
            count: [count.x.clamp(1.0, cap) as usize, count.y.clamp(1.0, cap) as usize],
        }
    }

    /// Photon (i, j)'s rest position (its cell's centre).
    pub fn photon_at(&self, i: usize, j: usize) -> Vec2 {
        Vec2::new(
            self.origin[0] + (i as f32 + 0.5) * self.spacing,
            self.origin[1] + (j as f32 + 0.5) * self.spacing,
        )
    }
}

/// The sun's rays under flat water (unit, downwards).
pub fn sun_travel(sun_dir: Vec3, ior: f32) -> Vec3 {
    refract(-sun_dir, Vec3::Y, IOR_AIR, ior).unwrap_or(Vec3::NEG_Y)
}

/// The illumination map: per cell of the window, the factor on the sunlight
/// (see the module's unit).
#[derive(Clone, Debug, PartialEq)]
pub struct GroundCaustics {
    pub window: CausticWindow,
    pub factor: Vec<f32>,
}

/// The ground photons are traced against.
pub struct Ground<'a> {
    pub heightfield: &'a Heightfield,
    pub pyramid: &'a MinMaxPyramid,
}

/// How far photons are traced (m).
pub const PHOTON_REACH: f32 = 2000.0;

/// Trace the photon grid `emission` over a surface (`photon(x, z)`: the
/// photon entering at rest position (x, z) as [`crate::caustics::refracted_photon`]
/// gives it) to the ground, splat each into `window` with bilinear weights
/// and filter with the 3×3 binomial; `blocked(o, d, t_max)` says whether
/// something that is not a heightfield (the traced objects) lies on the ray
/// o + t·d before `t_max`. Twin of `caustic_trace` and `caustic_resolve`.
pub fn trace_ground_caustics(
    photon: impl Fn(f32, f32) -> Option<(Vec3, Vec3, f32)>,
    ground: &Ground,
    blocked: impl Fn(Vec3, Vec3, f32) -> bool,
    window: &CausticWindow,
    emission: &Emission,
    sun_dir: Vec3,
    ior: f32,
) -> GroundCaustics {
    let m = window.m;
    let mut sum = vec![0.0f32; m * m];
    let energy_scale = emission.spacing * emission.spacing / (window.cell * window.cell);
    for j in 0..emission.count[1] {
        for i in 0..emission.count[0] {
            let rest = emission.photon_at(i, j);
            let Some((hit, weight)) = photon_landing(&photon, ground, &blocked, rest, sun_dir)
            else {
                continue;
            };
            splat(&mut sum, window, hit, weight * energy_scale);
        }
    }
    let inv_flat = 1.0 / flat_floor_irradiance(sun_dir, ior).max(1e-4);
    let factor = binomial_clamped(&sum, m).into_iter().map(|v| v * inv_flat).collect();
    GroundCaustics { window: *window, factor }
}

/// Where the photon entering at `rest` lands on the ground (x, z) and the
/// light it carries, or `None`: no photon, the surface there lies under the
/// ground (land), something shades its way in from the sun, or it meets an
/// object or nothing on its way down.
fn photon_landing(
    photon: &impl Fn(f32, f32) -> Option<(Vec3, Vec3, f32)>,
    ground: &Ground,
    blocked: &impl Fn(Vec3, Vec3, f32) -> bool,
    rest: Vec2,
    sun_dir: Vec3,
) -> Option<(Vec2, f32)> {
    let (pos, dir, weight) = photon(rest.x, rest.y)?;
    let hf = ground.heightfield;
    if pos.y <= hf.height(pos.x, pos.z) {
        return None;
    }
    // The way in from the sun: terrain (a cliff) or an object shades it.
    let up = Ray { origin: pos.into(), dir: sun_dir.into() };
    if trace_hierarchical(hf, ground.pyramid, &up, PHOTON_REACH).is_some()
        || blocked(pos, sun_dir, PHOTON_REACH)
    {
        return None;
    }
    let down = Ray { origin: pos.into(), dir: dir.into() };
    let hit = trace_hierarchical(hf, ground.pyramid, &down, PHOTON_REACH)?;
    if blocked(pos, dir, hit.t) {
        return None;
    }
    Some((Vec2::new(hit.position[0], hit.position[2]), weight))
}

/// Add `energy` at world `at` to the four nearest cell centres (bilinear),
/// dropping what falls off the window.
fn splat(sum: &mut [f32], window: &CausticWindow, at: Vec2, energy: f32) {
    let m = window.m as i64;
    let f = (at - Vec2::from(window.origin)) / window.cell - 0.5;
    let base = f.floor();
    let a = f - base;
    let (i0, j0) = (base.x as i64, base.y as i64);
    for (di, dj, w) in [
        (0, 0, (1.0 - a.x) * (1.0 - a.y)),
        (1, 0, a.x * (1.0 - a.y)),
        (0, 1, (1.0 - a.x) * a.y),
        (1, 1, a.x * a.y),
    ] {
        let (i, j) = (i0 + di, j0 + dj);
        if (0..m).contains(&i) && (0..m).contains(&j) {
            sum[(j * m + i) as usize] += energy * w;
        }
    }
}

/// The [1 2 1]/4 × [1 2 1]/4 filter, the edges' cells repeated beyond the
/// window.
fn binomial_clamped(v: &[f32], m: usize) -> Vec<f32> {
    let at = |i: i64, j: i64| {
        let c = |k: i64| k.clamp(0, m as i64 - 1) as usize;
        v[c(j) * m + c(i)]
    };
    let mut out = vec![0.0; m * m];
    for j in 0..m as i64 {
        for i in 0..m as i64 {
            let mut s = 0.0;
            for dj in -1..=1i64 {
                for di in -1..=1i64 {
                    let w = (2 - di.abs()) as f32 * (2 - dj.abs()) as f32 / 16.0;
                    s += w * at(i + di, j + dj);
                }
            }
            out[j as usize * m + i as usize] = s;
        }
    }
    out
}

impl GroundCaustics {
    /// The factor at world (x, z), bilinear between cell centres; `None`
    /// off the window.
    pub fn at(&self, x: f32, z: f32) -> Option<f32> {
        let w = &self.window;
        if !w.contains(x, z) {
            return None;
        }
        let m = w.m as i64;
        let f = (Vec2::new(x, z) - Vec2::from(w.origin)) / w.cell - 0.5;
        let base = f.floor();
        let a = f - base;
        let c = |k: i64| k.clamp(0, m - 1) as usize;
        let v = |i: i64, j: i64| self.factor[c(j) * w.m + c(i)];
        let (i, j) = (base.x as i64, base.y as i64);
        Some(
            v(i, j) * (1.0 - a.x) * (1.0 - a.y)
                + v(i + 1, j) * a.x * (1.0 - a.y)
                + v(i, j + 1) * (1.0 - a.x) * a.y
                + v(i + 1, j + 1) * a.x * a.y,
        )
    }
}

/// Pearson's correlation of two equally long series.
pub fn correlation(a: &[f32], b: &[f32]) -> f64 {
    let n = a.len().min(b.len()) as f64;
    let ma = a.iter().map(|&v| v as f64).sum::<f64>() / n;
    let mb = b.iter().map(|&v| v as f64).sum::<f64>() / n;
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (&x, &y) in a.iter().zip(b) {
        let (dx, dy) = (x as f64 - ma, y as f64 - mb);
        sab += dx * dy;
        saa += dx * dx;
        sbb += dy * dy;
    }
    sab / (saa * sbb).sqrt().max(1e-300)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::caustics::tests::ocean;
    use crate::caustics::{PhotonSettings, refracted_photon, trace_floor_caustics};
    use crate::waves::SurfaceSample;

    fn flat_ground(depth: f32) -> (Heightfield, MinMaxPyramid) {
        let hf = Heightfield::sampled([-1.0, -1.0], 2.0, 2, -depth, |_, _| -depth);
        let p = MinMaxPyramid::new(&hf);
        (hf, p)
    }

    const IOR: f32 = 1.333;

    /// Flat water over ground of any shape: each cell gets the light of the
    /// beam on its slope (Lambert's cosine, from the photons' density alone):
    /// n·(−b) / (n_y·(−b_y)) per horizontal area.
    #[test]
    fn flat_water_lights_sloped_ground_by_lamberts_cosine() {
        let sun = crate::sky::sun_direction(55.0, 30.0);
        let hills = |x: f32, z: f32| -4.0 + 1.5 * (0.4 * x).sin() * (0.3 * z + 1.0).cos();
        let hf = Heightfield::sampled([-20.0, -20.0], 0.125, 321, -4.0, hills);
        let pyramid = MinMaxPyramid::new(&hf);
        let ground = Ground { heightfield: &hf, pyramid: &pyramid };
        let window = CausticWindow::around([0.0, 0.0], 16.0, 64);
        let emission = Emission::covering(&window, 0.03125, sun, IOR, 5.5);
        let flat = SurfaceSample::default();
        let photon = |x: f32, z: f32| refracted_photon(&flat, x, z, sun, IOR);
        let map =
            trace_ground_caustics(photon, &ground, |_, _, _| false, &window, &emission, sun, IOR);
        let b = sun_travel(sun, IOR);
        let mut worst = 0.0f32;
        let (mut lo, mut hi) = (f32::MAX, 0.0f32);
        for j in 2..62 {
            for i in 2..62 {
                let c = window.cell_center(i, j);
                let e = 1e-3;
                let dx = (hills(c.x + e, c.y) - hills(c.x - e, c.y)) / (2.0 * e);
                let dz = (hills(c.x, c.y + e) - hills(c.x, c.y - e)) / (2.0 * e);
                let n = Vec3::new(-dx, 1.0, -dz).normalize();
                let want = n.dot(-b) / (n.y * -b.y);
                let got = map.factor[j * 64 + i];
                worst = worst.max((got - want).abs() / want);
                lo = lo.min(want);
                hi = hi.max(want);
            }
        }
        assert!(hi - lo > 0.4, "the hills face the sun and turn from it: {lo}..{hi}");
        assert!(worst < 0.03, "worst relative error {worst}");
    }

    /// On a flat floor the traced map is the layered photon map's floor
    /// layer: the same photons, the same cells (correlation and mean).
    #[test]
    fn on_a_flat_floor_it_agrees_with_the_photon_caustics() {
        let fields = ocean(9.0);
        let sun = crate::sky::sun_direction(60.0, -20.0);
        let depth = 4.0;
        let settings = PhotonSettings {
            photons_per_side: 256,
            map_resolution: 64,
            patch: [16.0, 16.0],
            floor_depth: depth,
            ior: IOR,
            sun_dir: sun,
        };
        let (layered, _) =
            trace_floor_caustics(|x, z| fields.sample(x as f64, z as f64), &settings);
        let layered = layered.blurred();
        let flat = flat_floor_irradiance(sun, IOR);
        let (hf, pyramid) = flat_ground(depth);
        let ground = Ground { heightfield: &hf, pyramid: &pyramid };
        let window = CausticWindow::around([3.0, -2.0], 16.0, 64);
        let emission = Emission::covering(&window, 16.0 / 256.0, sun, IOR, depth);
        let photon =
            |x: f32, z: f32| refracted_photon(&fields.sample(x as f64, z as f64), x, z, sun, IOR);
        let traced =
            trace_ground_caustics(photon, &ground, |_, _, _| false, &window, &emission, sun, IOR);
        // The same cells: the window is whole cells of the periodic map.
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for j in 1..63 {
            for i in 1..63 {
                let c = window.cell_center(i, j);
                let pi = ((c.x / 16.0 + 0.5) * 64.0 - 0.5).round().rem_euclid(64.0) as usize;
                let pj = ((c.y / 16.0 + 0.5) * 64.0 - 0.5).round().rem_euclid(64.0) as usize;
                a.push(traced.factor[j * 64 + i]);
                b.push(layered.irradiance[pj * 64 + pi] / flat);
            }
        }
        let r = correlation(&a, &b);
        let mean_a = a.iter().sum::<f32>() / a.len() as f32;
        let mean_b = b.iter().sum::<f32>() / b.len() as f32;
        assert!(r > 0.999, "correlation {r}");
        assert!((mean_a - mean_b).abs() < 0.002 * mean_b, "means {mean_a} vs {mean_b}");
        // And it is caustics, not a flat field.
        let max = a.iter().cloned().fold(0.0, f32::max);
        assert!(max > 1.5, "focused to {max}");
    }

    /// A block standing in the water casts its shadow on the floor where the
    /// refracted sunbeam puts it, and light is kept elsewhere.
    #[test]
    fn an_object_shades_the_ground_where_snell_puts_its_shadow() {
        let sun = crate::sky::sun_direction(50.0, 0.0);
        let depth = 3.0;
        let (hf, pyramid) = flat_ground(depth);
        let ground = Ground { heightfield: &hf, pyramid: &pyramid };
        let window = CausticWindow::around([0.0, 0.0], 16.0, 64);
        let emission = Emission::covering(&window, 0.0625, sun, IOR, depth);
        let flat = SurfaceSample::default();
        let photon = |x: f32, z: f32| refracted_photon(&flat, x, z, sun, IOR);
        // A thin horizontal plate 2 m across at y = −1.
        let plate = |o: Vec3, d: Vec3, t_max: f32| {
            if d.y.abs() < 1e-6 {
                return false;
            }
            let t = (-1.0 - o.y) / d.y;
            let p = o + d * t;
            t > 0.0 && t < t_max && p.x.abs() < 1.0 && p.z.abs() < 1.0
        };
        let map = trace_ground_caustics(photon, &ground, plate, &window, &emission, sun, IOR);
        // The plate's shadow: its centre (0, −1, 0) carried down 2 m along
        // the refracted sunbeam.
        let travel = sun_travel(sun, IOR);
        let centre = Vec3::new(0.0, -1.0, 0.0) + travel * (2.0 / -travel.y);
        // Dark across it (the bilinear splat and the filter soften its
        // edges by up to three cells)…
        for (dx, dz) in [(0.0, 0.0), (0.3, 0.0), (-0.3, 0.0), (0.0, 0.3), (0.0, -0.3)] {
            let shade = map.at(centre.x + dx, centre.z + dz).unwrap();
            assert!(shade < 1e-3, "in the shadow at {dx}, {dz}: {shade}");
        }
        // …and the flat value beyond its edges: no wider than the plate.
        for (dx, dz) in [(1.7, 0.0), (-1.7, 0.0), (0.0, 1.7), (0.0, -1.7)] {
            let lit = map.at(centre.x + dx, centre.z + dz).unwrap();
            assert!((lit - 1.0).abs() < 1e-3, "lit at {dx}, {dz}: {lit}");
        }
    }

    /// Photons that the land shades or that start under it bring nothing:
    /// the ground behind a cliff, up-sun of it, lies in the cliff's shadow.
    #[test]
    fn a_cliff_shades_the_water_beside_it() {
        let sun = crate::sky::sun_direction(35.0, 180.0);
        // Sun towards −x; a cliff 2 m high at x < −4 (up-sun) shades the
        // water beside it.
        let cliff = |x: f32, _z: f32| if x < -4.0 { 2.0 } else { -3.0 };
        let hf = Heightfield::sampled([-20.0, -20.0], 0.25, 161, -3.0, cliff);
        let pyramid = MinMaxPyramid::new(&hf);
        let ground = Ground { heightfield: &hf, pyramid: &pyramid };
        let window = CausticWindow::around([0.0, 0.0], 16.0, 64);
        let emission = Emission::covering(&window, 0.0625, sun, IOR, 3.0);
        let flat = SurfaceSample::default();
        let photon = |x: f32, z: f32| refracted_photon(&flat, x, z, sun, IOR);
        let map =
            trace_ground_caustics(photon, &ground, |_, _, _| false, &window, &emission, sun, IOR);
        assert!(sun.x < -0.5, "the sun stands towards −x");
        // The cliff's edge (x = −4.25, y = 2) shades the surface out to
        // x = −4.25 + 2/tan 35° ≈ −1.39; refracted, that light would reach
        // the floor 3 m down 3·tan θt further on, at ≈ 0.94.
        let travel = sun_travel(sun, IOR);
        let edge = -4.25 + 2.0 / 35f32.to_radians().tan() + 3.0 * travel.x / -travel.y;
        for x in [-3.5, -2.0, edge - 0.7] {
            let dark = map.at(x, 0.0).unwrap();
            assert!(dark < 1e-3, "in the cliff's shadow at x = {x}: {dark}");
        }
        for x in [edge + 0.7, 4.0, 7.0] {
            let lit = map.at(x, 0.0).unwrap();
            assert!((lit - 1.0).abs() < 1e-3, "lit at x = {x}: {lit}");
        }
    }
}

//! Ray tracing of water volumes (seed 003 §3.3.1, after Baboud & Décoret
//! 2006, *Realistic Water Volumes in Real-Time*): the water surface and the
//! ground are heightfields, and a ray is intersected with either exactly.
//!
//! A [`Heightfield`] is corner-sampled and bilinear between its samples, so
//! along a ray inside one cell its height is a quadratic in the ray's
//! parameter and the crossing is a root of that quadratic: exact, with no
//! step size to tune. [`MinMaxPyramid`] bounds every block of 2^k × 2^k
//! cells by the least and greatest of its samples (a bilinear patch takes its
//! extremes at its corners, so the bounds are conservative), and
//! [`trace_hierarchical`] walks it (the maximum-mipmap traversal of Tevs,
//! Ihrke & Seidel, *Maximum Mipmaps for Fast, Accurate, and Scalable
//! Dynamic Height Field Rendering*, 2008): a block the ray's height range
//! clears is skipped whole, and only the cells it may cross are solved.
//! [`trace_dense`] is the brute-force reference (a fine march and
//! bisection) the hierarchical tracer and its GPU twin are tested against.
//!
//! A choppy surface (horizontal displacement) is not a heightfield of its
//! rest position: [`Heightfield::resampled`] builds the world-space
//! heightfield of it by undoing the displacement at every sample (a
//! fixed-point iteration, as the white water's particles do). Where a crest
//! folds over, only one of its layers is kept.
//!
//! [`caustics`] traces the sun's photons through the surface to the ground
//! (the paper's photon texture) for the light the traced ground receives.

pub mod bvh;
pub mod caustics;

/// The surface a ray is traced against: y = height(x, z), with the sign of
/// y − height telling the sides apart.
#[derive(Clone, Debug, PartialEq)]
pub struct Heightfield {
    /// World (x, z) of sample (0, 0) (m).
    pub origin: [f32; 2],
    /// Spacing of the samples (m).
    pub cell: f32,
    /// Samples per side (n × n, row = z).
    pub n: usize,
    pub heights: Vec<f32>,
    /// The height beyond the sampled square (a floor that goes on, or the
    /// mean level of the water).
    pub outside: f32,
}

impl Heightfield {
    /// `n` × `n` samples of `height` over the square from `origin`, `cell` apart.
    pub fn sampled(
        origin: [f32; 2],
        cell: f32,
        n: usize,
        outside: f32,
        height: impl Fn(f32, f32) -> f32,
    ) -> Self {
        let mut heights = Vec::with_capacity(n * n);
        for j in 0..n {
            for i in 0..n {
                heights.push(height(origin[0] + i as f32 * cell, origin[1] + j as f32 * cell));
            }
        }
        Heightfield { origin, cell, n, heights, outside }
    }

    /// The world-space heightfield of a displaced surface: at each sample x
    /// the height of the surface point displaced onto x, found by undoing
    /// the displacement (x₀ ← x − D(x₀), `iterations` times; `surface`
    /// gives (Dx, h, Dz) at a rest position). Twin of `resample` in
    /// `passes/raytrace/raytrace.wgsl`.
    pub fn resampled(
        origin: [f32; 2],
        cell: f32,
        n: usize,
        outside: f32,
        iterations: u32,
        surface: impl Fn(f32, f32) -> [f32; 3],
    ) -> Self {
        Self::sampled(origin, cell, n, outside, |x, z| {
            let mut rest = [x, z];
            for _ in 0..iterations {
                let d = surface(rest[0], rest[1]);
                rest = [x - d[0], z - d[2]];
            }
            surface(rest[0], rest[1])[1]
        })
    }

    /// Cells per side (samples − 1).
    pub fn cells(&self) -> usize {
        self.n.saturating_sub(1)
    }

    /// Sample (i, j), the outside height beyond the grid.
    pub fn sample(&self, i: i64, j: i64) -> f32 {
        let n = self.n as i64;
        if i < 0 || j < 0 || i >= n || j >= n {
            return self.outside;
        }
        self.heights[(j * n + i) as usize]
    }

    /// Bilinear height at world (x, z); the outside height off the grid.
    pub fn height(&self, x: f32, z: f32) -> f32 {
        let u = (x - self.origin[0]) / self.cell;
        let v = (z - self.origin[1]) / self.cell;
        let c = self.cells() as f32;
        if !(u >= 0.0 && v >= 0.0 && u <= c && v <= c) {
            return self.outside;
        }
        let (i, j) = (
            (u.floor() as i64).min(self.cells() as i64 - 1),
            (v.floor() as i64).min(self.cells() as i64 - 1),
        );
        let (a, b) = (u - i as f32, v - j as f32);
        let h00 = self.sample(i, j);
        let h10 = self.sample(i + 1, j);
        let h01 = self.sample(i, j + 1);
        let h11 = self.sample(i + 1, j + 1);
        h00 * (1.0 - a) * (1.0 - b) + h10 * a * (1.0 - b) + h01 * (1.0 - a) * b + h11 * a * b
    }

    /// The least and greatest height anywhere (samples and outside).
    pub fn range(&self) -> (f32, f32) {
        self.heights
            .iter()
            .fold((self.outside, self.outside), |(lo, hi), &h| (lo.min(h), hi.max(h)))
    }
}

/// A ray o + t·d.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: [f32; 3],
    pub dir: [f32; 3],
}

impl Ray {
    pub fn at(&self, t: f32) -> [f32; 3] {
        [0, 1, 2].map(|k| self.origin[k] + t * self.dir[k])
    }
}

/// Where a ray crosses a heightfield.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub position: [f32; 3],
}

/// Which side of the heightfield a ray starts on: +1 above, −1 below.
fn side(hf: &Heightfield, ray: &Ray) -> f32 {
    let o = ray.origin;
    if o[1] >= hf.height(o[0], o[2]) { 1.0 } else { -1.0 }
}

/// The reference: march the ray in steps of `cell / 16` up to `t_max` and
/// bisect the first step over which it changes side.
pub fn trace_dense(hf: &Heightfield, ray: &Ray, t_max: f32) -> Option<Hit> {
    let s = side(hf, ray);
    let f = |t: f32| {
        let p = ray.at(t);
        s * (p[1] - hf.height(p[0], p[2]))
    };
    let step = hf.cell / 16.0;
    let steps = (t_max / step).ceil() as usize;
    let mut t0 = 0.0;
    for k in 1..=steps {
        let t1 = (k as f32 * step).min(t_max);
        if f(t1) < 0.0 {
            let (mut a, mut b) = (t0, t1);
            // To the float's resolution (40 halvings of a sixteenth of a cell).
            for _ in 0..40 {
                let m = 0.5 * (a + b);
                if f(m) < 0.0 { b = m } else { a = m }
            }
            let t = 0.5 * (a + b);
            return Some(Hit { t, position: ray.at(t) });
        }
        t0 = t1;
    }
    None
}

/// Per level k, for each block of 2^k × 2^k cells: (least, greatest)
/// sample over its corners. Level 0 is per cell; the grid of each level is
/// padded to a power of two (blocks off the heightfield hold its outside
/// height). Twin of the GPU's min/max mip chain.
#[derive(Clone, Debug, PartialEq)]
pub struct MinMaxPyramid {
    /// Blocks per side at level 0 (a power of two ≥ the cells).
    pub side: usize,
    pub levels: Vec<Vec<[f32; 2]>>,
}

impl MinMaxPyramid {
    pub fn new(hf: &Heightfield) -> Self {
        let side = hf.cells().max(1).next_power_of_two();
        let mut level = vec![[0.0f32; 2]; side * side];
        for j in 0..side {
            for i in 0..side {
                let (i, j) = (i as i64, j as i64);
                let s = [
                    hf.sample(i, j),
                    hf.sample(i + 1, j),
                    hf.sample(i, j + 1),
                    hf.sample(i + 1, j + 1),
                ];
                let lo = s.iter().copied().fold(f32::INFINITY, f32::min);
                let hi = s.iter().copied().fold(f32::NEG_INFINITY, f32::max);
                level[j as usize * side + i as usize] = [lo, hi];
            }
        }
        let mut levels = vec![level];
        let mut n = side;
        while n > 1 {
            let prev = levels.last().unwrap();
            let m = n / 2;
            let mut next = vec![[0.0f32; 2]; m * m];
            for j in 0..m {
                for i in 0..m {
                    let c = [(0, 0), (1, 0), (0, 1), (1, 1)]
                        .map(|(di, dj)| prev[(2 * j + dj) * n + 2 * i + di]);
                    next[j * m + i] = [
                        c.iter().map(|v| v[0]).fold(f32::INFINITY, f32::min),
                        c.iter().map(|v| v[1]).fold(f32::NEG_INFINITY, f32::max),
                    ];
                }
            }
            levels.push(next);
            n = m;
        }
        MinMaxPyramid { side, levels }
    }

    /// (least, greatest) of block (i, j) at `level`.
    pub fn bounds(&self, level: usize, i: usize, j: usize) -> [f32; 2] {
        let n = self.side >> level;
        self.levels[level][j * n + i]
    }
}

/// The first root in [t0, t1] of y(t) − h(t) for the ray inside cell (i, j),
/// where h is the cell's bilinear patch: a quadratic in t. Twin of
/// `cell_crossing` in WGSL.
fn cell_crossing(hf: &Heightfield, ray: &Ray, i: i64, j: i64, t0: f32, t1: f32) -> Option<f32> {
    let h00 = hf.sample(i, j);
    let h10 = hf.sample(i + 1, j);
    let h01 = hf.sample(i, j + 1);
    let h11 = hf.sample(i + 1, j + 1);
    // Cell coordinates along the ray: a = a0 + a1·t, b = b0 + b1·t.
    let a0 = (ray.origin[0] - hf.origin[0]) / hf.cell - i as f32;
    let a1 = ray.dir[0] / hf.cell;
    let b0 = (ray.origin[2] - hf.origin[1]) / hf.cell - j as f32;
    let b1 = ray.dir[2] / hf.cell;
    // h = h00 + (h10 − h00)·a + (h01 − h00)·b + k·a·b, k = h00 − h10 − h01 + h11.
    let (ea, eb, k) = (h10 - h00, h01 - h00, h00 - h10 - h01 + h11);
    // f(t) = y(t) − h(t) = c0 + c1·t + c2·t².
    let c0 = ray.origin[1] - (h00 + ea * a0 + eb * b0 + k * a0 * b0);
    let c1 = ray.dir[1] - (ea * a1 + eb * b1 + k * (a0 * b1 + a1 * b0));
    let c2 = -k * a1 * b1;
    first_root(c0, c1, c2, t0, t1)
}

/// The first t in [t0, t1] where c0 + c1·t + c2·t² changes sign (or is 0),
/// if it does. Twin of `first_root` in WGSL.
fn first_root(c0: f32, c1: f32, c2: f32, t0: f32, t1: f32) -> Option<f32> {
    let f = |t: f32| c0 + t * (c1 + t * c2);
    let (f0, f1) = (f(t0), f(t1));
    let mut roots = [f32::INFINITY; 2];
    if c2.abs() <= 1e-7 * (c1.abs() + c0.abs()).max(1e-20) {
        if c1 != 0.0 {
            roots[0] = -c0 / c1;
        }
    } else {
        let disc = c1 * c1 - 4.0 * c2 * c0;
        if disc >= 0.0 {
            // The numerically stable pair.
            let q = -0.5 * (c1 + c1.signum() * disc.sqrt());
            let (r0, r1) = (q / c2, if q != 0.0 { c0 / q } else { f32::INFINITY });
            roots = [r0.min(r1), r0.max(r1)];
        }
    }
    for r in roots {
        if r >= t0 && r <= t1 {
            return Some(r);
        }
    }
    // Rounding can push a root a hair outside while the ends disagree.
    if f0 * f1 < 0.0 || f1 == 0.0 {
        return Some(if f1 == 0.0 { t1 } else { t0 });
    }
    None
}

/// The most pyramid steps a ray takes by default (`water.trace_steps`): no
/// ray a test or scene has thrown needs as many.
pub const MAX_TRACE_STEPS: u32 = 4096;

/// The first crossing of `ray` (from whichever side it starts on) with the
/// heightfield within `t_max`, walking the min/max pyramid: exact for the
/// bilinear heightfield, in time about logarithmic in its size for rays
/// that clear it. Twin of `trace_heightfield` in WGSL.
pub fn trace_hierarchical(
    hf: &Heightfield,
    pyramid: &MinMaxPyramid,
    ray: &Ray,
    t_max: f32,
) -> Option<Hit> {
    trace_hierarchical_within(hf, pyramid, ray, t_max, MAX_TRACE_STEPS)
}

/// [`trace_hierarchical`] with a budget of `steps` pyramid steps (the
/// quality tiers' `water.trace_steps`): a ray that spends it without a hit
/// is taken to miss the heightfield (`None`).
pub fn trace_hierarchical_within(
    hf: &Heightfield,
    pyramid: &MinMaxPyramid,
    ray: &Ray,
    t_max: f32,
    steps: u32,
) -> Option<Hit> {
    let s = side(hf, ray);
    let top = pyramid.levels.len() - 1;
    // Clip the ray to the pyramid's square; beyond it, the outside plane.
    let span = pyramid.side as f32 * hf.cell;
    let lo = hf.origin;
    let (mut t_in, mut t_out) = (0.0f32, t_max);
    for (a, k) in [(0usize, 0usize), (2, 1)] {
        let (o, d) = (ray.origin[a], ray.dir[a]);
        if d.abs() < 1e-12 {
            if o < lo[k] || o > lo[k] + span {
                t_in = f32::INFINITY;
            }
        } else {
            let (ta, tb) = ((lo[k] - o) / d, (lo[k] + span - o) / d);
            t_in = t_in.max(ta.min(tb));
            t_out = t_out.min(ta.max(tb));
        }
    }
    let plane = |t0: f32, t1: f32| -> Option<Hit> {
        // Off the grid the heightfield is the flat outside height.
        let c0 = ray.origin[1] - hf.outside;
        first_root(c0, ray.dir[1], 0.0, t0, t1).map(|t| Hit { t, position: ray.at(t) })
    };
    if t_in >= t_out {
        return plane(0.0, t_max);
    }
    // A thousandth of a cell sideways along the ray: where it goes next
    // (a nudge in t alone can vanish in the float's rounding).
    let nudge = 1e-3 * hf.cell / ray.dir[0].abs().max(ray.dir[2].abs()).max(1e-3);
    if let Some(h) = plane(0.0, t_in) {
        return Some(h);
    }
    // The grid's edge is a wall between it and the outside plane: a ray
    // that meets the grid already on the other side hits the wall.
    let wall = |t: f32, h: f32| -> Option<Hit> {
        let p = ray.at(t);
        (s * (p[1] - h) < 0.0).then_some(Hit { t, position: p })
    };
    if t_in > 0.0 {
        let p = ray.at(t_in + nudge);
        if let Some(h) = wall(t_in, hf.height(p[0], p[2])) {
            return Some(h);
        }
    }
    let mut t = t_in;
    let mut level = top;
    let mut guard = 0;
    while t < t_out && guard < steps {
        guard += 1;
        let size = hf.cell * (1u64 << level) as f32;
        // The block the ray is in just past t.
        let p = ray.at(t + nudge);
        let n = (pyramid.side >> level) as i64;
        let bi = (((p[0] - lo[0]) / size).floor() as i64).clamp(0, n - 1);
        let bj = (((p[2] - lo[1]) / size).floor() as i64).clamp(0, n - 1);
        // Where the ray leaves the block.
        let mut t_exit = t_out;
        for (a, k, b) in [(0usize, 0usize, bi), (2, 1, bj)] {
            let d = ray.dir[a];
            if d.abs() > 1e-12 {
                let edge = lo[k] + (b + (d > 0.0) as i64) as f32 * size;
                t_exit = t_exit.min((edge - ray.origin[a]) / d);
            }
        }
        t_exit = t_exit.max(t);
        let (y0, y1) = (ray.at(t)[1], ray.at(t_exit)[1]);
        let [hmin, hmax] = pyramid.bounds(level, bi as usize, bj as usize);
        let clear = if s > 0.0 { y0.min(y1) > hmax } else { y0.max(y1) < hmin };
        if clear {
            t = t_exit;
            level = (level + 1).min(top);
            continue;
        }
        if level > 0 {
            level -= 1;
            continue;
        }
        if let Some(r) = cell_crossing(hf, ray, bi, bj, t, t_exit) {
            return Some(Hit { t: r, position: ray.at(r) });
        }
        t = t_exit;
    }
    if t < t_out {
        // The budget is spent short of the grid's far side.
        return None;
    }
    if t_out < t_max
        && let Some(h) = wall(t_out, hf.outside)
    {
        return Some(h);
    }
    plane(t_out, t_max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64 as Rng;

    /// Choppy-looking hills: a sum of sines with sharp crests.
    fn waves(x: f32, z: f32) -> f32 {
        0.4 * (0.9 * x + 0.3 * z).sin()
            + 0.25 * (1.7 * z - 0.4 * x + 1.0).sin().powi(3)
            + 0.1 * (3.1 * x + 2.3 * z).cos()
    }

    fn field(n: usize) -> Heightfield {
        Heightfield::sampled([-8.0, -8.0], 16.0 / (n - 1) as f32, n, 0.0, waves)
    }

    #[test]
    fn a_cell_crossing_is_exact_on_the_bilinear_patch() {
        let hf = field(33);
        let ray = Ray { origin: [-3.1, 2.0, 1.7], dir: [0.6, -0.7, 0.2] };
        let hit = trace_hierarchical(&hf, &MinMaxPyramid::new(&hf), &ray, 50.0).expect("a hit");
        let p = hit.position;
        assert!((p[1] - hf.height(p[0], p[2])).abs() < 1e-4, "on the surface: {p:?}");
    }

    #[test]
    fn hierarchical_and_dense_tracing_find_the_same_first_hit() {
        let hf = field(65);
        let pyramid = MinMaxPyramid::new(&hf);
        let mut rng = Rng::new(7);
        let (mut hits, mut earlier) = (0, 0);
        for k in 0..2000 {
            // From above and below, steep to grazing (down to 0.3°), some vertical.
            let above = k % 3 != 0;
            let x = (rng.unit() * 14.0 - 7.0) as f32;
            let z = (rng.unit() * 14.0 - 7.0) as f32;
            let h = hf.height(x, z);
            let y = if above {
                h + (0.01 + 2.0 * rng.unit()) as f32
            } else {
                h - (0.01 + 2.0 * rng.unit()) as f32
            };
            let a = (rng.unit() * std::f64::consts::TAU) as f32;
            let elevation = match k % 5 {
                0 => 0.005,
                1 => 0.05,
                _ => (rng.unit() * 1.5) as f32,
            };
            let vertical = if above { -elevation.sin() } else { elevation.sin() };
            let dir = if k % 97 == 0 {
                [0.0, if above { -1.0 } else { 1.0 }, 0.0]
            } else {
                [a.cos() * elevation.cos(), vertical, a.sin() * elevation.cos()]
            };
            let ray = Ray { origin: [x, y, z], dir };
            let dense = trace_dense(&hf, &ray, 30.0);
            let fast = trace_hierarchical(&hf, &pyramid, &ray, 30.0);
            match (dense, fast) {
                (Some(d), Some(f)) => {
                    hits += 1;
                    if f.t < d.t - 1e-3 {
                        // A grazing crossing the march stepped over: check it is real.
                        let p = f.position;
                        assert!((p[1] - hf.height(p[0], p[2])).abs() < 1e-3, "ray {k}: {p:?}");
                        earlier += 1;
                    } else {
                        assert!(
                            (f.t - d.t).abs() < 1e-3 * d.t.max(1.0),
                            "ray {k}: t {} vs dense {}",
                            f.t,
                            d.t
                        );
                    }
                }
                (None, None) => {}
                (d, f) => panic!("ray {k} {ray:?}: dense {d:?}, hierarchical {f:?}"),
            }
        }
        assert!(hits > 1200, "{hits} rays hit");
        assert!(earlier < 20, "{earlier} rays found an earlier hit than the march");
    }

    #[test]
    fn a_grazing_ray_does_not_tunnel_through_a_thin_crest() {
        // A ridge one cell wide and 2 cm high; a ray skimming 1 cm under its
        // top at 0.06° must hit it, from far away.
        let n = 257;
        let hf = Heightfield::sampled([0.0, 0.0], 0.25, n, 0.0, |x, _| {
            if (x - 40.0).abs() < 0.2 { 0.02 } else { 0.0 }
        });
        let pyramid = MinMaxPyramid::new(&hf);
        let ray = Ray { origin: [1.0, 0.05, 30.0], dir: [1.0, -0.001, 0.0] };
        let hit = trace_hierarchical(&hf, &pyramid, &ray, 100.0).expect("the crest stops it");
        assert!((hit.position[0] - 40.0).abs() < 0.25, "hit at {:?}", hit.position);
    }

    #[test]
    fn off_the_grid_the_outside_height_is_hit() {
        let hf = Heightfield::sampled([0.0, 0.0], 1.0, 9, -2.0, |_, _| -1.0);
        let pyramid = MinMaxPyramid::new(&hf);
        let ray = Ray { origin: [4.0, 1.0, 4.0], dir: [0.8, -0.2, 0.0] };
        // Leaves the 8 m square at x = 8 (y = 0) still above −1; meets −2 at t = 15.
        let hit = trace_hierarchical(&hf, &pyramid, &ray, 100.0).expect("the floor beyond");
        assert!((hit.position[1] + 2.0).abs() < 1e-5 && (hit.t - 15.0).abs() < 1e-3, "{hit:?}");
        let up = Ray { origin: [4.0, 1.0, 4.0], dir: [0.0, 1.0, 0.0] };
        assert_eq!(trace_hierarchical(&hf, &pyramid, &up, 100.0), None);
    }

    #[test]
    fn resampling_undoes_a_gerstner_waves_displacement() {
        // A Gerstner wave: rest x₀ goes to x₀ − Q·A·sin(k·x₀), height A·cos(k·x₀).
        let (a, k, q) = (0.3f32, 0.8f32, 0.9f32);
        let surface = |x: f32, _z: f32| [-q * a * (k * x).sin(), a * (k * x).cos(), 0.0];
        let hf = Heightfield::resampled([-4.0, -4.0], 0.125, 65, 0.0, 12, surface);
        for x0 in [-2.5f32, -1.0, 0.3, 1.9] {
            let d = surface(x0, 0.0);
            let x = x0 + d[0];
            assert!(
                (hf.height(x, 0.0) - d[1]).abs() < 3e-3,
                "at x = {x}: {} vs {}",
                hf.height(x, 0.0),
                d[1]
            );
        }
    }
}

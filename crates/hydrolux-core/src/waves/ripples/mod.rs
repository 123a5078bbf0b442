//! Interactive water: a dynamic heightfield that drops, rain and objects
//! disturb (seed 003 §2.4, heightfields; Tessendorf, *eWave: Using an
//! Exponential Solver on the iWave Problem*, 2014). The CPU twin of
//! `hydrolux::simulation::ripples`.
//!
//! Linear waves on water of depth d: height h and surface velocity potential
//! φ obey ∂h/∂t = K φ and ∂φ/∂t = −B h with K = k·tanh(k·d) and
//! B = g + (σ/ρ)·k², so every wave number k oscillates at
//! ω² = (g·k + (σ/ρ)·k³)·tanh(k·d), gravity waves and capillary ripples alike.
//! In Fourier space each k is an independent oscillator, so a step is its
//! exact rotation (an exponential integrator: exact dispersion at every
//! resolved wavelength, stable for any step), damped by viscosity at
//! 2νk² (Lamb, *Hydrodynamics* §348). A step is one forward FFT of h + iφ,
//! the rotation, one inverse FFT.
//!
//! Boundaries. `Walls`: the domain is mirrored into a grid twice its size,
//! so the state is even about every wall (∂h/∂n = 0, no flux): walls
//! reflect perfectly and volume is conserved exactly. `Open`: the grid is
//! periodic and a sponge ring damps what leaves the domain, which may
//! follow the camera (the grid is addressed by world cell modulo its size;
//! moving the window re-labels cells, nothing is copied).
//!
//! Depth. The operator K depends on the depth. Two depth levels are
//! stepped from one forward transform (packed in one inverse transform) and
//! each cell takes the linear blend of the two by its own depth: waves slow
//! and shorten where the water shoals. Cells with no depth (an object
//! standing through the surface, land) are held at rest: walls inside the
//! domain ([`bed`] says which cells are which).

pub mod bed;

use rustfft::FftPlanner;
use rustfft::num_complex::Complex64;
use std::f64::consts::PI;

use super::dispersion::GRAVITY;
pub use crate::coupling::{BodyMove, Drop};
pub use bed::{RippleBed, wet};

/// Surface tension of clean water over its density, σ/ρ (m³/s²): 0.0728 N/m at 20 °C.
pub const WATER_TENSION: f64 = 0.0728 / 1000.0;
/// Kinematic viscosity of water at 20 °C (m²/s).
pub const WATER_VISCOSITY: f64 = 1.0e-6;

/// ω(k) of linear capillary-gravity waves over depth `depth` (m), with
/// `tension` = σ/ρ (m³/s²).
pub fn capillary_gravity_omega(k: f64, depth: f64, tension: f64) -> f64 {
    ((GRAVITY * k + tension * k * k * k) * (k * depth).tanh()).sqrt()
}

/// The group speed dω/dk of [`capillary_gravity_omega`] (central difference).
pub fn capillary_gravity_group_speed(k: f64, depth: f64, tension: f64) -> f64 {
    let e = k * 1e-5;
    (capillary_gravity_omega(k + e, depth, tension)
        - capillary_gravity_omega(k - e, depth, tension))
        / (2.0 * e)
}

/// How the domain's edges behave.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RippleBoundary {
    /// Closed, reflecting walls on the domain's four sides (a pool, a tank).
    Walls,
    /// Open water: what leaves the domain is absorbed.
    Open,
    /// A tile that repeats: what leaves one side enters the other (for
    /// measurements free of any boundary).
    Periodic,
}

/// The simulated domain: `cells` × `cells` square cells of `cell_size` m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RippleGrid {
    pub boundary: RippleBoundary,
    pub cells: usize,
    pub cell_size: f64,
}

impl RippleGrid {
    /// Side of the FFT grid: the mirrored domain for walls, the domain itself when open.
    pub fn fft_size(&self) -> usize {
        match self.boundary {
            RippleBoundary::Walls => 2 * self.cells,
            RippleBoundary::Open | RippleBoundary::Periodic => self.cells,
        }
    }

    pub fn extent(&self) -> f64 {
        self.cells as f64 * self.cell_size
    }

    /// Width of the absorbing ring of an open domain (cells).
    pub fn sponge_cells(&self) -> usize {
        match self.boundary {
            RippleBoundary::Walls | RippleBoundary::Periodic => 0,
            RippleBoundary::Open => (self.cells / 8).max(4),
        }
    }

    /// The wave vector of FFT index (p, q) (rad/m).
    pub fn wave_vector(&self, p: usize, q: usize) -> (f64, f64) {
        let f = self.fft_size();
        let signed = |i: usize| if i <= f / 2 { i as f64 } else { i as f64 - f as f64 };
        let dk = 2.0 * PI / (f as f64 * self.cell_size);
        (signed(p) * dk, signed(q) * dk)
    }
}

/// The physics of one simulation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RippleSettings {
    pub grid: RippleGrid,
    /// σ/ρ (m³/s²).
    pub tension: f64,
    /// Kinematic viscosity ν (m²/s): waves decay at 2νk².
    pub viscosity: f64,
    /// Extra damping of every wave (1/s), on top of viscosity (0 = physical).
    pub damping: f64,
    /// The two depth levels (m) cells blend between (equal for even depth).
    pub depths: [f64; 2],
    /// Step (s).
    pub dt: f64,
}

/// The fraction of a disturbance's amplitude that counts as forgotten
/// (a simulation's memory is the time to fall to it).
pub const FORGOTTEN: f64 = 1e-3;

/// The most of a wave's amplitude the open edges' sponge gives back per
/// return crossing of the domain (`open_edges_absorb_what_reaches_them`
/// measures under 5% of the energy back).
pub const SPONGE_RETURN: f64 = 0.22;

/// The longest memory (s) a simulation declares: walls without damping
/// ring for days (2νk² is 3e-7/s for a pool's longest wave), and a late
/// time is then simulated from still water 10 to 20 minutes before it.
pub const MAX_MEMORY_S: f64 = 600.0;

impl RippleSettings {
    /// The memory (s, see `clock`): how long until nothing of the water's
    /// start is left, to [`FORGOTTEN`]. Each wave number k decays at
    /// 2νk² + damping; between walls that is all (the slowest, longest
    /// standing wave sets it); in open water a wave also meets the sponge
    /// once per return crossing of the domain (2·extent at its group
    /// speed), which gives back at most [`SPONGE_RETURN`] of it. The
    /// slowest of the resolved waves sets it, at most [`MAX_MEMORY_S`].
    pub fn memory(&self) -> f64 {
        // Twice as long a fall: where waves meet, their peaks add.
        let forget = (2.0 / FORGOTTEN).ln();
        let extent = self.grid.extent();
        let rate = |k: f64| 2.0 * self.viscosity * k * k + self.damping;
        let decay = |k: f64| forget / rate(k);
        let memory = match self.grid.boundary {
            RippleBoundary::Walls => decay(PI / extent),
            RippleBoundary::Periodic => decay(2.0 * PI / extent),
            RippleBoundary::Open => {
                let (k_low, k_high) = (2.0 * PI / extent, PI / self.grid.cell_size);
                (0..=64)
                    .map(|i| {
                        let k = k_low * (k_high / k_low).powf(i as f64 / 64.0);
                        let slowest = self
                            .depths
                            .map(|d| capillary_gravity_group_speed(k, d, self.tension))
                            .into_iter()
                            .fold(f64::INFINITY, f64::min);
                        let crossing = 2.0 * extent / slowest;
                        forget / (rate(k) + (1.0 / SPONGE_RETURN).ln() / crossing)
                    })
                    .fold(0.0, f64::max)
            }
        };
        if memory.is_finite() { memory.min(MAX_MEMORY_S) } else { MAX_MEMORY_S }
    }
}

/// One step's rotation of wave number `k` over depth `depth`: the factors
/// of h' = e·(c·h + s_h·φ), φ' = e·(−s_φ·h + c·φ). Twin of `rotation` in
/// `simulation/ripples/spectral.wgsl`.
pub fn rotation(s: &RippleSettings, k: f64, depth: f64) -> [f64; 4] {
    if k == 0.0 {
        // The mean level never changes (volume); φ's mean is a gauge.
        return [1.0, 1.0, 0.0, 0.0];
    }
    let kk = k * (k * depth).tanh();
    let bb = GRAVITY + s.tension * k * k;
    let w = (kk * bb).sqrt();
    let wt = w * s.dt;
    let sinc = if wt < 1e-6 { 1.0 } else { wt.sin() / wt };
    let decay = (-(2.0 * s.viscosity * k * k + s.damping) * s.dt).exp();
    [decay, wt.cos(), kk * s.dt * sinc, bb * s.dt * sinc]
}

/// Δh of `drop` at world point `w` of the domain. Walls see the drop's
/// mirror images too (the method of images): a wall reflects the part of the
/// crater beyond it, so a drop stays volume-neutral next to a wall. Twin of
/// `drop_height` in WGSL.
pub fn drop_height(grid: &RippleGrid, window: &RippleWindow, drop: &Drop, w: [f64; 2]) -> f64 {
    let mut dh = 0.0;
    let images = if grid.boundary == RippleBoundary::Walls { 3 } else { 1 };
    for ix in 0..images {
        for iz in 0..images {
            let image = |axis: usize, i: usize, c: f64| {
                let lo = window.low_edge(grid, axis);
                match i {
                    0 => c,
                    1 => 2.0 * lo - c,
                    _ => 2.0 * (lo + grid.extent()) - c,
                }
            };
            let (x, z) = (image(0, ix, drop.x), image(1, iz, drop.z));
            dh += drop.height((w[0] - x).powi(2) + (w[1] - z).powi(2));
        }
    }
    dh
}

/// The steepest the water's surface stands between two cells: tan 30°, the
/// slope of the limiting Stokes wave (its crest's 120° corner). Steeper water
/// breaks.
pub const BREAKING_SLOPE: f64 = 0.577;
/// Fraction of the excess over [`BREAKING_SLOPE`] each pair of neighbouring
/// cells trades per step (stable for ≤ ¼ with four neighbours).
pub const BREAKING_RELAX: f64 = 0.25;

/// How far (m) below a hull's bottom the water must be pushed to have
/// parted from it (then it breaks back in: `RippleSim::step_with`); a
/// margin, so that water resting against the hull does not flicker
/// between held and not from rounding.
pub const HULL_GAP: f64 = 0.02;

/// How far (cells) from a point of a lifted body's hollow the free water
/// is looked for whose velocity potential that point takes
/// ([`released_source`]): past the widest hull a pool floats.
pub const RELEASE_REACH_CELLS: i32 = 64;

/// Fixed-point units (per metre of height) the water a hull pushes out in
/// a step is summed in (µm: exact sums in any order; 2 147 m of height over
/// all cells in one step before the GPU's 32 bits overflow, a thousand
/// times a pool's plunge).
pub const PUSHED_UNITS_PER_M: f64 = 1e6;

/// Where a body was lifted out of the water ([`BodyMove::released`]) and
/// no hull holds it now, the water of the hollow it held takes the
/// velocity potential of the free water just outside, one cell past the
/// hollow's edge along the line from the body's centre through world
/// point `w`: the grid index read. What φ held under the hull is the
/// pressure it pressed with, not the water's motion; left there, it
/// sprang back as a mound once the hull let go (φ = 0 would be no better:
/// φ also holds the whole pool's gauge). `None` elsewhere. Twin of `released_source` in
/// ripples.wgsl.
pub fn released_source(
    grid: &RippleGrid,
    window: &RippleWindow,
    bodies: &[BodyMove],
    w: [f64; 2],
) -> Option<usize> {
    // The lifted bodies first: every cell asks every step, and almost
    // always none was lifted.
    let lifted =
        bodies.iter().find(|b| b.released.is_some() && b.depth_before(w[0], w[1]) > 0.0)?;
    if bodies.iter().any(|b| b.depth(w[0], w[1]) > 0.0) {
        return None;
    }
    let c = lifted.held().position;
    let (dx, dz) = (w[0] - c.x, w[1] - c.z);
    let len = dx.hypot(dz);
    let dir = if len > 1e-9 { [dx / len, dz / len] } else { [1.0, 0.0] };
    let cell = grid.cell_size;
    let at = |k: i32| [w[0] + dir[0] * k as f64 * cell, w[1] + dir[1] * k as f64 * cell];
    let edge = (1..=RELEASE_REACH_CELLS).find(|&k| {
        let p = at(k);
        lifted.depth_before(p[0], p[1]) <= 0.0 && bodies.iter().all(|b| b.depth(p[0], p[1]) <= 0.0)
    })?;
    let q = at(edge + 1);
    let n = grid.cells as i64;
    let f = grid.fft_size() as i64;
    let g = [0, 1].map(|a| {
        let world_cell = (q[a] / cell).floor() as i64;
        match grid.boundary {
            RippleBoundary::Walls => (world_cell - window.origin[a]).clamp(0, n - 1),
            RippleBoundary::Open | RippleBoundary::Periodic => world_cell.rem_euclid(f),
        }
    });
    Some((g[1] * f + g[0]) as usize)
}

/// The mean height (m) of the free water of the domain (`h` and
/// `covered` per grid cell): what a hull's pressure head is measured
/// from (`RippleSim::step_with`). 0 when hulls cover it all.
pub fn free_level(grid: &RippleGrid, h: &[f64], covered: &[bool]) -> f64 {
    let (n, f) = (grid.cells, grid.fft_size());
    let (mut sum, mut count) = (0.0, 0usize);
    for j in 0..n {
        for i in 0..n {
            let c = j * f + i;
            if !covered[c] {
                sum += h[c];
                count += 1;
            }
        }
    }
    if count == 0 { 0.0 } else { sum / count as f64 }
}

/// Breaking, as the linear model cannot: where the surface between a cell
/// (height `h`) and a neighbour stands steeper than [`BREAKING_SLOPE`], they
/// trade water until it does not (the pairs are symmetric: the volume is
/// kept; the potential energy only falls). Without it, the linear hollow
/// of a ball dropped in rebounded as a spout 2 m high through the ball, and
/// a ball dragged about left the whole pool heaving metres high. Returns
/// what the cell gives (m). Twin of `breaking` in ripples.wgsl.
pub fn breaking(h: f64, neighbours: [f64; 4], cell: f64) -> f64 {
    let most = BREAKING_SLOPE * cell;
    neighbours
        .iter()
        .map(|n| {
            let d = h - n;
            d.signum() * (d.abs() - most).max(0.0)
        })
        .sum::<f64>()
        * BREAKING_RELAX
}

/// The still water around floating bodies: each rests in its hollow,
/// h = −d, and the free water lies at the scene's level, 0 (the level with
/// the bodies in: what they displace is not added to it, so that the heads
/// they press with, measured from the free water's level, hold their
/// hollows as they are from the first step), over the FFT grid.
pub fn resting_heights(grid: &RippleGrid, window: &RippleWindow, bodies: &[BodyMove]) -> Vec<f64> {
    let f = grid.fft_size();
    let mut h = vec![0.0; f * f];
    for q in 0..f {
        for p in 0..f {
            let (_, w) = domain_cell(grid, window, [p, q]);
            h[q * f + p] = -bodies.iter().map(|b| b.depth(w[0], w[1])).sum::<f64>();
        }
    }
    h
}

/// Where the domain lies in the world: its centre (m). A walled domain
/// stays put; an open one may follow the camera, snapped to whole cells.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RippleWindow {
    /// World cell index of the domain's first cell (x, z).
    pub origin: [i64; 2],
}

impl RippleWindow {
    /// The window of `grid` centred as near `center` as whole cells allow.
    pub fn centred(grid: &RippleGrid, center: [f64; 2]) -> Self {
        let half = grid.cells as f64 / 2.0;
        let o = |c: f64| (c / grid.cell_size - half).round() as i64;
        RippleWindow { origin: [o(center[0]), o(center[1])] }
    }

    /// Where an open domain goes for a camera at `position` looking at
    /// `look_at`: centred a quarter of its side ahead of the camera, over
    /// the water it looks at.
    pub fn ahead_of(grid: &RippleGrid, position: [f64; 3], look_at: [f64; 3]) -> Self {
        let (dx, dz) = (look_at[0] - position[0], look_at[2] - position[2]);
        let len = (dx * dx + dz * dz).sqrt();
        let ahead = if len > 1e-9 { 0.25 * grid.extent() / len } else { 0.0 };
        Self::centred(grid, [position[0] + dx * ahead, position[2] + dz * ahead])
    }

    /// World x (or z) of the domain's low edge.
    pub fn low_edge(&self, grid: &RippleGrid, axis: usize) -> f64 {
        self.origin[axis] as f64 * grid.cell_size
    }
}

/// What a grid cell is: the domain cell whose state it holds and the world
/// position of that cell's centre. Twin of `cell_of` in WGSL.
pub fn domain_cell(
    grid: &RippleGrid,
    window: &RippleWindow,
    g: [usize; 2],
) -> ([usize; 2], [f64; 2]) {
    let n = grid.cells;
    let mut d = [0usize; 2];
    let mut w = [0.0; 2];
    for a in 0..2 {
        d[a] = match grid.boundary {
            // Mirror images: cell 2n−1−i holds cell i.
            RippleBoundary::Walls => {
                if g[a] < n {
                    g[a]
                } else {
                    2 * n - 1 - g[a]
                }
            }
            // Toroidal: grid cell g holds the world cell ≡ g (mod n) in the window.
            RippleBoundary::Open | RippleBoundary::Periodic => {
                (g[a] as i64 - window.origin[a]).rem_euclid(n as i64) as usize
            }
        };
        w[a] = (window.origin[a] as f64 + d[a] as f64 + 0.5) * grid.cell_size;
    }
    (d, w)
}

/// The grid cell holding world cell `c` (open) or domain cell `c` (walls, its first image).
pub fn grid_cell(grid: &RippleGrid, window: &RippleWindow, d: [usize; 2]) -> [usize; 2] {
    match grid.boundary {
        RippleBoundary::Walls => d,
        RippleBoundary::Open | RippleBoundary::Periodic => {
            let n = grid.cells as i64;
            [0, 1].map(|a| (window.origin[a] + d[a] as i64).rem_euclid(n) as usize)
        }
    }
}

/// The texel (row = z) of the surface's texture, and of the landing spray's
/// kicks, that holds world point (x, z): the domain cell for walls, the
/// world cell modulo the grid for open and periodic domains (as the
/// texture tiles the plane). `None` outside the domain. Twin of `kick_texel`
/// in `simulation/whitewater/whitewater.wgsl`.
pub fn texel_of(grid: &RippleGrid, window: &RippleWindow, x: f64, z: f64) -> Option<usize> {
    let n = grid.cells as i64;
    let mut t = [0usize; 2];
    for (a, v) in [x, z].into_iter().enumerate() {
        let c = (v / grid.cell_size).floor();
        if !c.is_finite() {
            return None;
        }
        let d = c as i64 - window.origin[a];
        if !(0..n).contains(&d) {
            return None;
        }
        t[a] = match grid.boundary {
            RippleBoundary::Walls => d as usize,
            RippleBoundary::Open | RippleBoundary::Periodic => (c as i64).rem_euclid(n) as usize,
        };
    }
    Some(t[1] * grid.cells + t[0])
}

/// Per-step damping factor of the sponge at domain cell `d` (1 inside;
/// falling to 0 at the outermost cell). Twin of `sponge` in WGSL.
pub fn sponge(grid: &RippleGrid, d: [usize; 2], dt: f64) -> f64 {
    let w = grid.sponge_cells();
    if w == 0 {
        return 1.0;
    }
    let n = grid.cells;
    let edge = d.iter().map(|&i| i.min(n - 1 - i)).min().unwrap();
    if edge >= w {
        return 1.0;
    }
    if edge == 0 {
        return 0.0;
    }
    let x = (w - edge) as f64 / w as f64;
    (-sponge_rate(grid) * x * x * dt).exp()
}

/// Peak damping rate (1/s) of the sponge, reached at its outer edge: a
/// quadratic ramp up to six times the angular frequency of the longest
/// wave the sponge is as wide as.
pub fn sponge_rate(grid: &RippleGrid) -> f64 {
    let width = grid.sponge_cells() as f64 * grid.cell_size;
    6.0 * (GRAVITY * 2.0 * PI / width.max(1e-9)).sqrt()
}

/// Blend weight of depth level 1 at depth `d` (level 0 at 0, level 1 at
/// 1): linear in √d, so that waves long enough to feel the floor (speed
/// √(g·d)) take their own speed. Twin of `depth_weight` in WGSL.
pub fn depth_weight(depths: [f64; 2], d: f64) -> f64 {
    let [a, b] = depths.map(f64::sqrt);
    if b > a { ((d.max(0.0).sqrt() - a) / (b - a)).clamp(0.0, 1.0) } else { 0.0 }
}

/// The CPU simulation. State on the FFT grid, row = z, col = x.
pub struct RippleSim {
    pub settings: RippleSettings,
    pub window: RippleWindow,
    /// Height (m) and potential (m²/s) per FFT grid cell.
    pub h: Vec<f64>,
    pub phi: Vec<f64>,
    /// Depth (m) per domain cell, row = z.
    pub depth: Vec<f64>,
    /// Landing spray since the last step, per texel ([`texel_of`]): the
    /// sum of the parcels' downward speeds in fixed point
    /// (`whitewater::KICK_SCALE` per m/s), as the GPU's atomics hold it.
    pub kicks: Vec<u32>,
    /// Δφ (m²/s) one kick unit gives its cell: the spray parcel's water
    /// over the cell's area, per unit
    /// ([`crate::coupling::kick_per_unit`]; 0: spray does not ring the water).
    pub kick_per_unit: f64,
    /// Water that liquid landings added since the last step (fixed point,
    /// [`PUSHED_UNITS_PER_M`] per metre of height summed over the FFT grid,
    /// like the hulls' `pushed`): it joins the level at the next step.
    pub landed: i64,
    planner: FftPlanner<f64>,
    pub steps: u64,
}

impl RippleSim {
    pub fn new(settings: RippleSettings, window: RippleWindow) -> Self {
        let f = settings.grid.fft_size();
        let n = settings.grid.cells;
        RippleSim {
            settings,
            window,
            h: vec![0.0; f * f],
            phi: vec![0.0; f * f],
            depth: vec![settings.depths[0]; n * n],
            kicks: vec![0; n * n],
            kick_per_unit: 0.0,
            landed: 0,
            planner: FftPlanner::new(),
            steps: 0,
        }
    }

    fn f(&self) -> usize {
        self.settings.grid.fft_size()
    }

    /// The height of domain cell (i, j) (i along x).
    pub fn height(&self, i: usize, j: usize) -> f64 {
        let g = grid_cell(&self.settings.grid, &self.window, [i, j]);
        self.h[g[1] * self.f() + g[0]]
    }

    /// The surface potential φ (m²/s) of domain cell (i, j).
    pub fn potential(&self, i: usize, j: usize) -> f64 {
        let g = grid_cell(&self.settings.grid, &self.window, [i, j]);
        self.phi[g[1] * self.f() + g[0]]
    }

    /// Heights over the domain, row = z, col = x.
    pub fn heights(&self) -> Vec<f64> {
        let n = self.settings.grid.cells;
        (0..n * n).map(|c| self.height(c % n, c / n)).collect()
    }

    /// Volume above the mean level over the domain (m³).
    pub fn volume(&self) -> f64 {
        let a = self.settings.grid.cell_size.powi(2);
        self.heights().iter().sum::<f64>() * a
    }

    /// Set the state of every grid cell from its domain cell's world position.
    pub fn set(&mut self, state: impl Fn(f64, f64) -> (f64, f64)) {
        let f = self.f();
        for q in 0..f {
            for p in 0..f {
                let (_, w) = domain_cell(&self.settings.grid, &self.window, [p, q]);
                let (h, phi) = state(w[0], w[1]);
                self.h[q * f + p] = h;
                self.phi[q * f + p] = phi;
            }
        }
    }

    /// A spray parcel landing at world (x, z) at `speed` m/s downwards: its
    /// momentum kicks the water at the next step (twin of `kick` in
    /// `whitewater.wgsl`). Outside the domain it is lost.
    pub fn land(&mut self, x: f32, z: f32, speed: f32) {
        if let Some(t) = texel_of(&self.settings.grid, &self.window, x as f64, z as f64) {
            self.kicks[t] = self.kicks[t].wrapping_add(crate::coupling::kick_units(speed));
        }
    }

    /// Liquid landing at world (x, z): `volume` m³ falling at `down_speed`
    /// m/s becomes this water (issue #29; `fluid::Landing`). Its momentum
    /// ρ·V·v is an impulsive pressure, Δφ = −V·v/A (as for spray,
    /// [`crate::coupling::kick_per_unit`]), spread over the plume it drives
    /// down ([`crate::coupling::plunge_weight`]: a jet's steady thrust on one
    /// cell would hold a pit metres deep in these linear waves), in kick units of this
    /// water's `kick_per_unit` (0: it rings nothing); its volume joins the
    /// level between walls at the next step (open water hands it to the sea
    /// around, as it does the hulls'). The horizontal momentum is lost: the
    /// surface water is a potential flow of its heights. Outside the domain
    /// it is lost. Twin of `land_liquid` in `simulation/ripples/ripples.wgsl`.
    pub fn land_liquid(&mut self, x: f64, z: f64, down_speed: f64, volume: f64) {
        use crate::coupling::{PLUME_DEPTH_PER_SPEED, PLUNGE_SPREAD_CELLS, plunge_weight};
        if texel_of(&self.settings.grid, &self.window, x, z).is_none() {
            return;
        }
        let grid = self.settings.grid;
        let cell = grid.cell_size;
        let area = cell * cell;
        if self.kick_per_unit > 0.0 {
            let speed = if down_speed.is_finite() { down_speed.clamp(0.0, 60.0) } else { 0.0 };
            let units = volume * speed / area / self.kick_per_unit;
            // Over the plume's width: the cells whose centres it covers, in
            // the domain (their weights normalised there, so walls keep the
            // whole impulse).
            let radius = (PLUME_DEPTH_PER_SPEED as f64 * speed).max(cell);
            let reach = ((radius / cell).ceil() as i64).min(PLUNGE_SPREAD_CELLS);
            let (ci, cj) = ((x / cell).floor(), (z / cell).floor());
            let mut taps = Vec::new();
            let mut sum = 0.0;
            for dj in -reach..=reach {
                for di in -reach..=reach {
                    let cx = (ci + di as f64 + 0.5) * cell;
                    let cz = (cj + dj as f64 + 0.5) * cell;
                    let w = plunge_weight((cx - x).powi(2) + (cz - z).powi(2), radius);
                    if let Some(t) = texel_of(&grid, &self.window, cx, cz).filter(|_| w > 0.0) {
                        taps.push((t, w));
                        sum += w;
                    }
                }
            }
            for (t, w) in taps {
                self.kicks[t] = self.kicks[t].wrapping_add((units * w / sum).round() as u32);
            }
        }
        // Every image of the cell in the FFT grid holds the level's rise.
        let images = (grid.fft_size() / grid.cells).pow(2) as f64;
        self.landed += (volume / area * images * PUSHED_UNITS_PER_M).round() as i64;
    }

    /// One step: the disturbances first (drops, the sponge), then the
    /// exact rotation of every wave.
    pub fn step(&mut self, drops: &[Drop]) {
        self.step_with(drops, &[]);
    }

    /// A step with bodies moving through the water.
    pub fn step_with(&mut self, drops: &[Drop], bodies: &[BodyMove]) {
        let (grid, dt) = (self.settings.grid, self.settings.dt);
        let f = self.f();
        let before = self.h.clone();
        let phi_before = self.phi.clone();
        // How deep hulls hold the water down in each cell (0 where none
        // pierces the surface). Twin of `hull_depth` in ripples.wgsl.
        let held_down: Vec<f64> = (0..f * f)
            .map(|i| {
                let (_, w) = domain_cell(&grid, &self.window, [i % f, i / f]);
                bodies.iter().map(|b| b.depth(w[0], w[1])).sum()
            })
            .collect();
        let covered: Vec<bool> = held_down.iter().map(|&d| d > 0.0).collect();
        // Cells of the bed with no water (obstacles, land), per grid cell.
        let n = grid.cells;
        let dry: Vec<bool> = (0..f * f)
            .map(|i| {
                let (d, _) = domain_cell(&grid, &self.window, [i % f, i / f]);
                !wet(self.depth[d[1] * n + d[0]])
            })
            .collect();
        // A hull presses with the head of its bottom below the free water
        // around it, not below the mean level: in a walled pool the hulls'
        // hollows raise the free water, and a head short by that rise let
        // the water flow into the hollow for as long as a body floated
        // (the contact pushing it back out each step), a current that
        // stored itself in φ and rose as a mound where a floating ball was
        // lifted out. Twin of `free_level` in ripples.wgsl.
        let free_level = if bodies.is_empty() {
            0.0
        } else {
            let not_free: Vec<bool> = covered.iter().zip(&dry).map(|(&c, &d)| c || d).collect();
            free_level(&grid, &before, &not_free)
        };
        // A hull holds its hollow down: free water does not pour into it by
        // breaking (else the two fight every step, and the ring about a
        // floating ball stands steep), though a hollow rebounding above
        // the water around still breaks (no spout through the ball), and
        // so does water pushed below the hull's bottom: a plunging ball's
        // pressure head, a spring, would carry it on (it once dug a hollow
        // 1.9 m deep, below the pool's floor, that spouted over the deck),
        // where the contact holds it. Each pair decides alike from both
        // sides, so the volume is kept.
        let holds = |c: usize| before[c] >= -held_down[c] - HULL_GAP;
        let at = |i: usize, p: usize, q: usize| {
            let j = (q % f) * f + p % f;
            // A dry neighbour is a wall: no water to trade with.
            if dry[j] {
                return before[i];
            }
            let held = covered[i] != covered[j]
                && (if covered[j] {
                    before[j] < before[i] && holds(j)
                } else {
                    before[i] < before[j] && holds(i)
                });
            if held { before[i] } else { before[j] }
        };
        for q in 0..f {
            for p in 0..f {
                let (d, w) = domain_cell(&grid, &self.window, [p, q]);
                let i = q * f + p;
                let h = before[i];
                let neighbours =
                    [at(i, p + 1, q), at(i, p + f - 1, q), at(i, p, q + 1), at(i, p, q + f - 1)];
                self.h[i] -= breaking(h, neighbours, grid.cell_size);
                // ∂φ/∂t = −g·(h + d): the bodies' pressure heads, one step's
                // worth, where the water touches the hulls (water that fell
                // away below a hull's bottom feels no push from it).
                if holds(i) && covered[i] {
                    self.phi[i] -= GRAVITY * (held_down[i] + free_level) * dt;
                }
                for drop in drops {
                    self.h[i] += drop_height(&grid, &self.window, drop, w);
                }
                // Landing spray: an impulsive pressure P changes φ by −P/ρ
                // (linearised Bernoulli); P·A = the parcels' momentum.
                let t = grid_cell(&grid, &self.window, d);
                self.phi[i] -= self.kicks[t[1] * grid.cells + t[0]] as f64 * self.kick_per_unit;
                // Dry cells (obstacles, land) hold no water: what the step
                // moved into them is taken out, so waves reflect from them.
                let s = if wet(self.depth[d[1] * grid.cells + d[0]]) {
                    sponge(&grid, d, dt)
                } else {
                    0.0
                };
                self.h[i] *= s;
                self.phi[i] *= s;
            }
        }
        self.kicks.iter_mut().for_each(|k| *k = 0);
        // Contact. Water never stands inside a hull: where it rose past a
        // hull's bottom (a plunging hull outruns the water its pressure head
        // pushes; the water's rebound meets a hull at rest) the hull puts it
        // back at its bottom. And water touching a hull follows it up: where
        // a hull rose or moved on, or was lifted out, the hollow it held
        // closes at once, up to the hull's new bottom or the mean level. What the hulls push out or let in comes from the
        // level (walls) or the sea around (open water). Without the contact
        // the pressure head acted as a spring: a ball dropped into the pool
        // dug a hollow below the floor whose rebound spouted through the
        // ball and over the deck, and the hollow a dragged ball left behind
        // sprang up as high as it was deep. Summed in fixed point, so that
        // the sum is the same in any order. Twin of the contact in
        // ripples.wgsl's `disturb`.
        let mut pushed: i64 = std::mem::take(&mut self.landed);
        for i in 0..f * f {
            let (_, w) = domain_cell(&grid, &self.window, [i % f, i / f]);
            let was: f64 = bodies.iter().map(|b| b.depth_before(w[0], w[1])).sum();
            let rise = -held_down[i] - self.h[i];
            if was > held_down[i] && before[i] >= -was - HULL_GAP && rise > 0.0 {
                let units = (rise * PUSHED_UNITS_PER_M).round();
                self.h[i] += units / PUSHED_UNITS_PER_M;
                pushed -= units as i64;
            }
            let excess = self.h[i] + held_down[i];
            if covered[i] && excess > 0.0 {
                let units = (excess * PUSHED_UNITS_PER_M).round();
                self.h[i] -= units / PUSHED_UNITS_PER_M;
                pushed += units as i64;
            }
            if let Some(j) = released_source(&grid, &self.window, bodies, w) {
                self.phi[i] = phi_before[j];
            }
        }
        let rise = match grid.boundary {
            RippleBoundary::Open => 0.0,
            _ => pushed as f64 / PUSHED_UNITS_PER_M / (f * f) as f64,
        };
        let mut z: Vec<Complex64> =
            self.h.iter().zip(&self.phi).map(|(&h, &p)| Complex64::new(h + rise, p)).collect();
        fft2(&mut self.planner, &mut z, f, false);
        let norm = 1.0 / (f * f) as f64;
        let mut levels = [vec![Complex64::default(); f * f], vec![Complex64::default(); f * f]];
        for q in 0..f {
            for p in 0..f {
                let i = q * f + p;
                let m = ((f - q) % f) * f + (f - p) % f;
                let (zk, zm) = (z[i], z[m].conj());
                let hk = (zk + zm) * 0.5;
                let pk = (zk - zm) * Complex64::new(0.0, -0.5);
                let (kx, kz) = grid.wave_vector(p, q);
                let k = (kx * kx + kz * kz).sqrt();
                // Open water has no level of its own: what a window gains or
                // loses flows away to the ocean around it.
                if k == 0.0 && grid.boundary == RippleBoundary::Open {
                    continue;
                }
                for (l, out) in levels.iter_mut().enumerate() {
                    let [e, c, sh, sp] = rotation(&self.settings, k, self.settings.depths[l]);
                    let h1 = (hk * c + pk * sh) * e;
                    let p1 = (pk * c - hk * sp) * e;
                    out[i] = (h1 + p1 * Complex64::new(0.0, 1.0)) * norm;
                }
            }
        }
        for l in levels.iter_mut() {
            fft2(&mut self.planner, l, f, true);
        }
        for q in 0..f {
            for p in 0..f {
                let (d, _) = domain_cell(&grid, &self.window, [p, q]);
                let n = grid.cells;
                let depth = self.depth[d[1] * n + d[0]];
                let wgt = depth_weight(self.settings.depths, depth);
                let i = q * f + p;
                let v = if wet(depth) {
                    levels[0][i] * (1.0 - wgt) + levels[1][i] * wgt
                } else {
                    Complex64::default()
                };
                self.h[i] = v.re;
                self.phi[i] = v.im;
            }
        }
        self.steps += 1;
    }

    /// Wave energy per unit density over the grid (J·m³/kg... i.e. ½Σ(B|ĥ|² + K|φ̂|²)),
    /// at depth level 0.
    pub fn energy(&mut self) -> f64 {
        let f = self.f();
        let grid = self.settings.grid;
        let mut hz: Vec<Complex64> = self.h.iter().map(|&h| Complex64::new(h, 0.0)).collect();
        let mut pz: Vec<Complex64> = self.phi.iter().map(|&p| Complex64::new(p, 0.0)).collect();
        fft2(&mut self.planner, &mut hz, f, false);
        fft2(&mut self.planner, &mut pz, f, false);
        let mut e = 0.0;
        for q in 0..f {
            for p in 0..f {
                let (kx, kz) = grid.wave_vector(p, q);
                let k = (kx * kx + kz * kz).sqrt();
                if k == 0.0 {
                    continue;
                }
                let kk = k * (k * self.settings.depths[0]).tanh();
                let bb = GRAVITY + self.settings.tension * k * k;
                let i = q * f + p;
                e += 0.5 * (bb * hz[i].norm_sqr() + kk * pz[i].norm_sqr());
            }
        }
        e * grid.cell_size.powi(2) / (f * f) as f64
    }
}

/// 2-D FFT in place; `inverse` is unnormalised e^(+i).
fn fft2(planner: &mut FftPlanner<f64>, data: &mut [Complex64], n: usize, inverse: bool) {
    let fft = if inverse { planner.plan_fft_inverse(n) } else { planner.plan_fft_forward(n) };
    super::fft2(&*fft, data, n);
}

#[cfg(test)]
mod tests;

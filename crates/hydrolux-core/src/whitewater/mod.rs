//! White water: foam that lives on the surface, bubbles under it and spray
//! over it (seed 003 §4.4 foam, §4.5 bubbles after Thürey et al. 2007,
//! §4.6 splashes, §2.3 particle systems). The CPU twin of
//! `simulation/whitewater` in the renderer: the same formulas in the same f32
//! arithmetic and order, so the GPU's fields and particles can be compared
//! with these.
//!
//! - **Foam** is an amount F per cell of a world-anchored square window
//!   (`FoamGrid`). Each step it is carried by the surface drift
//!   (semi-Lagrangian, bilinear), decays as e^(−dt/τ) with Monahan's
//!   lifetimes (τ = 3.85 s in sea water, 2.54 s in fresh water), and gains
//!   what the sources put in: folding crests (Jacobian below a threshold
//!   calibrated so that the whitecap cover follows Monahan &
//!   O'Muircheartaigh's W = 3.84·10⁻⁶·U^3.41), steep interactive ripples,
//!   splashes, bubbles bursting and spray landing. A cell shows as
//!   whitecap where its cover 1 − e^(−F) passes ½.
//! - **Bubbles** rise at their terminal velocity (Stokes' law for small
//!   bubbles, Mendelson's wave analogy for large ones, joined harmonically),
//!   merge when they touch (volume kept exactly, in fixed point), and burst
//!   into foam at the surface.
//! - **Spray** drops fly ballistically with quadratic air drag and land in
//!   the foam.

pub use crate::coupling::{
    KICK_SCALE, PLUME_DEPTH_PER_SPEED, SPRAY_LIQUID_FRACTION, kick_per_unit, kick_units,
    spray_parcel_volume,
};
use crate::waves::SurfaceSample;
use bytemuck::{Pod, Zeroable};

/// Foam lifetime (e-folding, s) in sea water (Monahan 1971).
pub const FOAM_LIFE_SEA_S: f64 = 3.85;
/// Foam lifetime (s) in fresh water (Monahan 1971).
pub const FOAM_LIFE_FRESH_S: f64 = 2.54;
/// Salinity of the open sea (PSU).
pub const SEA_SALINITY: f64 = 35.0;
/// Gravity (m/s²).
pub const G: f32 = 9.81;
/// Kinematic viscosity of water (m²/s).
pub const WATER_NU: f32 = 1.0e-6;
/// Surface tension over density of water (m³/s²).
pub const WATER_SIGMA_RHO: f32 = 7.2e-5;
/// Air over water density.
pub const AIR_WATER_RATIO: f32 = 1.2 / 1000.0;
/// Drag coefficient of a small sphere in air.
pub const DROP_DRAG: f32 = 0.47;
/// Radius (m) of a spray drop, for its drag (splash drops are millimetres).
pub const SPRAY_DROP_RADIUS: f32 = 1.5e-3;
/// Bubble volumes are kept in units of this (m³): merges add integers.
pub const VOLUME_UNIT_M3: f64 = 1.0e-12;
/// Foam a fully covered cell holds: cover = 1 − e^(−F); whitecap where F > ln 2.
pub const WHITECAP_FOAM: f32 = std::f32::consts::LN_2;

/// Particle kinds.
pub const DEAD: u32 = 0;
pub const BUBBLE: u32 = 1;
pub const SPRAY: u32 = 2;
/// Foam on the volumetric liquid's surface (`fluid::white_water`).
pub const FOAM: u32 = 3;

/// Foam's e-folding lifetime (s) at `salinity` (PSU): Monahan's fresh- and
/// sea-water values, linear between (and held beyond sea water).
pub fn foam_life(salinity: f64) -> f64 {
    let s = (salinity / SEA_SALINITY).clamp(0.0, 1.0);
    FOAM_LIFE_FRESH_S + (FOAM_LIFE_SEA_S - FOAM_LIFE_FRESH_S) * s
}

/// Monahan & O'Muircheartaigh (1980): fraction of the sea covered by
/// whitecaps at 10 m wind speed `u10` (m/s).
pub fn monahan_whitecap_fraction(u10: f64) -> f64 {
    3.84e-6 * u10.max(0.0).powf(3.41)
}

/// Foam's diffuse albedo (sea foam: 0.4–0.8, fresh to dense; Whitlock,
/// Bartlett & Gurganus 1982): as bright as the water shader draws it.
pub const FOAM_ALBEDO: f32 = 0.8;

/// The bubble cloud a breaker drives under its whitecap scatters back this
/// fraction of the light that reaches it where it is dense: bubble clouds
/// of void fraction ~1% over some tens of centimetres have a
/// backscattering optical depth of order one (Stramski & Tegowski 2001;
/// Terrill, Melville & Stramski 2001), and their scattering is strongly
/// forward, so about a third comes back up.
pub const BUBBLE_CLOUD_REFLECTANCE: f32 = 0.3;
/// The mean depth (m) from which the cloud's light comes back up (the
/// plume's top half-metre, Deane & Stokes 2002).
pub const BUBBLE_CLOUD_DEPTH: f32 = 0.3;

/// The light (radiance, per channel) that a bubble cloud of `cloud` (0–1)
/// sends up to just under the surface, for downwelling irradiance
/// `e_water` under the surface and the water's absorption `absorption`
/// (1/m): Lambertian, after the way down and up through
/// [`BUBBLE_CLOUD_DEPTH`] of water. As `bubble_cloud_radiance` in WGSL.
pub fn bubble_cloud_radiance(cloud: f32, e_water: [f32; 3], absorption: [f32; 3]) -> [f32; 3] {
    std::array::from_fn(|k| {
        cloud * BUBBLE_CLOUD_REFLECTANCE * e_water[k] / std::f32::consts::PI
            * (-2.0 * BUBBLE_CLOUD_DEPTH * absorption[k]).exp()
    })
}

/// The fraction of sunlight that a foam cover (0–1, the shading's
/// `foam_cover`) lets into the water: what it does not scatter back (foam
/// absorbs next to nothing), so caustics and god rays darken beneath it.
pub fn foam_transmittance(cover: f32) -> f32 {
    1.0 - FOAM_ALBEDO * cover
}

/// Foam's cover (0–1) of a cell holding F: about ½ at the whitecap
/// threshold F = ln 2 ([`WHITECAP_FOAM`]), a dense sheet from 1.3; as
/// `foam_cover` in WGSL.
pub fn foam_cover(f: f32) -> f32 {
    let t = ((f - 0.15) / (1.3 - 0.15)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The most foam a cell holds (F): a dense, freshly whipped sheet. What
/// lands on a full cell runs off; a cap makes a whitecap fade in
/// τ·ln(F_max/ln 2) ≈ 1.1·τ once its breaking stops, as Monahan's stage-B
/// whitecaps do, however long it broke or however much spray fell on it.
pub const FOAM_MAX: f32 = 2.0;

/// Foam gained per second (F/s) by a cell that is fully breaking.
pub const FOLD_GAIN: f32 = 10.0;

/// Breaking is calibrated on stretches of simulated ocean spread over
/// minutes, each run as a loop: wave groups come and go, and a patch holds
/// few of them, so one short stretch can misjudge the cover by a factor of
/// two. Small oceans are cheap to evaluate and hold the fewest groups, so
/// they get more stretches: [`CALIBRATION_WINDOWS_K`]/√(FFT texels),
/// between 4 and 32 (4 for three 256² cascades, 8 for three 128² ones): a
/// fraction of a second at load.
pub const CALIBRATION_WINDOW_S: f64 = 6.0;
pub const CALIBRATION_SPACING_S: f64 = 37.7;
pub const CALIBRATION_DT: f32 = 0.25;
pub const CALIBRATION_CELLS: usize = 4_096;
pub const CALIBRATION_WINDOWS_K: f64 = 1800.0;

/// The Jacobians a foam grid's cells see of an ocean over a stretch of
/// time (a subset of cells when the grid is large), read as the GPU's foam
/// step reads them: prefiltered over the cell (waves shorter than a cell
/// do not break a cell's worth of sea, and unfiltered they flicker).
#[derive(Clone, Debug)]
pub struct JacobianSeries {
    pub cells: usize,
    /// Separate stretches of time, of equal length, one after the other.
    pub windows: usize,
    pub dt: f32,
    /// Time-major: `values[step * cells + cell]`.
    pub values: Vec<f32>,
}

impl JacobianSeries {
    pub fn of_ocean(spectrum: &crate::waves::ocean::OceanSpectrum, grid: &FoamGrid) -> Self {
        use crate::waves::ocean::OceanFields;
        let n = (grid.cells * grid.cells) as usize;
        let stride = n.div_ceil(CALIBRATION_CELLS).max(1);
        let at: Vec<(f64, f64)> = (0..n)
            .step_by(stride)
            .map(|k| {
                let [i, j] = grid.world_cell(k);
                (((i as f32 + 0.5) * grid.cell) as f64, ((j as f32 + 0.5) * grid.cell) as f64)
            })
            .collect();
        let steps = (CALIBRATION_WINDOW_S / CALIBRATION_DT as f64).round() as usize;
        let texels = spectrum.modes.len().max(1) as f64;
        let windows = ((CALIBRATION_WINDOWS_K / texels.sqrt()).round() as usize).clamp(4, 32);
        let times: Vec<f64> = (0..windows)
            .flat_map(|w| {
                let t0 = w as f64 * CALIBRATION_SPACING_S;
                (0..steps).map(move |i| t0 + i as f64 * CALIBRATION_DT as f64)
            })
            .collect();
        let row = |ts: &[f64]| {
            let mut out = Vec::with_capacity(ts.len() * at.len());
            for &t in ts {
                let mips = OceanFields::evaluate_jacobian(spectrum, t).mips_of(5..8);
                out.extend(
                    at.iter()
                        .map(|&(x, z)| jacobian(&mips.sample_footprint(x, z, grid.cell as f64))),
                );
            }
            out
        };
        // The evaluations are independent: spread them over the cores, where
        // there are threads (not on the web: wasm32 has none, and spawning
        // one panics there).
        let threads = if cfg!(target_arch = "wasm32") {
            1
        } else {
            std::thread::available_parallelism().map_or(1, |n| n.get()).min(times.len())
        };
        let rows: Vec<Vec<f32>> = if threads <= 1 {
            vec![row(&times)]
        } else {
            let chunk = times.len().div_ceil(threads);
            std::thread::scope(|scope| {
                let workers: Vec<_> =
                    times.chunks(chunk).map(|ts| scope.spawn(move || row(ts))).collect();
                workers.into_iter().map(|w| w.join().expect("calibration worker")).collect()
            })
        };
        JacobianSeries { cells: at.len(), windows, dt: CALIBRATION_DT, values: rows.concat() }
    }

    /// The whitecap cover (fraction of cells with F > ln 2) that the foam
    /// model gives on this series with breaking threshold `threshold` and
    /// foam lifetime `life`: every cell's foam decays, gains
    /// [`FOLD_GAIN`]·[`fold_source`] and is capped as in
    /// [`FoamField::step`]; each window is run twice, as a loop (the first
    /// pass brings its foam to a steady state), and the second passes are
    /// averaged.
    pub fn whitecap_cover(&self, threshold: f32, life: f32) -> f64 {
        let keep = (-self.dt / life).exp();
        let mut covered = 0usize;
        let cells = self.cells.max(1);
        let window = self.values.len() / self.windows.max(1);
        for values in self.values.chunks_exact(window.max(1)) {
            let mut foam = vec![0.0f32; self.cells];
            for pass in 0..2 {
                for row in values.chunks_exact(cells) {
                    for (f, &j) in foam.iter_mut().zip(row) {
                        let source = FOLD_GAIN * fold_source(j, threshold);
                        *f = (*f * keep + source * self.dt).min(FOAM_MAX);
                        if pass == 1 && *f > WHITECAP_FOAM {
                            covered += 1;
                        }
                    }
                }
            }
        }
        covered as f64 / self.values.len().max(1) as f64
    }
}

/// The Jacobian threshold J₀ at which the foam model run on `series`
/// covers the sea with whitecaps as Monahan & O'Muircheartaigh's fit says
/// for wind `u10` (by bisection: cover grows with J₀). Calibrated with sea
/// water's foam lifetime, as their data are: breaking belongs to the
/// waves, so fresh water, whose foam dies sooner, shows less cover.
pub fn calibrated_fold_threshold(series: &JacobianSeries, u10: f64) -> f32 {
    let target = monahan_whitecap_fraction(u10).min(0.5);
    let life = FOAM_LIFE_SEA_S as f32;
    let low = series.values.iter().copied().fold(f32::INFINITY, f32::min);
    if !low.is_finite() {
        return 0.0;
    }
    let (mut lo, mut hi) = (low, 2.0f32);
    for _ in 0..24 {
        let mid = 0.5 * (lo + hi);
        if series.whitecap_cover(mid, life) < target { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}

/// Jacobian span over which breaking turns on below J₀ (soft edges).
pub const FOLD_RAMP: f32 = 0.1;

/// Breaking-source strength (0–1) of a sample with Jacobian `jacobian`:
/// off above J₀, fully on [`FOLD_RAMP`] below it.
pub fn fold_source(jacobian: f32, threshold: f32) -> f32 {
    ((threshold - jacobian) / FOLD_RAMP).clamp(0.0, 1.0)
}

/// The Jacobian of a surface sample (as `surface_jacobian` in WGSL).
pub fn jacobian(s: &SurfaceSample) -> f32 {
    (1.0 + s.dxx) * (1.0 + s.dzz) - s.dxz * s.dxz
}

/// How mobile a bubble's surface is in water of `salinity` (PSU): 1 in
/// clean fresh water, whose bubbles' surfaces slip (their inner air
/// circulates), 0 in sea water, whose surfactants stiffen them into rigid
/// spheres (Clift, Grace & Weber 1978 ch. 7; Thorpe 1982 for the sea);
/// linear between, as the foam's lifetime.
pub fn bubble_mobility(salinity: f64) -> f32 {
    (1.0 - salinity / SEA_SALINITY).clamp(0.0, 1.0) as f32
}

/// Fixed-point steps of the drag balance (each halves the error at low
/// Reynolds numbers, better above).
pub const RISE_STEPS: u32 = 24;

/// Speed (m/s) at which a sphere of radius `r` rising through water has
/// drag equal to buoyancy: v²·C_D(Re) = 8/3·g·r with Re = 2rv/ν, by
/// fixed-point steps from Stokes' speed. `clean`: Mei, Klausner &
/// Lawrence's (1994) drag on a bubble with a mobile surface, C_D =
/// 16/Re·(1 + 1/(8/Re + ½(1 + 3.315/√Re))) (Hadamard–Rybczynski's 16/Re
/// when creeping, Levich's 48/Re when fast); else Schiller & Naumann's on
/// a rigid sphere, C_D = 24/Re·(1 + 0.15·Re^0.687).
fn drag_balance_velocity(r: f32, clean: bool) -> f32 {
    let weight = 8.0 / 3.0 * G * r;
    let mut v = (2.0 * G * r * r / (9.0 * WATER_NU)).min(1.0);
    for _ in 0..RISE_STEPS {
        let re = (2.0 * r * v / WATER_NU).max(1e-6);
        let cd = if clean {
            16.0 / re * (1.0 + 1.0 / (8.0 / re + 0.5 * (1.0 + 3.315 / re.sqrt())))
        } else {
            24.0 / re * (1.0 + 0.15 * re.powf(0.687))
        };
        v = (weight / cd).sqrt();
    }
    v
}

/// Terminal rise speed (m/s) of an air bubble of radius `r` (m) in water
/// whose bubbles have surface mobility `mobility` ([`bubble_mobility`]):
/// the drag balance of a rigid sphere (sea water) or a clean bubble (fresh
/// water), blended by the mobility, capped by Mendelson's (1967) wave
/// analogy v = √(2.14·σ/(ρ·d) + 0.505·g·d), which large, wobbling bubbles
/// follow in either water. A 1 mm bubble rises at 0.11 m/s in sea water
/// and 0.31 m/s in clean fresh water, as measured (Clift, Grace & Weber
/// 1978 Fig. 7.3; Duineveld 1995).
pub fn bubble_terminal_velocity(r: f32, mobility: f32) -> f32 {
    let r = r.max(1e-6);
    let rigid = drag_balance_velocity(r, false);
    let clean = drag_balance_velocity(r, true);
    let viscous = rigid + (clean - rigid) * mobility;
    let d = 2.0 * r;
    let mendelson = (2.14 * WATER_SIGMA_RHO / d + 0.505 * G * d).sqrt();
    viscous.min(mendelson)
}

/// Time constant (s) over which a bubble reaches its terminal velocity:
/// buoyancy over the added mass (half the displaced water) accelerates it
/// at 2g from rest.
pub fn bubble_relaxation(r: f32, mobility: f32) -> f32 {
    (bubble_terminal_velocity(r, mobility) / (2.0 * G)).max(1e-4)
}

/// Quadratic drag constant k (1/m) of a water drop of radius `r` in air:
/// a = −k·|v|·v with k = 3·ρa·Cd / (8·ρw·r).
pub fn drop_drag(r: f32) -> f32 {
    3.0 * AIR_WATER_RATIO * DROP_DRAG / (8.0 * r.max(1e-6))
}

/// Radius (m) of a bubble holding `volume` units of [`VOLUME_UNIT_M3`].
pub fn bubble_radius(volume: u32) -> f32 {
    ((3.0 * volume as f64 * VOLUME_UNIT_M3 / (4.0 * std::f64::consts::PI)).cbrt()) as f32
}

/// The volume units of a bubble of radius `r` (m), at least one.
pub fn bubble_volume(r: f32) -> u32 {
    let v = 4.0 / 3.0 * std::f64::consts::PI * (r as f64).powi(3) / VOLUME_UNIT_M3;
    v.round().clamp(1.0, u32::MAX as f64) as u32
}

/// Entrained bubble radius (m) for a uniform number `u` in [0, 1): the
/// size spectrum under breaking waves (Deane & Stokes 2002), N(r) ∝ r^(−3/2)
/// below the Hinze scale (1 mm) and r^(−10/3) above, from 0.1 to 5 mm,
/// sampled by inverting each piece's distribution.
pub fn sample_bubble_radius(u: f32) -> f32 {
    let (r0, rh, r1) = (1.0e-4f32, 1.0e-3f32, 5.0e-3f32);
    // Number in each piece (continuous at the Hinze scale).
    let (a, b) = (-1.5f32, -10.0 / 3.0f32);
    let piece = |e: f32, lo: f32, hi: f32| (hi.powf(e + 1.0) - lo.powf(e + 1.0)) / (e + 1.0);
    let n_small = piece(a, r0, rh);
    let scale = rh.powf(a - b);
    let n_large = scale * piece(b, rh, r1);
    let t = u.clamp(0.0, 0.999_999) * (n_small + n_large);
    if t < n_small {
        (r0.powf(a + 1.0) + t * (a + 1.0)).powf(1.0 / (a + 1.0))
    } else {
        let t = (t - n_small) / scale;
        (rh.powf(b + 1.0) + t * (b + 1.0)).powf(1.0 / (b + 1.0))
    }
}

/// A 32-bit integer hash (PCG output permutation), identical in WGSL
/// (`hash_u32` in the shared WGSL module `hash`).
pub fn hash_u32(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// A uniform number in [0, 1) from a step, an index and a salt.
pub fn random(step: u32, index: u32, salt: u32) -> f32 {
    let h = hash_u32(index ^ hash_u32(step.wrapping_mul(0x9E37_79B9) ^ hash_u32(salt)));
    (h >> 8) as f32 / 16_777_216.0
}

/// The foam's window: `cells`² cells of `cell` metres, anchored to the
/// world (cell (i, j) covers [i·cell, (i+1)·cell)), addressed modulo its
/// size so that it can follow the camera by moving `low` (the world cell
/// of its low corner).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoamGrid {
    pub cells: u32,
    pub cell: f32,
    pub low: [i32; 2],
    /// The window tiles the plane (an FFT ocean's patch: its sources are
    /// periodic), instead of ending at its edges.
    pub periodic: bool,
}

impl FoamGrid {
    /// A window of `cells` cells covering about `extent` metres, centred on
    /// world point `centre`.
    pub fn centred(cells: u32, extent: f32, centre: [f32; 2]) -> Self {
        let cell = extent / cells as f32;
        let low = centre.map(|c| (c / cell).floor() as i32 - cells as i32 / 2);
        FoamGrid { cells, cell, low, periodic: false }
    }

    /// A window that tiles the plane with period `extent` (m).
    pub fn periodic(cells: u32, extent: f32) -> Self {
        FoamGrid { cells, cell: extent / cells as f32, low: [0, 0], periodic: true }
    }

    /// The storage index of world cell (i, j) (toroidal).
    pub fn index(&self, i: i32, j: i32) -> usize {
        let n = self.cells as i32;
        (j.rem_euclid(n) * n + i.rem_euclid(n)) as usize
    }

    /// The world cell of storage index k within the current window.
    pub fn world_cell(&self, k: usize) -> [i32; 2] {
        let n = self.cells as i32;
        let (si, sj) = ((k as i32) % n, (k as i32) / n);
        let w = |s: i32, lo: i32| lo + (s - lo).rem_euclid(n);
        [w(si, self.low[0]), w(sj, self.low[1])]
    }

    /// Whether world cell (i, j) is inside the window.
    pub fn contains(&self, i: i32, j: i32) -> bool {
        let n = self.cells as i32;
        self.periodic
            || (self.low[0]..self.low[0] + n).contains(&i)
                && (self.low[1]..self.low[1] + n).contains(&j)
    }
}

/// The foam's state and its step (twin of `foam_step` in `foam.wgsl`).
#[derive(Clone, Debug)]
pub struct FoamField {
    pub grid: FoamGrid,
    pub amount: Vec<f32>,
    /// Foam left by particles since the last step, per cell, in
    /// 1/[`DEPOSIT_SCALE`] of F (integers, as the GPU adds them atomically).
    pub deposits: Vec<u32>,
}

/// Fixed-point scale of foam deposits (F).
pub const DEPOSIT_SCALE: f32 = 65536.0;

/// What one foam step is given.
#[derive(Clone, Copy, Debug)]
pub struct FoamStep {
    pub dt: f32,
    /// Lifetime τ (s).
    pub life: f32,
    /// Horizontal drift of the surface (m/s): wind drift and Stokes drift.
    pub drift: [f32; 2],
}

impl FoamField {
    pub fn new(grid: FoamGrid) -> Self {
        let n = (grid.cells * grid.cells) as usize;
        FoamField { grid, amount: vec![0.0; n], deposits: vec![0; n] }
    }

    /// Leave `foam` (F·m²) in the cell holding world (x, z) for the next
    /// step, at most a full cell's ([`FOAM_MAX`]).
    pub fn deposit(&mut self, x: f32, z: f32, foam: f32) {
        let c = self.grid.cell;
        let (i, j) = ((x / c).floor() as i32, (z / c).floor() as i32);
        if self.grid.contains(i, j) {
            // One deposit fills its cell at most (more runs off): the sum
            // cannot wrap however many land in a cell in a step.
            let units = ((foam / (c * c)).min(FOAM_MAX) * DEPOSIT_SCALE).round() as u32;
            let k = self.grid.index(i, j);
            self.deposits[k] = self.deposits[k].wrapping_add(units);
        }
    }

    /// Foam at world cell (i, j): 0 outside the window.
    pub fn at(&self, i: i32, j: i32) -> f32 {
        if self.grid.contains(i, j) { self.amount[self.grid.index(i, j)] } else { 0.0 }
    }

    /// Bilinear foam at world point (x, z), cell centres at (i + ½)·cell.
    pub fn sample(&self, x: f32, z: f32) -> f32 {
        let c = self.grid.cell;
        let (u, v) = (x / c - 0.5, z / c - 0.5);
        let (i, j) = (u.floor(), v.floor());
        let (a, b) = (u - i, v - j);
        let (i, j) = (i as i32, j as i32);
        let top = self.at(i, j) * (1.0 - a) + self.at(i + 1, j) * a;
        let bottom = self.at(i, j + 1) * (1.0 - a) + self.at(i + 1, j + 1) * a;
        top * (1.0 - b) + bottom * b
    }

    /// Move the window to `grid` (same size): cells that leave it are
    /// forgotten, cells that enter start without foam.
    pub fn follow(&mut self, grid: FoamGrid) {
        let old = self.grid;
        if old == grid {
            return;
        }
        let mut next = FoamField::new(grid);
        for k in 0..next.amount.len() {
            let [i, j] = grid.world_cell(k);
            if old.contains(i, j) {
                next.amount[k] = self.amount[old.index(i, j)];
            }
        }
        *self = next;
    }

    /// One step: advect by the drift, decay, add `source(x, z)` (F per
    /// second at each cell centre) times dt, the splashes' foam and what
    /// was deposited.
    pub fn step(&mut self, s: &FoamStep, splashes: &[Splash], source: impl Fn(f32, f32) -> f32) {
        let c = self.grid.cell;
        let keep = (-s.dt / s.life).exp();
        let mut next = vec![0.0f32; self.amount.len()];
        for (k, out) in next.iter_mut().enumerate() {
            let [i, j] = self.grid.world_cell(k);
            let (x, z) = ((i as f32 + 0.5) * c, (j as f32 + 0.5) * c);
            let carried = self.sample(x - s.drift[0] * s.dt, z - s.drift[1] * s.dt);
            let mut rate = source(x, z);
            for sp in splashes {
                let (dx, dz) = (x - sp.position[0], z - sp.position[2]);
                let u = (dx * dx + dz * dz) / (sp.radius * sp.radius);
                rate += sp.foam * (1.0 - u).max(0.0) / s.dt;
            }
            let landed = self.deposits[k] as f32 / DEPOSIT_SCALE;
            *out = (carried * keep + rate * s.dt + landed).min(FOAM_MAX);
        }
        self.deposits.fill(0);
        self.amount = next;
    }

    /// Fraction of the window's cells showing as whitecap (F > ln 2, cover > ½).
    pub fn coverage(&self) -> f64 {
        let n = self.amount.iter().filter(|&&f| f > WHITECAP_FOAM).count();
        n as f64 / self.amount.len() as f64
    }
}

/// The top layer's wind drift as a fraction of the 10 m wind.
pub const WIND_DRIFT: f32 = 0.03;

/// Horizontal surface drift (m/s) under wind `u10` from `direction`
/// (unit, towards): the wind drift of the top layer, about 3% of the wind
/// (Wu 1975), which carries foam downwind.
pub fn surface_drift(u10: f32, direction: [f32; 2]) -> [f32; 2] {
    [WIND_DRIFT * u10 * direction[0], WIND_DRIFT * u10 * direction[1]]
}

/// One particle, laid out as `Particle` in `particle.wgsl` (64 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Particle {
    pub position: [f32; 3],
    /// Bubble or drop radius (m).
    pub radius: f32,
    pub velocity: [f32; 3],
    /// [`DEAD`], [`BUBBLE`] or [`SPRAY`].
    pub kind: u32,
    /// Unique per emission (step and source): merges and comparisons use it.
    pub id: u32,
    /// Seconds since birth.
    pub age: f32,
    /// Bubbles: air volume in [`VOLUME_UNIT_M3`] units.
    pub volume: u32,
    /// Bubbles: volume units merged into it this step (applied next update).
    pub gained: u32,
    /// Bubbles: where the surface above was displaced to (Dx, h, Dz) when
    /// last looked at, from here: the next step's water motion.
    pub carried: [f32; 3],
    pub _pad: u32,
}

/// The water as particles see it: its height over (x, z), and where the
/// surface point above (x, z) is displaced to (Dx, h, Dz), prefiltered over
/// `footprint` metres. A plain height function is water without horizontal
/// displacement (a heightfield, the interactive water).
pub trait WaterSurface {
    fn height(&self, x: f32, z: f32) -> f32;
    fn displacement(&self, x: f32, z: f32, footprint: f32) -> [f32; 3];
}

impl<F: Fn(f32, f32) -> f32> WaterSurface for F {
    fn height(&self, x: f32, z: f32) -> f32 {
        self(x, z)
    }
    fn displacement(&self, x: f32, z: f32, _footprint: f32) -> [f32; 3] {
        [0.0, self(x, z), 0.0]
    }
}

/// An FFT ocean as particles see it, read as the GPU reads its cascades:
/// the height under (x, z) after one fixed-point step back through the
/// choppy displacement (as `water_height` in WGSL), the displacement
/// prefiltered over the footprint.
impl WaterSurface for crate::waves::ocean::OceanMips {
    fn height(&self, x: f32, z: f32) -> f32 {
        let d = self.sample_footprint(x as f64, z as f64, 0.0).displacement;
        let back = self.sample_footprint((x - d[0]) as f64, (z - d[2]) as f64, 0.0);
        back.displacement[1]
    }
    fn displacement(&self, x: f32, z: f32, footprint: f32) -> [f32; 3] {
        self.sample_footprint(x as f64, z as f64, footprint as f64).displacement
    }
}

/// The water under waves moves as its surface does, less the deeper it
/// is (linear waves: e^(−kd)): a bubble d metres down follows the surface
/// prefiltered over this many times d, i.e. without the waves shorter than
/// about that, whose motion has faded to e^(−2π/4) ≈ 0.2 there.
pub const MOTION_FOOTPRINT_PER_DEPTH: f32 = 4.0;

/// A splash: particles born at a point (a body hitting or cutting the
/// water, a drop landing), laid out as `Splash` in `particles.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Splash {
    /// Where (m): on the surface.
    pub position: [f32; 3],
    /// Radius (m) of the disturbed patch.
    pub radius: f32,
    /// The water's (or the body's) velocity there (m/s).
    pub velocity: [f32; 3],
    /// Speed (m/s) that throws the spray.
    pub speed: f32,
    pub spray: u32,
    pub bubbles: u32,
    /// Foam (F) it leaves on the surface under it.
    pub foam: f32,
    /// Its first particle among the step's emissions (set on upload).
    pub first: u32,
}

/// The constants of one particle step (`ParticleStep` in `particles.wgsl`).
#[derive(Clone, Copy, Debug)]
pub struct ParticleStep {
    pub dt: f32,
    pub step: u32,
    /// Wind at the surface (m/s, xz), which drags spray.
    pub wind: [f32; 2],
    /// Floor depth (m, positive down): bubbles stay above it.
    pub floor_depth: f32,
    /// Lifetime caps (s) of spray and bubbles.
    pub max_age: f32,
    /// The domain: x and z from `low` to `high` (m); outside, particles die.
    pub low: [f32; 2],
    pub high: [f32; 2],
    /// Spray drop radius (m).
    pub drop_radius: f32,
    /// The bubbles' surface mobility ([`bubble_mobility`]).
    pub bubble_mobility: f32,
}

/// Particles a splash makes, identically on the GPU (`spawn_splash`):
/// spray thrown up and out at up to `speed`, bubbles just under the
/// surface. `local` numbers the particle within this step's spawns.
pub fn splash_particle(s: &Splash, k: u32, step: u32, id: u32, drop_radius: f32) -> Particle {
    let r1 = random(step, id, 1);
    let r2 = random(step, id, 2);
    let r3 = random(step, id, 3);
    let a = r1 * std::f32::consts::TAU;
    let d = s.radius * r2.sqrt();
    let (ca, sa) = (a.cos(), a.sin());
    let mut p = Particle {
        position: [s.position[0] + d * ca, s.position[1], s.position[2] + d * sa],
        id,
        ..Default::default()
    };
    if k < s.spray {
        let up = s.speed * (0.6 + 0.4 * r3);
        let out = s.speed * 0.5 * r2;
        p.kind = SPRAY;
        p.radius = drop_radius;
        p.position[1] += 0.01;
        p.velocity = [s.velocity[0] * 0.5 + out * ca, up, s.velocity[2] * 0.5 + out * sa];
    } else {
        p.kind = BUBBLE;
        let r = sample_bubble_radius(r3);
        p.volume = bubble_volume(r);
        p.radius = bubble_radius(p.volume);
        p.position[1] -= 0.02 + 0.3 * s.radius * r3;
        p.velocity = [s.velocity[0] * 0.3, 0.0, s.velocity[2] * 0.3];
    }
    p
}

/// Spray (and twice as many bubbles) per square metre of water a body
/// sweeps through at 2 m/s: one particle stands for a parcel of drops or
/// a cloud of bubbles. Grows as the speed squared (the splash's energy),
/// capped at four times.
pub const SPLASH_SPRAY_PER_M2: f32 = 500.0;
/// Most particles one splash makes.
pub const SPLASH_MAX: u32 = 1024;

/// The splash of a body moving through the water surface over one step
/// of `dt` s (seed 003 §4.6): its waterline sweeps an area 2R·|v|·dt,
/// throws spray at up to 0.7·|v| and entrains bubbles, and leaves foam
/// (a hull cutting through the water draws a wake of it). `None` when it
/// does not touch the surface (flat, y = 0) or moves slower than 0.3 m/s.
pub fn body_splash(m: &crate::coupling::BodyMove, dt: f64) -> Option<Splash> {
    let r = m.shape.bounding_radius() as f32;
    let (a, b) = (m.before.position.as_vec3(), m.after.position.as_vec3());
    let v = (b - a) / dt as f32;
    let speed = v.length();
    let touching = a.y.min(b.y) - r < 0.0 && a.y.max(b.y) + r > 0.0;
    if !touching || speed < 0.3 || !speed.is_finite() {
        return None;
    }
    let swept = 2.0 * r * speed * dt as f32;
    // Slow hulls cut the water cleanly; from about 4 m/s they throw it.
    let vigour = (speed / 4.0).powi(2).min(4.0);
    let spray = (SPLASH_SPRAY_PER_M2 * swept * vigour).round() as u32;
    Some(Splash {
        position: [b.x, 0.0, b.z],
        radius: 1.1 * r,
        velocity: v.to_array(),
        speed: 0.7 * speed,
        spray: spray.min(SPLASH_MAX / 3),
        bubbles: (2 * spray).min(2 * SPLASH_MAX / 3),
        foam: WAKE_FOAM_PER_M * speed.min(4.0) * dt as f32,
        first: 0,
    })
}

/// Foam (F) a moving body's splash leaves at its centre per metre it
/// travels: a cell it passes over gains about 0.25 per metre of hull above
/// it, i.e. a lacy wake rather than a white sheet behind a 5 m launch at
/// harbour speed (and the same whatever the step).
pub const WAKE_FOAM_PER_M: f32 = 0.25;

/// The splash of a drop (a crater `radius` wide and `strength` deep, as
/// the interactive water takes it): a crown thrown at about
/// 4·√(g·depth), bubbles, foam. Rain's small drops make none.
pub fn drop_splash(d: &crate::coupling::Drop) -> Option<Splash> {
    let (r, s) = (d.radius as f32, d.strength.abs() as f32);
    let swept = std::f32::consts::PI * r * r;
    let spray = (0.3 * SPLASH_SPRAY_PER_M2 * swept * (s / 0.05).min(4.0)).round() as u32;
    if spray == 0 || !(r.is_finite() && s.is_finite()) {
        return None;
    }
    Some(Splash {
        position: [d.x as f32, 0.0, d.z as f32],
        radius: r,
        velocity: [0.0; 3],
        speed: 4.0 * (G * s).sqrt(),
        spray: spray.min(SPLASH_MAX / 3),
        bubbles: (2 * spray).min(2 * SPLASH_MAX / 3),
        foam: (10.0 * s).min(1.0),
        first: 0,
    })
}

/// Speed (m/s) under which liquid falling into the water entrains no air:
/// the onset of air entrainment by plunging jets, about 1 m/s (Ervine,
/// McKeogh & Elsawy 1980; Chanson 1997, "Air bubble entrainment in
/// free-surface turbulent shear flows").
pub const ENTRAINMENT_ONSET_SPEED: f32 = 1.0;
/// Air a fast plunge carries under per volume of liquid, the ratio's
/// limit: measured Q_air/Q_water of plunging jets are of order 0.1–1
/// (Chanson 1997), growing with the impact speed above the onset.
pub const ENTRAINMENT_RATIO: f32 = 0.5;
/// Entrained air (m³) that one bubble particle born under a plunge stands
/// for: a cloud of about a hundred millimetre bubbles, so that a garden
/// fountain's plume (a few litres a second) shows a few thousand.
pub const PLUNGE_AIR_PER_BUBBLE: f32 = 4.0e-7;
/// Most bubble particles one landing parcel makes.
pub const PLUNGE_MAX_BUBBLES: u32 = 4;

/// Air (m³) that `volume` m³ of liquid plunging at `down_speed` m/s
/// carries under: β·V with β = [`ENTRAINMENT_RATIO`]·(1 − v_e/v)² above
/// the onset speed v_e, nothing below it (as `entrained_air` in WGSL).
pub fn entrained_air(volume: f32, down_speed: f32) -> f32 {
    let v = if down_speed.is_finite() { down_speed.clamp(0.0, 60.0) } else { 0.0 };
    if v <= ENTRAINMENT_ONSET_SPEED {
        return 0.0;
    }
    let excess = 1.0 - ENTRAINMENT_ONSET_SPEED / v;
    ENTRAINMENT_RATIO * excess * excess * volume
}

/// A parcel of the volumetric liquid falling into the water (issue #29),
/// as the white water takes it from the liquid's landings log.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plunge {
    pub x: f32,
    pub z: f32,
    /// Its downward speed as it crossed the level (m/s).
    pub down_speed: f32,
    /// Its volume (m³).
    pub volume: f32,
    /// The clock step it landed in.
    pub clock_step: u32,
}

impl Plunge {
    /// Foam (F·m²) it leaves where it lands: the air it carries under
    /// surfaces around the plume as froth at once, as a bubble's air does
    /// when it bursts ([`BURST_FOAM_PER_M3`]).
    pub fn foam(&self) -> f32 {
        entrained_air(self.volume, self.down_speed) * BURST_FOAM_PER_M3
    }

    /// Where its froth surfaces (x, z, m): the entrained air rises through
    /// the plume and spreads as it reaches the surface, so each plunge's
    /// froth lands at a random distance up to the plume's depth (uniform in
    /// radius: the froth thins as 1/r from a white centre to nothing at
    /// the plume's reach, not a disc with a hard rim). The same on the GPU
    /// (`plunge`), from the same hash as its bubbles.
    pub fn froth_at(&self, step: u32) -> [f32; 2] {
        let id0 =
            hash_u32(self.x.to_bits() ^ hash_u32(self.z.to_bits() ^ hash_u32(self.clock_step)));
        let reach = PLUME_DEPTH_PER_SPEED * self.down_speed.clamp(0.0, 60.0);
        let r = reach * random(step, id0, 21);
        let angle = std::f32::consts::TAU * random(step, id0, 22);
        [self.x + r * angle.cos(), self.z + r * angle.sin()]
    }

    /// The bubble particles it makes (each a cloud of
    /// [`PLUNGE_AIR_PER_BUBBLE`] of air; a random rounding keeps the
    /// mean), spread over its cell and down the plume: the same on the GPU
    /// (`plunge` in `whitewater.wgsl`), their ids hashed from where and
    /// when it landed (the log's order is the GPU's atomics').
    pub fn bubbles(&self, step: u32) -> Vec<Particle> {
        let id0 =
            hash_u32(self.x.to_bits() ^ hash_u32(self.z.to_bits() ^ hash_u32(self.clock_step)));
        let air = entrained_air(self.volume, self.down_speed) / PLUNGE_AIR_PER_BUBBLE;
        let count = ((air + random(step, id0, 13)) as u32).min(PLUNGE_MAX_BUBBLES);
        let depth = PLUME_DEPTH_PER_SPEED * self.down_speed.clamp(0.0, 60.0);
        (0..count)
            .map(|m| {
                let id = hash_u32(id0 ^ m.wrapping_mul(0x9E37_79B9)) | 0x8000_0000;
                let (r1, r2, r3) = (random(step, id, 1), random(step, id, 2), random(step, id, 3));
                let r4 = random(step, id, 4);
                let r = sample_bubble_radius(r3);
                let volume = bubble_volume(r);
                // A plume as wide as it is deep, about where it plunged.
                Particle {
                    position: [
                        self.x + (r1 - 0.5) * depth,
                        -0.01 - depth * r4,
                        self.z + (r2 - 0.5) * depth,
                    ],
                    kind: BUBBLE,
                    id,
                    volume,
                    radius: bubble_radius(volume),
                    ..Default::default()
                }
            })
            .collect()
    }
}

pub mod foam_look;
mod particles;
pub mod spray_look;
pub use particles::*;

#[cfg(test)]
mod tests;

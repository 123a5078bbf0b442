//! Marker particles carried through the grid (seed 003 §2.2, the
//! marker-and-cell method) with FLIP/PIC transfers (Zhu & Bridson 2005): each
//! step the particles' velocities are splatted onto the faces (trilinear
//! weights), the cells holding particles are liquid, gravity acts, the
//! pressure projection makes the flow divergence-free, the liquid's
//! velocity is extended one cell into the air, and the particles take the
//! grid's change (FLIP) blended with its value (PIC) before moving through it.

use super::grid::{Cell, MacGrid};
use super::pressure::{Projection, project};

/// How the liquid steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LiquidSettings {
    /// m/s²
    pub gravity: [f64; 3],
    /// kg/m³
    pub density: f64,
    /// The FLIP share of the particles' new velocity (0 = PIC: smooth and
    /// dissipative; 0.95–0.99: lively, the usual choice).
    pub flip: f64,
    /// The largest |∇·u| the projection leaves (1/s), and its iteration cap.
    pub tolerance: f64,
    pub max_iterations: usize,
    /// Kinematic viscosity ν (m²/s): water's is 1e-6, too small to matter
    /// on these grids; honey's about 1e-2. Explicit, so ν·dt/h² ≤ 1/6.
    pub viscosity: f64,
}

impl Default for LiquidSettings {
    fn default() -> Self {
        LiquidSettings {
            gravity: [0.0, -9.81, 0.0],
            density: 1000.0,
            flip: 0.95,
            tolerance: 1e-6,
            max_iterations: 2000,
            viscosity: 0.0,
        }
    }
}

/// A nozzle (seed 003 §2.3's emitter): each step from `first_step` until
/// `end_step` it puts one layer of particles at its mouth, `points` (world
/// positions, m) moving at `velocity` (m/s). The layers go round a ring of
/// `layers` layers of slots from `first_slot`: a layer overwrites the one
/// emitted `layers` steps before, so the particles a nozzle has alive never
/// exceed its share of the budget, however long it runs.
#[derive(Clone, Debug, PartialEq)]
pub struct Emitter {
    pub points: Vec<[f64; 3]>,
    pub velocity: [f64; 3],
    pub first_step: u64,
    pub end_step: u64,
    pub first_slot: usize,
    pub layers: usize,
}

impl Emitter {
    /// The slot of the `j`th point of the layer emitted at `step`.
    pub fn slot(&self, step: u64, j: usize) -> usize {
        let layer = ((step - self.first_step) % self.layers as u64) as usize;
        self.first_slot + layer * self.points.len() + j
    }
}

/// A liquid of marker particles in a MAC grid.
#[derive(Clone, Debug)]
pub struct Liquid {
    pub grid: MacGrid,
    pub settings: LiquidSettings,
    /// Per particle slot: world position (m), velocity (m/s), and whether
    /// it holds liquid (a nozzle's slots wait empty for their layer; a
    /// drain empties them).
    pub positions: Vec<[f64; 3]>,
    pub velocities: Vec<[f64; 3]>,
    pub alive: Vec<bool>,
    /// Nozzles, and drains (boxes, m) that take the particles entering them.
    pub emitters: Vec<Emitter>,
    pub drains: Vec<[[f64; 3]; 2]>,
    /// Steps taken.
    pub steps: u64,
    /// The last step's projection.
    pub last: Option<Projection>,
    /// Surface water below the liquid (the interactive water's mean level):
    /// a particle that falls under it becomes that water (a [`Landing`]).
    pub surface: Option<LandingSurface>,
    /// The landings since the caller last took them, in step order.
    pub landings: Vec<Landing>,
    /// The moving bodies in the liquid, as the caller last placed them
    /// (`solids`), and what the last step's pressure did to each.
    pub bodies: Vec<super::LiquidBody>,
    pub loads: Vec<super::BodyLoad>,
    /// The cells solid without any body (walls and static objects), and
    /// which body fills each cell (`solids::NO_BODY`: none); empty until
    /// a body is first placed.
    pub(crate) static_solid: Vec<bool>,
    pub(crate) owner: Vec<u32>,
    /// Its white water (foam, spray and bubbles where it breaks), if shed.
    pub white_water: Option<super::white_water::WhiteWater>,
}

/// Where the liquid meets the surface water below it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LandingSurface {
    /// Its mean level (m).
    pub level: f64,
    /// Each particle's share of the liquid (m³): the domain's cell volume
    /// over its particles per cell.
    pub particle_volume: f64,
}

/// A particle that fell into the surface water: where (x, z, m), at what
/// velocity (m/s), how much water (m³), in which step (the liquid's own
/// count). The surface water takes its mass and momentum
/// (`waves::ripples::RippleSim::land_liquid`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Landing {
    pub position: [f64; 2],
    pub velocity: [f64; 3],
    pub volume: f64,
    pub step: u64,
}

impl Liquid {
    /// No liquid yet in `grid`.
    pub fn new(grid: MacGrid, settings: LiquidSettings) -> Self {
        Liquid {
            grid,
            settings,
            positions: Vec::new(),
            velocities: Vec::new(),
            alive: Vec::new(),
            emitters: Vec::new(),
            drains: Vec::new(),
            steps: 0,
            last: None,
            surface: None,
            landings: Vec::new(),
            bodies: Vec::new(),
            loads: Vec::new(),
            static_solid: Vec::new(),
            owner: Vec::new(),
            white_water: None,
        }
    }

    /// Add a nozzle with `layers` layers of empty slots after the present
    /// ones (see [`Emitter`]).
    pub fn add_emitter(
        &mut self,
        points: Vec<[f64; 3]>,
        velocity: [f64; 3],
        steps: std::ops::Range<u64>,
        layers: usize,
    ) {
        let first_slot = self.positions.len();
        let slots = points.len() * layers;
        self.positions.extend(std::iter::repeat_n([0.0; 3], slots));
        self.velocities.extend(std::iter::repeat_n([0.0; 3], slots));
        self.alive.extend(std::iter::repeat_n(false, slots));
        self.emitters.push(Emitter {
            points,
            velocity,
            first_step: steps.start,
            end_step: steps.end,
            first_slot,
            layers,
        });
    }

    /// Particles holding liquid now.
    pub fn alive_count(&self) -> usize {
        self.alive.iter().filter(|a| **a).count()
    }

    /// The live particles' positions.
    pub fn live_positions(&self) -> impl Iterator<Item = &[f64; 3]> {
        self.positions.iter().zip(&self.alive).filter(|(_, a)| **a).map(|(p, _)| p)
    }

    /// Each nozzle's layer for this step.
    fn emit(&mut self) {
        let step = self.steps;
        for e in &self.emitters {
            if step < e.first_step || step >= e.end_step {
                continue;
            }
            for (j, p) in e.points.iter().enumerate() {
                let slot = e.slot(step, j);
                self.positions[slot] = *p;
                self.velocities[slot] = e.velocity;
                self.alive[slot] = true;
            }
        }
    }

    /// Fill the cells whose centres lie in the box `lo`..`hi` (m) with
    /// `per_axis`³ particles each on a regular lattice, at rest.
    pub fn fill_box(&mut self, lo: [f64; 3], hi: [f64; 3], per_axis: usize) {
        let g = &self.grid;
        let h = g.h;
        for k in 0..g.n[2] {
            for j in 0..g.n[1] {
                for i in 0..g.n[0] {
                    let c = [i, j, k];
                    let centre = [0, 1, 2].map(|a| g.origin[a] + (c[a] as f64 + 0.5) * h);
                    let solid = g.cells[g.cell(i, j, k)] == Cell::Solid;
                    if solid || (0..3).any(|a| centre[a] < lo[a] || centre[a] > hi[a]) {
                        continue;
                    }
                    for s in 0..per_axis * per_axis * per_axis {
                        let d =
                            [s % per_axis, (s / per_axis) % per_axis, s / (per_axis * per_axis)];
                        let p = [0, 1, 2].map(|a| {
                            g.origin[a] + (c[a] as f64 + (d[a] as f64 + 0.5) / per_axis as f64) * h
                        });
                        self.positions.push(p);
                        self.velocities.push([0.0; 3]);
                        self.alive.push(true);
                    }
                }
            }
        }
    }

    /// The cell a world point lies in (clamped to the grid).
    pub(crate) fn cell_of(&self, p: [f64; 3]) -> [usize; 3] {
        let g = &self.grid;
        [0, 1, 2].map(|a| (((p[a] - g.origin[a]) / g.h).floor().max(0.0) as usize).min(g.n[a] - 1))
    }

    /// One step of `dt` s (keep dt·|u|max under a cell: the caller's CFL).
    pub fn step(&mut self, dt: f64) {
        self.emit();
        self.place_bodies();
        self.particles_to_grid();
        self.mark_cells();
        let counts = self.white_water.is_some().then(|| self.cell_counts());
        let old = self.grid.vel.clone();
        for a in 0..3 {
            let dv = self.settings.gravity[a] * dt;
            self.grid.vel[a].iter_mut().for_each(|v| *v += dv);
        }
        self.diffuse(dt);
        let s = self.settings;
        self.last = Some(project(&mut self.grid, dt, s.density, s.tolerance, s.max_iterations));
        self.loads = self.body_loads();
        self.extrapolate();
        self.grid_to_particles(&old);
        self.advect(dt);
        if let Some(counts) = counts {
            self.white_water_step(&counts, dt, self.steps);
        }
        self.steps += 1;
    }

    /// Splat the particles' velocities onto the faces (weighted means);
    /// faces no particle reaches get 0.
    fn particles_to_grid(&mut self) {
        let g = &mut self.grid;
        for a in 0..3 {
            let mut sum = vec![0.0; g.vel[a].len()];
            let mut weight = vec![0.0; g.vel[a].len()];
            let live = self.alive.iter();
            for ((p, v), _) in
                self.positions.iter().zip(&self.velocities).zip(live).filter(|t| *t.1)
            {
                let (idx, w) = g.stencil(a, *p);
                for (f, wt) in idx.iter().zip(w) {
                    sum[*f] += wt * v[a];
                    weight[*f] += wt;
                }
            }
            for (f, out) in g.vel[a].iter_mut().enumerate() {
                *out = if weight[f] > 0.0 { sum[f] / weight[f] } else { 0.0 };
            }
        }
    }

    /// Cells holding a particle are liquid, the rest (but solids) air.
    fn mark_cells(&mut self) {
        for c in self.grid.cells.iter_mut() {
            if *c != Cell::Solid {
                *c = Cell::Air;
            }
        }
        for i in (0..self.positions.len()).filter(|i| self.alive[*i]) {
            let [x, y, z] = self.cell_of(self.positions[i]);
            let c = self.grid.cell(x, y, z);
            if self.grid.cells[c] != Cell::Solid {
                self.grid.cells[c] = Cell::Liquid;
            }
        }
    }

    /// Viscosity (the momentum equation's ν∇²u), one explicit step on the
    /// liquid's faces: each face's 7-point Laplacian over its own axis's
    /// faces, a neighbour on a solid wall counting 0 (no slip through it),
    /// one beyond the domain or in the air counting as the face itself
    /// (free slip along a wall, no stress at the free surface).
    fn diffuse(&mut self, dt: f64) {
        let nu = self.settings.viscosity;
        if nu <= 0.0 {
            return;
        }
        self.grid.enforce_walls();
        let k = nu * dt / (self.grid.h * self.grid.h);
        for a in 0..3 {
            let m = self.grid.face_dims(a);
            let vel = self.grid.vel[a].clone();
            for f in 0..vel.len() {
                let c = [f % m[0], (f / m[0]) % m[1], f / (m[0] * m[1])];
                if !self.face_valid(a, c) {
                    continue;
                }
                let own = vel[f];
                let mut laplacian = 0.0;
                for d in face_neighbours(m, c) {
                    if self.grid.face_solid(a, d[0], d[1], d[2]) {
                        laplacian -= own;
                    } else if self.face_valid(a, d) {
                        laplacian += vel[self.grid.face(a, d[0], d[1], d[2])] - own;
                    }
                }
                self.grid.vel[a][f] = own + k * laplacian;
            }
        }
    }

    /// Whether face (a; i, j, k) borders a liquid cell and no solid: its
    /// velocity is the liquid's.
    fn face_valid(&self, a: usize, f: [usize; 3]) -> bool {
        let hi = [f[0] as i64, f[1] as i64, f[2] as i64];
        let mut lo = hi;
        lo[a] -= 1;
        let (cl, ch) = (self.grid.cell_at(lo), self.grid.cell_at(hi));
        cl != Cell::Solid && ch != Cell::Solid && (cl == Cell::Liquid || ch == Cell::Liquid)
    }

    /// Extend the liquid's velocity into the air two faces deep (each face
    /// the mean of its already-known neighbours), so that particles near the
    /// surface do not sample stale air velocities.
    fn extrapolate(&mut self) {
        for a in 0..3 {
            let m = self.grid.face_dims(a);
            let mut known: Vec<bool> = (0..self.grid.vel[a].len())
                .map(|f| {
                    let c = [f % m[0], (f / m[0]) % m[1], f / (m[0] * m[1])];
                    self.face_valid(a, c)
                })
                .collect();
            for _ in 0..2 {
                let vel = self.grid.vel[a].clone();
                let was = known.clone();
                for f in 0..vel.len() {
                    if was[f] {
                        continue;
                    }
                    let c = [f % m[0], (f / m[0]) % m[1], f / (m[0] * m[1])];
                    let (mut sum, mut n) = (0.0, 0);
                    for d in face_neighbours(m, c) {
                        let g = self.grid.face(a, d[0], d[1], d[2]);
                        if was[g] {
                            sum += vel[g];
                            n += 1;
                        }
                    }
                    if n > 0 {
                        self.grid.vel[a][f] = sum / n as f64;
                        known[f] = true;
                    }
                }
            }
        }
        self.grid.enforce_walls();
    }

    /// Each particle takes the grid's change (FLIP) blended with its value
    /// (PIC); `old` is the grid the particles splatted, before forces.
    fn grid_to_particles(&mut self, old: &[Vec<f64>; 3]) {
        let flip = self.settings.flip;
        let mut before = self.grid.clone();
        before.vel = old.clone();
        let live = self.alive.iter();
        for ((p, v), _) in
            self.positions.iter().zip(self.velocities.iter_mut()).zip(live).filter(|t| *t.1)
        {
            let now = self.grid.velocity(*p);
            let then = before.velocity(*p);
            *v = [0, 1, 2].map(|a| flip * (v[a] + now[a] - then[a]) + (1.0 - flip) * now[a]);
        }
    }

    /// Move the particles through the grid's velocity (midpoint rule),
    /// kept a hair inside the closed walls; a particle whose move would end
    /// in a solid cell stays where it was; one that ends in a drain or
    /// beyond an open side is gone, and one under the surface water's level
    /// lands in it.
    fn advect(&mut self, dt: f64) {
        let margin = 1e-3 * self.grid.h;
        for n in 0..self.positions.len() {
            if !self.alive[n] {
                continue;
            }
            let g = &self.grid;
            let p = self.positions[n];
            let u = g.velocity(p);
            let mid = [0, 1, 2].map(|a| p[a] + 0.5 * dt * u[a]);
            let u = g.velocity(mid);
            // Outside the bodies (a body's cells do not stop a particle,
            // its exact surface does), and kept inside the closed sides;
            // through an open one it leaves.
            let moved = [0, 1, 2].map(|a| p[a] + dt * u[a]);
            let mut v = self.velocities[n];
            let moved = self.clear_of_bodies(moved, &mut v);
            self.velocities[n] = v;
            let g = &self.grid;
            let next = [0, 1, 2].map(|a| {
                let lo = g.origin[a] + margin;
                let hi = g.origin[a] + g.n[a] as f64 * g.h - margin;
                let v = moved[a];
                let v = if g.open[a][0] { v } else { v.max(lo) };
                if g.open[a][1] { v } else { v.min(hi) }
            });
            if (0..3).any(|a| next[a] < g.origin[a] || next[a] > g.origin[a] + g.n[a] as f64 * g.h)
            {
                self.alive[n] = false;
                continue;
            }
            let [x, y, z] = self.cell_of(next);
            let c = self.grid.cell(x, y, z);
            let body_cell = self.owner.get(c).is_some_and(|o| *o != super::solids::NO_BODY);
            if self.grid.cells[c] != Cell::Solid || body_cell {
                self.positions[n] = next;
            }
            let p = self.positions[n];
            if self.drains.iter().any(|[lo, hi]| (0..3).all(|a| p[a] >= lo[a] && p[a] <= hi[a])) {
                self.alive[n] = false;
            } else if let Some(surface) = self.surface
                && p[1] < surface.level
            {
                self.alive[n] = false;
                self.landings.push(Landing {
                    position: [p[0], p[2]],
                    velocity: self.velocities[n],
                    volume: surface.particle_volume,
                    step: self.steps,
                });
            }
        }
    }
}

/// The up to six neighbours of face `c` in a face grid of `m` faces per
/// side (its own axis's faces one step along each axis), those in range.
fn face_neighbours(m: [usize; 3], c: [usize; 3]) -> impl Iterator<Item = [usize; 3]> {
    (0..6).filter_map(move |k| {
        let (b, up) = (k / 2, k % 2 == 1);
        let mut d = c;
        if up {
            d[b] += 1;
            (d[b] < m[b]).then_some(d)
        } else {
            d[b] = c[b].checked_sub(1)?;
            Some(d)
        }
    })
}

//! The marker-and-cell grid (seed 003 §2.2, after Harlow & Welch 1965):
//! velocities on the faces of cubic cells, pressure at their centres, each
//! cell solid, liquid or air. The domain's six sides are closed walls.

/// What fills a cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cell {
    Air,
    Liquid,
    Solid,
}

/// A box of `n` cells of side `h` (m) from `origin`, with the velocity
/// components on their faces: `u` on the x-faces ((nx+1)·ny·nz), `v` on
/// the y-faces, `w` on the z-faces, and a pressure per cell.
#[derive(Clone, Debug, PartialEq)]
pub struct MacGrid {
    pub n: [usize; 3],
    pub h: f64,
    pub origin: [f64; 3],
    /// Face velocities (m/s) per axis.
    pub vel: [Vec<f64>; 3],
    /// Pressure (Pa) per cell (0 in air).
    pub pressure: Vec<f64>,
    pub cells: Vec<Cell>,
    /// Which of the domain's sides are open, per axis low and high: beyond
    /// an open side is air (p = 0), and particles crossing it leave.
    pub open: [[bool; 2]; 3],
    /// Per cell, the velocity (m/s) of the solid filling it: 0 for the
    /// walls and static objects, a moving body's at the cell's centre.
    pub solid_velocity: Vec<[f64; 3]>,
}

impl MacGrid {
    /// Still air everywhere.
    pub fn new(n: [usize; 3], h: f64, origin: [f64; 3]) -> Self {
        let faces = |a: usize| {
            let mut m = n;
            m[a] += 1;
            m[0] * m[1] * m[2]
        };
        let count = n[0] * n[1] * n[2];
        MacGrid {
            n,
            h,
            origin,
            vel: [vec![0.0; faces(0)], vec![0.0; faces(1)], vec![0.0; faces(2)]],
            pressure: vec![0.0; count],
            cells: vec![Cell::Air; count],
            open: [[false; 2]; 3],
            solid_velocity: vec![[0.0; 3]; count],
        }
    }

    /// Index of cell (i, j, k).
    pub fn cell(&self, i: usize, j: usize, k: usize) -> usize {
        (k * self.n[1] + j) * self.n[0] + i
    }

    /// Index of the face of axis `a` at (i, j, k): the face on the low side
    /// of cell (i, j, k) along `a` (index n[a] is the far wall).
    pub fn face(&self, a: usize, i: usize, j: usize, k: usize) -> usize {
        let mut m = self.n;
        m[a] += 1;
        (k * m[1] + j) * m[0] + i
    }

    /// The faces per side of axis `a`'s velocity grid.
    pub fn face_dims(&self, a: usize) -> [usize; 3] {
        let mut m = self.n;
        m[a] += 1;
        m
    }

    /// The cell at integer coordinates that may lie outside: outside is
    /// solid (a closed wall) or air (beyond an open side).
    pub fn cell_at(&self, c: [i64; 3]) -> Cell {
        let beyond = |a: usize| {
            if c[a] < 0 {
                Some(self.open[a][0])
            } else if c[a] >= self.n[a] as i64 {
                Some(self.open[a][1])
            } else {
                None
            }
        };
        let sides: Vec<bool> = (0..3).filter_map(beyond).collect();
        if !sides.is_empty() {
            return if sides.iter().all(|o| *o) { Cell::Air } else { Cell::Solid };
        }
        self.cells[self.cell(c[0] as usize, c[1] as usize, c[2] as usize)]
    }

    /// Whether face (a; i, j, k) touches a solid (a wall or a solid cell):
    /// its velocity is the solid's ([`MacGrid::solid_face_velocity`]).
    pub fn face_solid(&self, a: usize, i: usize, j: usize, k: usize) -> bool {
        let mut lo = [i as i64, j as i64, k as i64];
        let hi = lo;
        lo[a] -= 1;
        self.cell_at(lo) == Cell::Solid || self.cell_at(hi) == Cell::Solid
    }

    /// The velocity along `a` of the solid at face (a; i, j, k): a solid
    /// cell's (the high side's if both are solid), 0 at a wall.
    pub fn solid_face_velocity(&self, a: usize, i: usize, j: usize, k: usize) -> f64 {
        let hi = [i, j, k];
        if hi[a] < self.n[a] && self.cells[self.cell(i, j, k)] == Cell::Solid {
            return self.solid_velocity[self.cell(i, j, k)][a];
        }
        if hi[a] > 0 {
            let mut lo = hi;
            lo[a] -= 1;
            let c = self.cell(lo[0], lo[1], lo[2]);
            if self.cells[c] == Cell::Solid {
                return self.solid_velocity[c][a];
            }
        }
        0.0
    }

    /// Give every face that touches a solid the solid's velocity (0 at the
    /// closed walls and static objects; a moving body's where it is).
    pub fn enforce_walls(&mut self) {
        for a in 0..3 {
            let m = self.face_dims(a);
            for k in 0..m[2] {
                for j in 0..m[1] {
                    for i in 0..m[0] {
                        if self.face_solid(a, i, j, k) {
                            let f = self.face(a, i, j, k);
                            self.vel[a][f] = self.solid_face_velocity(a, i, j, k);
                        }
                    }
                }
            }
        }
    }

    /// ∇·u of cell (i, j, k) (1/s): the net outflow of its six faces.
    pub fn divergence(&self, i: usize, j: usize, k: usize) -> f64 {
        let mut d = 0.0;
        for a in 0..3 {
            let mut hi = [i, j, k];
            hi[a] += 1;
            d +=
                self.vel[a][self.face(a, hi[0], hi[1], hi[2])] - self.vel[a][self.face(a, i, j, k)];
        }
        d / self.h
    }

    /// The largest |∇·u| over the liquid cells (1/s).
    pub fn max_liquid_divergence(&self) -> f64 {
        let mut worst = 0.0f64;
        for k in 0..self.n[2] {
            for j in 0..self.n[1] {
                for i in 0..self.n[0] {
                    if self.cells[self.cell(i, j, k)] == Cell::Liquid {
                        worst = worst.max(self.divergence(i, j, k).abs());
                    }
                }
            }
        }
        worst
    }

    /// Velocity component `a` at world point `p`, trilinear over its faces
    /// (clamped to the grid).
    pub fn sample(&self, a: usize, p: [f64; 3]) -> f64 {
        let (idx, w) = self.stencil(a, p);
        let mut s = 0.0;
        for (f, wt) in idx.iter().zip(w) {
            s += self.vel[a][*f] * wt;
        }
        s
    }

    /// The eight faces of axis `a` around world point `p` and their
    /// trilinear weights (summing to 1), clamped to the grid.
    pub fn stencil(&self, a: usize, p: [f64; 3]) -> ([usize; 8], [f64; 8]) {
        let m = self.face_dims(a);
        let mut base = [0usize; 3];
        let mut frac = [0.0f64; 3];
        for b in 0..3 {
            // Faces of axis a sit at integer coordinates along a, at cell
            // centres (half-integers) along the others.
            let offset = if b == a { 0.0 } else { 0.5 };
            let x = (p[b] - self.origin[b]) / self.h - offset;
            let hi = (m[b] - 1) as f64;
            let x = x.clamp(0.0, hi);
            let i0 = (x.floor() as usize).min(m[b].saturating_sub(2));
            base[b] = i0;
            frac[b] = if m[b] > 1 { x - i0 as f64 } else { 0.0 };
        }
        // The corner one step up each axis (none along an axis one face
        // long), as strides into the face array.
        let stride = [1, m[0], m[0] * m[1]];
        let up = [0, 1, 2].map(|b| if m[b] > 1 { stride[b] } else { 0 });
        let first = base[0] + base[1] * stride[1] + base[2] * stride[2];
        let w = [0, 1, 2].map(|b| [1.0 - frac[b], frac[b]]);
        let mut idx = [0usize; 8];
        let mut weights = [0.0f64; 8];
        for c in 0..8 {
            let d = [c & 1, (c >> 1) & 1, (c >> 2) & 1];
            idx[c] = first + d[0] * up[0] + d[1] * up[1] + d[2] * up[2];
            weights[c] = w[0][d[0]] * w[1][d[1]] * w[2][d[2]];
        }
        (idx, weights)
    }

    /// The velocity at world point `p`.
    pub fn velocity(&self, p: [f64; 3]) -> [f64; 3] {
        [self.sample(0, p), self.sample(1, p), self.sample(2, p)]
    }
}

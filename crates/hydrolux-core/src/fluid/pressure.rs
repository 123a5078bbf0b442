//! The pressure projection (seed 003 §2.2; Bridson, *Fluid Simulation for
//! Computer Graphics*, 2nd ed., ch. 5): the pressure that makes the liquid's
//! velocity divergence-free, with p = 0 in air (the free surface) and the
//! solid's velocity on faces that touch a solid. The discrete Poisson
//! equation is solved by conjugate gradients with a Jacobi (diagonal)
//! preconditioner — every step of it a stencil or a sum, as a GPU runs it.

use super::grid::{Cell, MacGrid};

/// How a projection went.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// Conjugate-gradient iterations taken.
    pub iterations: usize,
    /// The largest |∇·u| over liquid cells before and after (1/s): after
    /// is the solver's residual (the two are the same vector).
    pub divergence_before: f64,
    pub divergence_after: f64,
}

/// Make `grid`'s liquid velocity divergence-free for a step of `dt` s of a
/// liquid of `density` (kg/m³): solve for the pressure to `tolerance` (the
/// largest |∇·u| left, 1/s) in at most `max_iterations`, starting from the
/// pressure `grid` holds in its liquid cells (the last step's), write it to
/// `grid.pressure` (0 outside the liquid) and subtract its gradient from the
/// face velocities.
pub fn project(
    grid: &mut MacGrid,
    dt: f64,
    density: f64,
    tolerance: f64,
    max_iterations: usize,
) -> Projection {
    grid.enforce_walls();
    let [nx, ny, nz] = grid.n;
    // The unknowns: one per liquid cell.
    let mut unknown = vec![usize::MAX; grid.cells.len()];
    let mut cells = Vec::new();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let c = grid.cell(i, j, k);
                if grid.cells[c] == Cell::Liquid {
                    unknown[c] = cells.len();
                    cells.push([i, j, k]);
                }
            }
        }
    }
    let count = cells.len();
    let scale = dt / (density * grid.h * grid.h);
    // Per unknown: its non-solid neighbours (the diagonal) and its liquid
    // neighbours' unknowns (the off-diagonal −scale each).
    let mut diagonal = vec![0.0; count];
    let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); count];
    let mut b = vec![0.0; count];
    for (n, &[i, j, k]) in cells.iter().enumerate() {
        for a in 0..3 {
            for side in [-1i64, 1] {
                let mut q = [i as i64, j as i64, k as i64];
                q[a] += side;
                match grid.cell_at(q) {
                    Cell::Solid => {}
                    Cell::Air => diagonal[n] += scale,
                    Cell::Liquid => {
                        diagonal[n] += scale;
                        let other = grid.cell(q[0] as usize, q[1] as usize, q[2] as usize);
                        neighbours[n].push(unknown[other]);
                    }
                }
            }
        }
        b[n] = -grid.divergence(i, j, k);
    }
    let apply = |x: &[f64], out: &mut [f64]| {
        for n in 0..count {
            let mut s = diagonal[n] * x[n];
            for &m in &neighbours[n] {
                s -= scale * x[m];
            }
            out[n] = s;
        }
    };
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(a, b)| a * b).sum::<f64>();
    let max_abs = |x: &[f64]| x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let precondition = |r: &[f64], z: &mut [f64]| {
        for n in 0..count {
            z[n] = if diagonal[n] > 0.0 { r[n] / diagonal[n] } else { 0.0 };
        }
    };
    // Warm start from the last step's pressure (what the grid holds in its
    // liquid cells): it changes little from step to step.
    let mut p: Vec<f64> =
        cells.iter().map(|&[i, j, k]| grid.pressure[grid.cell(i, j, k)]).collect();
    let divergence_before = max_abs(&b);
    let mut r = vec![0.0; count];
    apply(&p, &mut r);
    for n in 0..count {
        r[n] = b[n] - r[n];
    }
    let mut z = vec![0.0; count];
    precondition(&r, &mut z);
    let mut s = z.clone();
    let mut sigma = dot(&r, &z);
    let mut q = vec![0.0; count];
    let mut iterations = 0;
    while iterations < max_iterations && max_abs(&r) > tolerance {
        apply(&s, &mut q);
        let sq = dot(&s, &q);
        if sq <= 0.0 {
            break;
        }
        let alpha = sigma / sq;
        for n in 0..count {
            p[n] += alpha * s[n];
            r[n] -= alpha * q[n];
        }
        precondition(&r, &mut z);
        let next = dot(&r, &z);
        let beta = next / sigma;
        sigma = next;
        for n in 0..count {
            s[n] = z[n] + beta * s[n];
        }
        iterations += 1;
    }
    // Pressure into the grid (0 elsewhere), its gradient out of the faces
    // between a liquid cell and a liquid or air cell.
    grid.pressure.iter_mut().for_each(|v| *v = 0.0);
    for (n, &[i, j, k]) in cells.iter().enumerate() {
        let c = grid.cell(i, j, k);
        grid.pressure[c] = p[n];
    }
    let gradient = dt / (density * grid.h);
    for a in 0..3 {
        let m = grid.face_dims(a);
        for k in 0..m[2] {
            for j in 0..m[1] {
                for i in 0..m[0] {
                    let hi = [i as i64, j as i64, k as i64];
                    let mut lo = hi;
                    lo[a] -= 1;
                    let (cl, ch) = (grid.cell_at(lo), grid.cell_at(hi));
                    if cl == Cell::Solid || ch == Cell::Solid {
                        continue;
                    }
                    if cl != Cell::Liquid && ch != Cell::Liquid {
                        continue;
                    }
                    // Beyond an open side: air, p = 0.
                    let at = |c: [i64; 3]| {
                        if (0..3).any(|a| c[a] < 0 || c[a] >= grid.n[a] as i64) {
                            return 0.0;
                        }
                        grid.pressure[grid.cell(c[0] as usize, c[1] as usize, c[2] as usize)]
                    };
                    let f = grid.face(a, i, j, k);
                    grid.vel[a][f] -= gradient * (at(hi) - at(lo));
                }
            }
        }
    }
    Projection { iterations, divergence_before, divergence_after: max_abs(&r) }
}

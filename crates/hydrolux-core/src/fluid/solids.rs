//! Moving bodies in the liquid (issue #29, two-way coupling; seed 003
//! §2.4): each step a body fills the cells whose centres it covers, and
//! their faces take its velocity there (v + ω × r), so the projection makes
//! the liquid flow round it and out of its way; what the liquid does to the
//! body is the pressure on those faces, p·h² along each face's normal,
//! summed into a force and a torque about the body's centre (Archimedes'
//! buoyancy is its hydrostatic part, the form drag and added mass its
//! dynamic part). Particles are kept outside the body's exact surface (its
//! signed distance), with no velocity into it.

use super::flip::Liquid;
use super::grid::Cell;
use crate::coupling::{Pose, Shape};
use glam::DVec3;

/// A body in the liquid this step: its exact shape, where it is and how it
/// moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LiquidBody {
    pub shape: Shape,
    pub pose: Pose,
    /// m/s, of its centre.
    pub velocity: DVec3,
    /// rad/s
    pub angular_velocity: DVec3,
}

impl LiquidBody {
    /// The body's velocity at world point `x` (m/s).
    pub fn velocity_at(&self, x: DVec3) -> DVec3 {
        self.velocity + self.angular_velocity.cross(x - self.pose.position)
    }

    fn local(&self, x: DVec3) -> DVec3 {
        self.pose.rotation.inverse() * (x - self.pose.position)
    }

    /// Signed distance (m) from its surface to world point `x`.
    pub fn signed_distance(&self, x: DVec3) -> f64 {
        self.shape.signed_distance(self.local(x))
    }

    /// Its outward normal nearest world point `x`.
    pub fn outward_normal(&self, x: DVec3) -> DVec3 {
        self.pose.rotation * self.shape.outward_normal(self.local(x))
    }
}

/// What the liquid did to a body over a step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyLoad {
    /// The pressure's force (N) and its torque about the body's centre
    /// (N·m).
    pub force: DVec3,
    pub torque: DVec3,
    /// The share of the body's cell faces that touch liquid (0–1): how wet
    /// it is, for the added mass.
    pub wetted: f64,
}

/// No body fills the cell.
pub(crate) const NO_BODY: u32 = u32::MAX;

impl Liquid {
    /// Fill the cells the bodies cover (their centres inside) with them,
    /// and give those cells the body's velocity there; the cells they left
    /// are air again (the static solids stay).
    pub(crate) fn place_bodies(&mut self) {
        if self.bodies.is_empty() && self.owner.is_empty() {
            return;
        }
        let g = &mut self.grid;
        if self.owner.is_empty() {
            self.static_solid = g.cells.iter().map(|c| *c == Cell::Solid).collect();
            self.owner = vec![NO_BODY; g.cells.len()];
        }
        for c in 0..g.cells.len() {
            if self.owner[c] != NO_BODY {
                self.owner[c] = NO_BODY;
                g.cells[c] = if self.static_solid[c] { Cell::Solid } else { Cell::Air };
                g.solid_velocity[c] = [0.0; 3];
            }
        }
        for (b, body) in self.bodies.iter().enumerate() {
            let reach = body.shape.bounding_radius();
            let range = |a: usize| {
                let lo = (body.pose.position[a] - reach - g.origin[a]) / g.h;
                let hi = (body.pose.position[a] + reach - g.origin[a]) / g.h;
                let clamp = |x: f64| (x.max(0.0) as usize).min(g.n[a]);
                clamp(lo.floor())..clamp(hi.ceil() + 1.0)
            };
            for k in range(2) {
                for j in range(1) {
                    for i in range(0) {
                        let c = g.cell(i, j, k);
                        if self.static_solid[c] || self.owner[c] != NO_BODY {
                            continue;
                        }
                        let centre = DVec3::new(
                            g.origin[0] + (i as f64 + 0.5) * g.h,
                            g.origin[1] + (j as f64 + 0.5) * g.h,
                            g.origin[2] + (k as f64 + 0.5) * g.h,
                        );
                        if body.signed_distance(centre) <= 0.0 {
                            g.cells[c] = Cell::Solid;
                            g.solid_velocity[c] = body.velocity_at(centre).to_array();
                            self.owner[c] = b as u32;
                        }
                    }
                }
            }
        }
    }

    /// The pressure's force and torque on each body: over every face
    /// between a body's cell and a liquid cell, the liquid's pressure
    /// carried linearly to the face (from the liquid cell and the one
    /// beyond it, so a hydrostatic pressure is exact there) times h².
    pub(crate) fn body_loads(&self) -> Vec<BodyLoad> {
        let mut loads = vec![BodyLoad::default(); self.bodies.len()];
        if self.bodies.is_empty() {
            return loads;
        }
        let g = &self.grid;
        let mut faces = vec![[0usize; 2]; self.bodies.len()];
        let area = g.h * g.h;
        let inside = |q: [i64; 3]| (0..3).all(|a| q[a] >= 0 && q[a] < g.n[a] as i64);
        let index = |q: [i64; 3]| g.cell(q[0] as usize, q[1] as usize, q[2] as usize);
        for k in 0..g.n[2] {
            for j in 0..g.n[1] {
                for i in 0..g.n[0] {
                    let c = g.cell(i, j, k);
                    let b = self.owner.get(c).copied().unwrap_or(NO_BODY);
                    if b == NO_BODY {
                        continue;
                    }
                    let body = &self.bodies[b as usize];
                    let centre = DVec3::new(
                        g.origin[0] + (i as f64 + 0.5) * g.h,
                        g.origin[1] + (j as f64 + 0.5) * g.h,
                        g.origin[2] + (k as f64 + 0.5) * g.h,
                    );
                    for side in 0..6 {
                        let (a, step) = (side / 2, if side % 2 == 0 { -1 } else { 1 });
                        let mut q = [i as i64, j as i64, k as i64];
                        q[a] += step;
                        if !inside(q) || self.owner[index(q)] == b {
                            continue;
                        }
                        faces[b as usize][0] += 1;
                        if g.cells[index(q)] != Cell::Liquid {
                            continue;
                        }
                        faces[b as usize][1] += 1;
                        let p = g.pressure[index(q)];
                        let mut beyond = q;
                        beyond[a] += step;
                        let p_beyond = if !inside(beyond) {
                            if g.open[a][usize::from(step > 0)] { 0.0 } else { p }
                        } else if g.cells[index(beyond)] == Cell::Solid {
                            p
                        } else {
                            g.pressure[index(beyond)]
                        };
                        let p_face = p + 0.5 * (p - p_beyond);
                        // The liquid at q pushes the body away from q.
                        let mut normal = DVec3::ZERO;
                        normal[a] = -(step as f64);
                        let force = p_face * area * normal;
                        let at = centre - normal * (0.5 * g.h);
                        let load = &mut loads[b as usize];
                        load.force += force;
                        load.torque += (at - body.pose.position).cross(force);
                    }
                }
            }
        }
        for (load, [all, wet]) in loads.iter_mut().zip(faces) {
            load.wetted = if all > 0 { wet as f64 / all as f64 } else { 0.0 };
        }
        loads
    }

    /// Keep a particle at `p` moving at `v` outside every body: one inside
    /// or on a body's surface goes to just outside it (a twentieth of a
    /// cell), and loses any velocity into the body.
    pub(crate) fn clear_of_bodies(&self, p: [f64; 3], v: &mut [f64; 3]) -> [f64; 3] {
        let margin = 0.05 * self.grid.h;
        let mut p = DVec3::from(p);
        for body in &self.bodies {
            let d = body.signed_distance(p);
            if d >= margin {
                continue;
            }
            let n = body.outward_normal(p);
            p += (margin - d) * n;
            let u = DVec3::from(*v);
            let into = (u - body.velocity_at(p)).dot(n);
            if into < 0.0 {
                *v = (u - into * n).to_array();
            }
        }
        p.to_array()
    }
}

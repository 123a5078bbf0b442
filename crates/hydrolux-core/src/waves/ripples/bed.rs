//! What the interactive water stands on (seed 003 §2.4; issue #33): the
//! still-water depth of every cell, from the floor, the terrain and the
//! static objects in the water.
//!
//! Depth sets the waves' speed: K = k·tanh(k·d) at the cell's own depth
//! (blended between the two levels the parent module steps), so waves slow,
//! shorten and bend towards the shallows (shoaling and refraction: along a
//! depth contour the wave number is kept, across it |k| follows the
//! dispersion relation at the new depth, which is Snell's law for wave
//! rays). A static object's top below the water is the bed there (a shelf,
//! a step). Where a static object stands through the surface, or the land
//! rises out of the water, the cell is dry: the water there is held at
//! rest, h = φ = 0 every step (the obstruction mask of Tessendorf's iWave),
//! a wall that waves reflect from and bend around.

use crate::coupling::{Pose, Shape, body_column};
use crate::geometry::terrain::Terrain;

use super::{RippleGrid, RippleWindow};

/// A static object the water meets: its exact shape, or the box its scale
/// spans (a mesh; as the rigid bodies take it).
#[derive(Clone, Debug, PartialEq)]
pub struct Obstacle {
    pub shape: Shape,
    pub pose: Pose,
}

/// The bed under the interactive water.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RippleBed {
    /// Depth (m) of the water where nothing else stands (a flat floor's,
    /// the scene's `ripples.depth`, or deep water's).
    pub depth: f64,
    /// The terrain floor, replacing the flat one where given.
    pub terrain: Option<Terrain>,
    /// The static objects the water reaches.
    pub obstacles: Vec<Obstacle>,
}

impl RippleBed {
    /// Water `depth` m deep everywhere.
    pub fn flat(depth: f64) -> Self {
        RippleBed { depth, ..Default::default() }
    }

    /// Whether every cell is as deep as every other.
    pub fn is_flat(&self) -> bool {
        self.terrain.is_none() && self.obstacles.is_empty()
    }

    /// The still water's depth (m) at world (x, z): down to the terrain or
    /// the flat floor, or to the top of a static object below the surface;
    /// 0 where an object stands through the surface or the land is above
    /// it (a dry cell).
    pub fn depth_at(&self, x: f64, z: f64) -> f64 {
        let mut bed = match &self.terrain {
            Some(t) => t.height_at(x as f32, z as f32) as f64,
            None => -self.depth,
        };
        for o in &self.obstacles {
            // Most columns miss most objects: their bounding sphere first.
            let (p, r) = (o.pose.position, o.shape.bounding_radius());
            if (x - p.x).abs() > r || (z - p.z).abs() > r {
                continue;
            }
            if let Some((y0, y1)) = body_column(&o.shape, &o.pose, x, z) {
                if y0 < 0.0 && y1 > 0.0 {
                    return 0.0;
                }
                if y1 <= 0.0 && y0 <= bed + 1e-6 {
                    // Standing on the bed: its top is the bed (an object
                    // hanging in the water is passed under).
                    bed = bed.max(y1);
                }
            }
        }
        (-bed).max(0.0)
    }

    /// The depth (m) of each cell of the domain `window` shows (row = z),
    /// at its centre: what [`super::RippleSim::depth`] and the GPU's depth
    /// buffer hold.
    pub fn depths(&self, grid: &RippleGrid, window: &RippleWindow) -> Vec<f64> {
        let n = grid.cells;
        let mut out = vec![0.0; n * n];
        for j in 0..n {
            for i in 0..n {
                let at = |a: usize, c: usize| {
                    (window.origin[a] as f64 + c as f64 + 0.5) * grid.cell_size
                };
                out[j * n + i] = self.depth_at(at(0, i), at(1, j));
            }
        }
        out
    }
}

/// Whether a cell of still-water depth `depth` holds water (else it is an
/// obstacle or land, held at rest).
pub fn wet(depth: f64) -> bool {
    depth > 0.0
}

#[cfg(test)]
mod tests {
    use super::super::*;
    use std::f64::consts::PI;

    fn periodic(cells: usize, cell: f64, depths: [f64; 2], dt: f64) -> RippleSim {
        let s = RippleSettings {
            grid: RippleGrid { boundary: RippleBoundary::Periodic, cells, cell_size: cell },
            tension: WATER_TENSION,
            viscosity: 0.0,
            damping: 0.0,
            depths,
            dt,
        };
        RippleSim::new(s, RippleWindow { origin: [0, 0] })
    }

    /// A packet of waves of wave vector `k` over water `depth` deep,
    /// travelling along k: h = A·e(p)·cos(k·p), φ = A·e(p)·(ω/K)·sin(k·p)
    /// with the envelope e(p) = exp(−Σ((p − centre)/σ)²/2).
    fn packet(sim: &mut RippleSim, k: [f64; 2], depth: f64, centre: [f64; 2], sigma: [f64; 2]) {
        let km = k[0].hypot(k[1]);
        let omega = capillary_gravity_omega(km, depth, sim.settings.tension);
        let kk = km * (km * depth).tanh();
        sim.set(|x, z| {
            let e = (-0.5
                * (((x - centre[0]) / sigma[0]).powi(2) + ((z - centre[1]) / sigma[1]).powi(2)))
            .exp();
            let phase = k[0] * x + k[1] * z;
            (1e-3 * e * phase.cos(), 1e-3 * e * omega / kk * phase.sin())
        });
    }

    /// The centre (m) of h² over the wet cells.
    fn centroid(sim: &RippleSim) -> [f64; 2] {
        let (n, c) = (sim.settings.grid.cells, sim.settings.grid.cell_size);
        let (mut sum, mut at) = (0.0, [0.0; 2]);
        for j in 0..n {
            for i in 0..n {
                let e = sim.height(i, j).powi(2);
                sum += e;
                at[0] += e * (i as f64 + 0.5) * c;
                at[1] += e * (j as f64 + 0.5) * c;
            }
        }
        at.map(|a| a / sum)
    }

    /// A wall at 30° across a packet's path sends it off by the mirror law
    /// and keeps its energy: the obstruction mask is a wall, not a sponge.
    #[test]
    fn a_wall_at_an_angle_reflects_waves_by_the_mirror_law_and_keeps_their_energy() {
        let (depth, cell, dt) = (2.0, 0.1, 1.0 / 30.0);
        let mut sim = periodic(128, cell, [depth; 2], dt);
        // The wall's face through (7, 6.4), its normal n at 30° to +x,
        // 2.5 m thick and 9 m long.
        let a = 30f64.to_radians();
        let (n, t) = ([a.cos(), a.sin()], [-a.sin(), a.cos()]);
        let w0 = [7.0, 6.4];
        let bed = |x: f64, z: f64| {
            let r = [x - w0[0], z - w0[1]];
            let (s, u) = (r[0] * n[0] + r[1] * n[1], r[0] * t[0] + r[1] * t[1]);
            if (0.0..2.5).contains(&s) && u.abs() < 4.5 { 0.0 } else { depth }
        };
        let size = sim.settings.grid.cells;
        for j in 0..size {
            for i in 0..size {
                sim.depth[j * size + i] = bed((i as f64 + 0.5) * cell, (j as f64 + 0.5) * cell);
            }
        }
        // λ = 0.8 m (8 cells) heading along +x from 4 m before the wall.
        let k = 2.0 * PI / 0.8;
        packet(&mut sim, [k, 0.0], depth, [3.0, 6.4], [0.7, 0.7]);
        sim.step(&[]);
        let e0 = sim.energy();
        let group = capillary_gravity_group_speed(k, depth, sim.settings.tension);
        // Out at (4 − 0.7 thick) m to the wall and as far back: measured
        // over the second half of the way back.
        let to = |t: f64| (t / dt).round() as usize;
        let (t1, t2) = (4.0 / group + 3.0, 4.0 / group + 6.0);
        for _ in 1..to(t1) {
            sim.step(&[]);
        }
        let c1 = centroid(&sim);
        for _ in to(t1)..to(t2) {
            sim.step(&[]);
        }
        let c2 = centroid(&sim);
        let e2 = sim.energy();
        // The mirror image of +x in the wall: u − 2(u·n)n.
        let mirror = [1.0 - 2.0 * n[0] * n[0], -2.0 * n[0] * n[1]];
        let moved = [c2[0] - c1[0], c2[1] - c1[1]];
        let angle = (moved[0] * mirror[0] + moved[1] * mirror[1])
            .atan2(moved[0] * mirror[1] - moved[1] * mirror[0])
            .to_degrees();
        let off = (90.0 - angle).abs();
        let speed = moved[0].hypot(moved[1]) / (t2 - t1);
        eprintln!(
            "reflected along {moved:?} at {speed:.3} m/s (group speed {group:.3}), {off:.2}° off the mirror law; energy kept {:.4}",
            e2 / e0
        );
        assert!(off < 3.0, "the packet left {off}° off the mirror direction");
        assert!((speed - group).abs() < 0.1 * group, "at {speed} m/s, group speed {group}");
        assert!(e2 / e0 > 0.9, "the wall kept {:.3} of the energy", e2 / e0);
    }

    /// Waves crossing a step from 0.8 m to 0.2 m deep at 48° keep their
    /// wave number along the step and take the |k| the dispersion relation
    /// gives at the new depth for the same frequency: they slow and bend
    /// towards the step's normal by Snell's law, sin θ₂ / c₂ = sin θ₁ / c₁.
    #[test]
    fn waves_over_a_step_slow_to_the_local_depth_and_bend_by_snells_law() {
        let (deep, shallow, cell, dt) = (0.8, 0.2, 0.2, 1.0 / 30.0);
        let mut sim = periodic(128, cell, [shallow, deep], dt);
        let size = sim.settings.grid.cells;
        let extent = size as f64 * cell;
        for j in 0..size {
            for i in 0..size {
                let x = (i as f64 + 0.5) * cell;
                sim.depth[j * size + i] = if x < 0.5 * extent { deep } else { shallow };
            }
        }
        // λ = 1.6 m, crests uniform along z with 12 waves across the
        // domain, a packet long enough (σ = 2 m) to hold one wave number.
        let tension = sim.settings.tension;
        let k1 = 2.0 * PI / 1.6;
        let kz = 2.0 * PI * 12.0 / extent;
        let kx1 = (k1 * k1 - kz * kz).sqrt();
        packet(&mut sim, [kx1, kz], deep, [6.4, 0.0], [2.0, 1e9]);
        let omega = capillary_gravity_omega(k1, deep, tension);
        // The shallow water's |k| at the same frequency (bisection).
        let (mut lo, mut hi) = (k1, 4.0 * k1);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if capillary_gravity_omega(mid, shallow, tension) < omega { lo = mid } else { hi = mid }
        }
        let k2 = 0.5 * (lo + hi);
        // Until the packet's middle is 5 m past the step.
        let cross = |k: f64, d: f64, kx: f64| capillary_gravity_group_speed(k, d, tension) * kx / k;
        let t = (0.5 * extent - 6.4) / cross(k1, deep, kx1)
            + 5.0 / cross(k2, shallow, (k2 * k2 - kz * kz).sqrt());
        for _ in 0..(t / dt).round() as usize {
            sim.step(&[]);
        }
        // Each column's amplitude of exp(i·kz·z); its phase advances at kx.
        let amplitude = |i: usize| {
            (0..size).fold((0.0, 0.0), |(re, im), j| {
                let z = (j as f64 + 0.5) * cell;
                let h = sim.height(i, j);
                (re + h * (kz * z).cos(), im - h * (kz * z).sin())
            })
        };
        let columns: Vec<(f64, f64)> = (0..size).map(amplitude).collect();
        let (mut weight, mut turned) = (0.0, 0.0);
        for i in size / 2 + 4..size - 2 {
            let (a, b) = (columns[i], columns[i + 1]);
            // arg(b·conj(a)) weighted by |a||b|.
            let (re, im) = (b.0 * a.0 + b.1 * a.1, b.1 * a.0 - b.0 * a.1);
            let w = re.hypot(im);
            turned += w * im.atan2(re);
            weight += w;
        }
        let kx2 = turned / weight / cell;
        let measured = kx2.hypot(kz);
        let theta1 = (kz / k1).asin().to_degrees();
        let theta2 = kz.atan2(kx2).to_degrees();
        let c1 = omega / k1;
        let c2 = omega / k2;
        let snell = (theta1.to_radians().sin() * c2 / c1).asin().to_degrees();
        eprintln!(
            "θ₁ {theta1:.2}°, θ₂ {theta2:.2}° (Snell {snell:.2}°); |k| {measured:.4} rad/m at 0.2 m (dispersion {k2:.4}, deep {k1:.4})"
        );
        assert!(
            (measured - k2).abs() < 0.015 * k2,
            "|k| {measured} in the shallows, dispersion gives {k2}"
        );
        assert!((theta2 - snell).abs() < 1.0, "θ₂ {theta2}°, Snell's law {snell}°");
        assert!(theta1 - theta2 > 10.0, "the waves bent towards the normal");
    }
}

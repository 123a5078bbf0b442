//! The particle pool's step (seed 003 §4.5–4.6): landings, merges and
//! each particle's update, the CPU twin of `whitewater.wgsl`'s particle
//! kernels.

use super::*;

/// Where a particle stops: what it leaves on the water.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Landing {
    pub x: f32,
    pub z: f32,
    /// Foam amount (F·m² spread over the cell it lands in).
    pub foam: f32,
    /// Spray: its downward speed (m/s) as it hits the water, which kicks
    /// the interactive water (0 for a bursting bubble).
    pub speed: f32,
}

/// Foam (F·m²) a bursting bubble leaves: its air as a film 0.1 mm thick
/// covering the area one cell of full cover would... kept simple: per
/// volume unit, so that a ball's splash leaves a ring of foam.
pub const BURST_FOAM_PER_M3: f32 = 2.0e4;
/// Foam (F·m²) one landing spray drop parcel leaves.
pub const SPRAY_FOAM: f32 = 0.004;

/// The particle system's CPU twin.
#[derive(Clone, Debug, Default)]
pub struct Particles {
    pub alive: Vec<Particle>,
    /// Particles that left the domain or failed (for the 10,000-step test).
    pub escaped: u64,
}

impl Particles {
    /// Total bubble air (volume units), including merges not yet applied.
    pub fn bubble_volume(&self) -> u64 {
        self.alive
            .iter()
            .filter(|p| p.kind == BUBBLE)
            .map(|p| p.volume as u64 + p.gained as u64)
            .sum()
    }

    /// Spawn `splashes`' particles at step `s` (ids as on the GPU).
    pub fn spawn(&mut self, splashes: &[Splash], s: &ParticleStep, capacity: usize) {
        for (i, sp) in splashes.iter().enumerate() {
            for k in 0..sp.spray + sp.bubbles {
                if self.alive.len() >= capacity {
                    return;
                }
                let id = splash_id(s.step, i as u32, k);
                self.alive.push(splash_particle(sp, k, s.step, id, s.drop_radius));
            }
        }
    }

    /// Merges (twin of `merge_pick` and `merge`): each bubble picks the
    /// touching bubble of smallest id below its own; it merges into it if
    /// that one is not itself merging; volume moves whole.
    pub fn merge(&mut self) {
        let n = self.alive.len();
        let mut target = vec![usize::MAX; n];
        for i in 0..n {
            let a = &self.alive[i];
            if a.kind != BUBBLE {
                continue;
            }
            let mut best = usize::MAX;
            for j in 0..n {
                let b = &self.alive[j];
                if j == i || b.kind != BUBBLE || b.id >= a.id {
                    continue;
                }
                if touching(a, b) && (best == usize::MAX || b.id < self.alive[best].id) {
                    best = j;
                }
            }
            target[i] = best;
        }
        for i in 0..n {
            let t = target[i];
            if t != usize::MAX && target[t] == usize::MAX {
                let v = self.alive[i].volume;
                self.alive[t].gained += v;
                self.alive[i].kind = DEAD;
            }
        }
    }

    /// Integrate every particle one step (twin of `update`) over the water
    /// `surface` (a height function will do for water without horizontal
    /// displacement). Returns what died on the water (foam).
    pub fn update(&mut self, s: &ParticleStep, surface: impl WaterSurface) -> Vec<Landing> {
        let mut landed = Vec::new();
        let mut kept = Vec::with_capacity(self.alive.len());
        for mut p in self.alive.drain(..) {
            match update_particle(&mut p, s, &surface) {
                Fate::Lives => kept.push(p),
                Fate::Lands(l) => landed.push(l),
                Fate::Escapes => self.escaped += 1,
                Fate::Merged => {}
            }
        }
        self.alive = kept;
        landed
    }
}

/// A splash particle's id: unique within a step (splash i, particle k).
pub fn splash_id(step: u32, splash: u32, k: u32) -> u32 {
    step.wrapping_mul(1 << 20).wrapping_add(splash * 1024 + k)
}

fn touching(a: &Particle, b: &Particle) -> bool {
    let d2: f32 = (0..3).map(|k| (a.position[k] - b.position[k]).powi(2)).sum();
    let r = a.radius + b.radius;
    d2 < r * r
}

/// What became of a particle in a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fate {
    Lives,
    Lands(Landing),
    Escapes,
    Merged,
}

/// One particle's step (twin of `update` in `particles.wgsl`).
pub fn update_particle(p: &mut Particle, s: &ParticleStep, surface: &impl WaterSurface) -> Fate {
    if p.kind == DEAD {
        return Fate::Merged;
    }
    let dt = s.dt;
    let newborn = p.age == 0.0;
    p.age += dt;
    if p.kind == BUBBLE {
        if p.gained > 0 {
            p.volume = p.volume.saturating_add(p.gained);
            p.gained = 0;
            p.radius = bubble_radius(p.volume);
        }
        // The water's motion here: how far the surface above moved since
        // the last step (nothing known yet in a bubble's first step).
        let mut water = [0.0f32; 3];
        if !newborn {
            let footprint = MOTION_FOOTPRINT_PER_DEPTH * (-p.position[1]).max(0.0);
            let now = surface.displacement(p.position[0], p.position[2], footprint);
            for k in 0..3 {
                water[k] = (now[k] - p.carried[k]) / dt;
            }
        }
        let rise = bubble_terminal_velocity(p.radius, s.bubble_mobility);
        let keep = (-dt / bubble_relaxation(p.radius, s.bubble_mobility)).exp();
        let target = [water[0], water[1] + rise, water[2]];
        for k in 0..3 {
            p.velocity[k] = target[k] + (p.velocity[k] - target[k]) * keep;
        }
    } else {
        let k = drop_drag(p.radius);
        let rel = [p.velocity[0] - s.wind[0], p.velocity[1], p.velocity[2] - s.wind[1]];
        let speed = (rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2]).sqrt();
        // Semi-implicit: the drag of the new velocity, so that no step overshoots.
        let damp = 1.0 / (1.0 + k * speed * dt);
        p.velocity[0] = s.wind[0] + rel[0] * damp;
        p.velocity[1] = (rel[1] - G * dt) * damp;
        p.velocity[2] = s.wind[1] + rel[2] * damp;
    }
    for k in 0..3 {
        p.position[k] += p.velocity[k] * dt;
    }
    let finite = p.position.iter().chain(&p.velocity).all(|v| v.is_finite());
    let inside = finite
        && p.position[0] >= s.low[0]
        && p.position[0] <= s.high[0]
        && p.position[2] >= s.low[1]
        && p.position[2] <= s.high[1]
        && p.age <= s.max_age;
    if !inside {
        return Fate::Escapes;
    }
    let h = surface.height(p.position[0], p.position[2]);
    if p.kind == BUBBLE {
        p.position[1] = p.position[1].max(-s.floor_depth + p.radius);
        if p.position[1] >= h {
            let foam = p.volume as f32 * VOLUME_UNIT_M3 as f32 * BURST_FOAM_PER_M3;
            return Fate::Lands(Landing { x: p.position[0], z: p.position[2], foam, speed: 0.0 });
        }
        let footprint = MOTION_FOOTPRINT_PER_DEPTH * (-p.position[1]).max(0.0);
        p.carried = surface.displacement(p.position[0], p.position[2], footprint);
    } else if p.position[1] <= h && p.velocity[1] < 0.0 {
        let (x, z, speed) = (p.position[0], p.position[2], -p.velocity[1]);
        return Fate::Lands(Landing { x, z, foam: SPRAY_FOAM, speed });
    }
    Fate::Lives
}

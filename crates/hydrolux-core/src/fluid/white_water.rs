//! White water on the volumetric liquid (issue #30's foam and spray where
//! the liquid breaks; seed 003 §4.4–4.6 foam, bubbles and splashes, §2.3
//! particle systems): diffuse particles shed where the liquid breaks,
//! after Ihmsen, Akinci, Akinci & Teschner 2012 ("Unified spray, foam and
//! air bubbles for particle-based fluids"), measured on the MAC grid
//! instead of SPH neighbourhoods. The CPU twin of the white-water kernels
//! in the renderer's `simulation/liquid/white_water.wgsl`, formula for
//! formula.
//!
//! - **Where it forms.** A liquid particle moving fast enough to entrain
//!   air ([`ENTRAINMENT_SPEED`]: plunging jets and breaking fronts draw air
//!   in from about 1 m/s, Ervine, McKeogh & Elsawy 1980; Chanson 1997)
//!   sheds in proportion to the larger of two potentials, each ramped
//!   between two thresholds as Ihmsen's Φ: *trapped air*, the shear the
//!   grid resolves, |∇×u|·h across a cell (what rolls air under), and
//!   *crest*, the speed at which the liquid leaves its own surface along
//!   the outward normal where it moves out of it (v̂·n̂ ≥ 0.6, as Ihmsen's
//!   wave crests: a crest overturning, a sheet thrown up; the normal is
//!   the negated gradient of the particle counts around it).
//! - **What it is.** By how full the 3×3×3 cells around it are (particles
//!   over what they hold, solids left out): spray below [`SPRAY_FILL`],
//!   bubbles above [`BUBBLE_FILL`], foam between (Ihmsen's neighbour
//!   counts of 6 and 20 as fractions of a full neighbourhood).
//! - **How it moves.** Spray flies ballistically with the quadratic drag
//!   of 1.5 mm drops; foam is carried by the liquid's velocity and dies
//!   after Monahan's lifetime for the water's salinity; bubbles move with
//!   the liquid plus their terminal rise speed (1 mm bubbles,
//!   `whitewater::bubble_terminal_velocity`), relaxed to it over
//!   `whitewater::bubble_relaxation`. A bubble that reaches the surface
//!   becomes foam, foam the liquid leaves becomes spray, spray that falls
//!   back becomes foam: the classification is made again every step.
//!
//! Deterministic and without atomics: liquid particle i owns
//! [`SLOTS_PER_PARTICLE`] slots and sheds into slot `step mod K` only
//! when it is empty; its chance and its jitter are the white water's
//! hash of (step, slot).

use super::flip::Liquid;
use super::grid::Cell;
use crate::whitewater::{self, random};
use bytemuck::{Pod, Zeroable};

/// Slots of the white-water pool each liquid particle owns.
pub const SLOTS_PER_PARTICLE: usize = 2;
/// Speeds (m/s) over which the energy potential ramps from 0 to 1: from
/// the onset of air entrainment the plunging liquid's landings use.
pub const ENTRAINMENT_SPEED: [f32; 2] = [whitewater::ENTRAINMENT_ONSET_SPEED, 2.5];
/// Velocity differences across a cell, |∇×u|·h (m/s), over which the
/// trapped-air potential ramps: shear the grid resolves, whatever its cell.
pub const TRAPPED_AIR_SHEAR: [f32; 2] = [0.25, 1.0];
/// Outward speeds (m/s) through the surface over which the crest
/// potential ramps, for liquid moving out of it (Ihmsen's v̂·n̂ ≥ 0.6).
pub const CREST_SPEED: [f32; 2] = [0.3, 1.5];
pub const CREST_ALIGNMENT: f32 = 0.6;
/// Fill of the 3×3×3 cells around under which a particle is spray.
pub const SPRAY_FILL: f32 = 0.15;
/// Fill over which it is a bubble.
pub const BUBBLE_FILL: f32 = 0.6;
/// The bubbles' radius (m): entrained bubbles are mostly around the Hinze
/// scale, a millimetre (Deane & Stokes 2002).
pub const BUBBLE_RADIUS: f32 = 1.0e-3;
/// Salts of the hash, one per random number drawn.
pub const SALT_CHANCE: u32 = 0x5157;
pub const SALT_JITTER: [u32; 3] = [0x5158, 0x5159, 0x515A];

/// One particle of the pool (WGSL `Diffuse`, 32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Diffuse {
    pub position: [f32; 3],
    /// `whitewater::{DEAD, BUBBLE, SPRAY, FOAM}`.
    pub kind: u32,
    pub velocity: [f32; 3],
    /// Seconds of foam left.
    pub life: f32,
}

/// The liquid's bubbles' surface mobility: it is fresh water, clean (its
/// foam lives Monahan's fresh-water time unless set), so its bubbles slip
/// (`whitewater::bubble_mobility`).
pub const LIQUID_BUBBLE_MOBILITY: f32 = 1.0;

/// How the liquid sheds white water.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WhiteWaterSettings {
    /// Particles a fully breaking liquid particle sheds per second.
    pub rate: f64,
    /// Foam's lifetime (s).
    pub foam_life: f64,
    /// Its bubbles' surface mobility (`whitewater::bubble_mobility`).
    pub bubble_mobility: f32,
    /// The liquid's particles per cell (what a full cell holds).
    pub particles_per_cell: f64,
}

/// Ihmsen's clamped ramp Φ(I, τmin, τmax): 0 below τmin, 1 above τmax.
pub fn ramp(value: f32, [lo, hi]: [f32; 2]) -> f32 {
    ((value.min(hi) - value.min(lo)) / (hi - lo)).clamp(0.0, 1.0)
}

/// What a particle is where the cells around it are `fill` full.
pub fn classify(fill: f32) -> u32 {
    if fill < SPRAY_FILL {
        whitewater::SPRAY
    } else if fill > BUBBLE_FILL {
        whitewater::BUBBLE
    } else {
        whitewater::FOAM
    }
}

/// The chance (0–1) a liquid particle sheds one diffuse particle in a step
/// of `dt`: rate × Φ_energy × max(Φ_trapped air, Φ_crest) × dt, from its
/// speed, the shear across its cell (m/s) and its outward speed.
pub fn shed_chance(speed: f32, shear: f32, outward: f32, rate: f32, dt: f32) -> f32 {
    let breaking = ramp(shear, TRAPPED_AIR_SHEAR).max(ramp(outward, CREST_SPEED));
    (rate * dt * ramp(speed, ENTRAINMENT_SPEED) * breaking).min(1.0)
}

/// What the pool's motion needs of the liquid's water.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    pub gravity: [f32; 3],
    pub dt: f32,
    /// The spray drops' quadratic drag (1/m), the bubbles' terminal rise
    /// (m/s) and the time they take to reach it (s).
    pub drag: f32,
    pub rise: f32,
    pub relaxation: f32,
}

impl Motion {
    pub fn new(gravity: [f64; 3], dt: f64, bubble_mobility: f32) -> Self {
        Motion {
            gravity: gravity.map(|g| g as f32),
            dt: dt as f32,
            drag: whitewater::drop_drag(whitewater::SPRAY_DROP_RADIUS),
            rise: whitewater::bubble_terminal_velocity(BUBBLE_RADIUS, bubble_mobility),
            relaxation: whitewater::bubble_relaxation(BUBBLE_RADIUS, bubble_mobility),
        }
    }
}

/// One step of a live particle of kind `kind` (already classified where it
/// is): its new velocity and position. `fluid` is the liquid's velocity
/// there.
pub fn advance(d: &mut Diffuse, fluid: [f32; 3], m: &Motion) {
    let v = d.velocity;
    let next = match d.kind {
        whitewater::SPRAY => {
            let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            [0, 1, 2].map(|a| v[a] + (m.gravity[a] - m.drag * speed * v[a]) * m.dt)
        }
        whitewater::BUBBLE => {
            let keep = (-m.dt / m.relaxation).exp();
            let target = [fluid[0], fluid[1] + m.rise, fluid[2]];
            [0, 1, 2].map(|a| target[a] + (v[a] - target[a]) * keep)
        }
        _ => fluid,
    };
    d.velocity = next;
    d.position = [0, 1, 2].map(|a| d.position[a] + next[a] * m.dt);
    if d.kind == whitewater::FOAM {
        d.life -= m.dt;
    }
}

/// The liquid's white water: the pool and how it sheds.
#[derive(Clone, Debug, PartialEq)]
pub struct WhiteWater {
    pub settings: WhiteWaterSettings,
    /// [`SLOTS_PER_PARTICLE`] per liquid particle slot.
    pub pool: Vec<Diffuse>,
}

impl WhiteWater {
    pub fn new(settings: WhiteWaterSettings, particles: usize) -> Self {
        WhiteWater { settings, pool: vec![Diffuse::default(); particles * SLOTS_PER_PARTICLE] }
    }

    /// The live particles of `kind`.
    pub fn count(&self, kind: u32) -> usize {
        self.pool.iter().filter(|d| d.kind == kind).count()
    }
}

impl Liquid {
    /// Particles per cell, as the splat counted them this step.
    pub(crate) fn cell_counts(&self) -> Vec<u32> {
        let mut counts = vec![0u32; self.grid.cells.len()];
        for i in (0..self.positions.len()).filter(|i| self.alive[*i]) {
            let [x, y, z] = self.cell_of(self.positions[i]);
            counts[self.grid.cell(x, y, z)] += 1;
        }
        counts
    }

    /// How full (0–1) the 3×3×3 cells around `p` are, and the outward
    /// normal there (not normalised; zero inside a uniform block).
    pub fn fill_at(&self, counts: &[u32], per_cell: f64, p: [f64; 3]) -> (f64, [f64; 3]) {
        let g = &self.grid;
        let c = [0, 1, 2].map(|a| ((p[a] - g.origin[a]) / g.h).floor() as i64);
        let (mut sum, mut room) = (0.0, 0.0);
        let mut gradient = [0.0; 3];
        for k in 0..27 {
            let d = [k % 3 - 1, (k / 3) % 3 - 1, k / 9 - 1].map(|x| x as i64);
            let at = [0, 1, 2].map(|a| c[a] + d[a]);
            if g.cell_at(at) == Cell::Solid {
                continue;
            }
            let inside = (0..3).all(|a| at[a] >= 0 && at[a] < g.n[a] as i64);
            let n = if inside {
                counts[g.cell(at[0] as usize, at[1] as usize, at[2] as usize)] as f64
            } else {
                0.0
            };
            sum += n;
            room += per_cell;
            for a in 0..3 {
                gradient[a] -= n * d[a] as f64;
            }
        }
        let fill = if room > 0.0 { (sum / room).min(1.0) } else { 1.0 };
        (fill, gradient)
    }

    /// |∇×u| at `p` by central differences a cell apart.
    pub fn vorticity_at(&self, p: [f64; 3]) -> f64 {
        let g = &self.grid;
        let h = g.h;
        let at = |a: usize, s: f64| {
            let mut q = p;
            q[a] += s * h;
            g.velocity(q)
        };
        let d = |a: usize, b: usize| (at(b, 1.0)[a] - at(b, -1.0)[a]) / (2.0 * h);
        let w = [d(2, 1) - d(1, 2), d(0, 2) - d(2, 0), d(1, 0) - d(0, 1)];
        (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt()
    }

    /// The white water's step, after the liquid's own (`counts` as the
    /// splat counted the cells; `step` the step's index): the pool moves,
    /// then the breaking particles shed into their empty slots.
    pub(crate) fn white_water_step(&mut self, counts: &[u32], dt: f64, step: u64) {
        let Some(mut ww) = self.white_water.take() else { return };
        let s = ww.settings;
        let motion = Motion::new(self.settings.gravity, dt, s.bubble_mobility);
        let g = &self.grid;
        let top = [0, 1, 2].map(|a| g.origin[a] + g.n[a] as f64 * g.h);
        for d in ww.pool.iter_mut().filter(|d| d.kind != whitewater::DEAD) {
            let p = d.position.map(|c| c as f64);
            let (fill, _) = self.fill_at(counts, s.particles_per_cell, p);
            d.kind = classify(fill as f32);
            let fluid = self.grid.velocity(p).map(|c| c as f32);
            advance(d, fluid, &motion);
            let q = d.position.map(|c| c as f64);
            let outside = (0..3).any(|a| q[a] < g.origin[a] || q[a] > top[a]);
            let solid = !outside
                && g.cells[{
                    let [x, y, z] = self.cell_of(q);
                    g.cell(x, y, z)
                }] == Cell::Solid;
            let landed = self.surface.is_some_and(|l| q[1] < l.level);
            if outside || solid || landed || (d.kind == whitewater::FOAM && d.life <= 0.0) {
                *d = Diffuse::default();
            }
        }
        let step = step as u32;
        let k = SLOTS_PER_PARTICLE;
        for i in (0..self.positions.len()).filter(|i| self.alive[*i]) {
            let slot = i * k + step as usize % k;
            if ww.pool[slot].kind != whitewater::DEAD {
                continue;
            }
            let p = self.positions[i];
            let v = self.velocities[i].map(|c| c as f32);
            let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if speed < ENTRAINMENT_SPEED[0] {
                continue;
            }
            let (fill, normal) = self.fill_at(counts, s.particles_per_cell, p);
            let length =
                (normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]).sqrt();
            let mut outward = 0.0;
            if fill < BUBBLE_FILL as f64 && length > 0.0 {
                let along = ((0..3).map(|a| v[a] as f64 * normal[a]).sum::<f64>() / length) as f32;
                if along >= CREST_ALIGNMENT * speed {
                    outward = along;
                }
            }
            let shear = (self.vorticity_at(p) * self.grid.h) as f32;
            let chance = shed_chance(speed, shear, outward, s.rate as f32, dt as f32);
            if random(step, slot as u32, SALT_CHANCE) >= chance {
                continue;
            }
            // Anywhere in the particle's share of its cell.
            let spacing = self.grid.h / s.particles_per_cell.cbrt();
            let at = [0, 1, 2].map(|a| {
                (p[a] + (random(step, slot as u32, SALT_JITTER[a]) as f64 - 0.5) * spacing) as f32
            });
            let (fill, _) = self.fill_at(counts, s.particles_per_cell, at.map(|c| c as f64));
            ww.pool[slot] = Diffuse {
                position: at,
                kind: classify(fill as f32),
                velocity: v,
                life: s.foam_life as f32,
            };
        }
        self.white_water = Some(ww);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fluid::{LiquidSettings, MacGrid};

    fn settings() -> WhiteWaterSettings {
        WhiteWaterSettings {
            rate: 200.0,
            foam_life: 2.54,
            bubble_mobility: 1.0,
            particles_per_cell: 8.0,
        }
    }

    /// A closed tank of `n` cells of `h` m with its lower `fill` metres
    /// liquid, at rest, shedding white water.
    fn tank(n: [usize; 3], h: f64, block: [f64; 3]) -> Liquid {
        let mut liquid = Liquid::new(MacGrid::new(n, h, [0.0; 3]), LiquidSettings::default());
        liquid.fill_box([0.0; 3], block, 2);
        liquid.white_water = Some(WhiteWater::new(settings(), liquid.positions.len()));
        liquid
    }

    #[test]
    fn the_potentials_ramp_and_the_kinds_split_by_fill() {
        assert_eq!(ramp(0.5, [0.8, 2.5]), 0.0);
        assert_eq!(ramp(3.0, [0.8, 2.5]), 1.0);
        assert!((ramp(1.65, [0.8, 2.5]) - 0.5).abs() < 1e-6);
        assert_eq!(classify(0.05), whitewater::SPRAY);
        assert_eq!(classify(0.4), whitewater::FOAM);
        assert_eq!(classify(0.9), whitewater::BUBBLE);
        // Slow water sheds nothing however it swirls; fast breaking water
        // sheds at the full rate.
        assert_eq!(shed_chance(0.5, 5.0, 5.0, 200.0, 0.01), 0.0);
        assert!((shed_chance(3.0, 5.0, 0.0, 50.0, 0.01) - 0.5).abs() < 1e-6);
        assert_eq!(shed_chance(3.0, 0.0, 0.0, 50.0, 0.01), 0.0);
    }

    #[test]
    fn spray_falls_to_the_terminal_speed_of_its_drops() {
        // v_t = √(g/k), k = 3·ρa·Cd/(8·ρw·r): 8.3 m/s for 1.5 mm drops.
        let m = Motion::new([0.0, -9.81, 0.0], 1.0 / 240.0, 1.0);
        let expected = (9.81 / m.drag).sqrt();
        assert!((expected - 8.34).abs() < 0.05, "{expected}");
        let mut d = Diffuse { kind: whitewater::SPRAY, ..Diffuse::default() };
        for _ in 0..(8.0 * 240.0) as usize {
            advance(&mut d, [0.0; 3], &m);
        }
        assert!((-d.velocity[1] - expected).abs() < 0.01 * expected, "{:?}", d.velocity);
        // Early on it falls as a projectile: ½gt² in the first 0.1 s.
        let mut d = Diffuse { kind: whitewater::SPRAY, ..Diffuse::default() };
        for _ in 0..24 {
            advance(&mut d, [0.0; 3], &m);
        }
        let fall = -d.position[1];
        assert!((fall - 0.5 * 9.81 * 0.01).abs() < 0.004, "fell {fall} m");
    }

    #[test]
    fn a_bubble_in_still_water_rises_at_its_terminal_speed_and_becomes_foam() {
        // A tank 0.4 m deep at rest: a bubble 0.3 m down rises at a 2 mm
        // bubble's 0.29 m/s in clean fresh water (Mendelson's wobbling
        // regime; 0.30–0.35 measured by Duineveld 1995), in ~1 s, and
        // turns to foam at the surface, where it stays.
        let mut liquid = tank([4, 8, 4], 0.1, [0.4, 0.4, 0.4]);
        liquid.white_water.as_mut().expect("on").settings.rate = 0.0;
        let rise = whitewater::bubble_terminal_velocity(BUBBLE_RADIUS, 1.0);
        assert!((rise - 0.29).abs() < 0.02, "{rise}");
        liquid.white_water.as_mut().expect("on").pool[0] = Diffuse {
            position: [0.2, 0.1, 0.2],
            kind: whitewater::BUBBLE,
            velocity: [0.0; 3],
            life: 2.54,
        };
        let dt = 1.0 / 120.0;
        for _ in 0..60 {
            liquid.step(dt);
        }
        let d = liquid.white_water.as_ref().expect("on").pool[0];
        assert_eq!(d.kind, whitewater::BUBBLE, "{d:?}");
        // 0.5 s at 0.29 m/s less the ~15 ms it takes to reach it.
        let risen = d.position[1] - 0.1;
        let expected = rise * (0.5 - whitewater::bubble_relaxation(BUBBLE_RADIUS, 1.0));
        assert!((risen - expected).abs() < 0.01, "rose {risen} m, expected {expected} m");
        for _ in 0..120 {
            liquid.step(dt);
        }
        let d = liquid.white_water.as_ref().expect("on").pool[0];
        assert_eq!(d.kind, whitewater::FOAM, "{d:?}");
        assert!((d.position[1] - 0.4).abs() < 0.1, "foam at {} m", d.position[1]);
    }

    #[test]
    fn foam_on_still_water_stays_put_and_lasts_its_lifetime() {
        let mut liquid = tank([4, 8, 4], 0.1, [0.4, 0.4, 0.4]);
        let ww = liquid.white_water.as_mut().expect("on");
        ww.settings.foam_life = 0.5;
        ww.pool[0] = Diffuse {
            // Just over the top cell of liquid (its particles' top is at
            // 0.375 m): the cells around it a third full.
            position: [0.2, 0.405, 0.2],
            kind: whitewater::FOAM,
            velocity: [0.0; 3],
            life: 0.5,
        };
        let dt = 1.0 / 120.0;
        for _ in 0..59 {
            liquid.step(dt);
        }
        let d = liquid.white_water.as_ref().expect("on").pool[0];
        assert_eq!(d.kind, whitewater::FOAM, "{d:?}");
        let moved = ((d.position[0] - 0.2).powi(2) + (d.position[1] - 0.405).powi(2)).sqrt();
        assert!(moved < 1e-3, "moved {moved} m");
        // Gone within a step of its 0.5 s.
        liquid.step(dt);
        liquid.step(dt);
        let d = liquid.white_water.as_ref().expect("on").pool[0];
        assert_eq!(d.kind, whitewater::DEAD, "{d:?}");
    }

    #[test]
    fn still_water_sheds_nothing_and_a_breaking_dam_sheds_all_three() {
        let dt = 1.0 / 240.0;
        let mut still = tank([8, 8, 2], 0.05, [0.4, 0.2, 0.1]);
        for _ in 0..60 {
            still.step(dt);
        }
        let ww = still.white_water.as_ref().expect("on");
        assert!(ww.pool.iter().all(|d| d.kind == whitewater::DEAD));
        // A column 0.4 m high collapsing: its front runs into the far wall
        // at over 2 m/s and throws up a sheet that breaks into spray.
        let mut dam = tank([16, 12, 2], 0.05, [0.2, 0.4, 0.1]);
        let mut seen = [0usize; 4];
        for _ in 0..(1.0 / dt) as usize {
            dam.step(dt);
            let ww = dam.white_water.as_ref().expect("on");
            for kind in [whitewater::BUBBLE, whitewater::SPRAY, whitewater::FOAM] {
                seen[kind as usize] = seen[kind as usize].max(ww.count(kind));
            }
        }
        assert!(seen[1] > 0 && seen[2] > 0 && seen[3] > 0, "bubbles, spray, foam: {seen:?}");
        let ww = dam.white_water.as_ref().expect("on");
        let g = &dam.grid;
        let inside = ww.pool.iter().filter(|d| d.kind != whitewater::DEAD).all(|d| {
            (0..3).all(|a| {
                d.position[a] as f64 >= g.origin[a]
                    && d.position[a] as f64 <= g.origin[a] + g.n[a] as f64 * g.h
            })
        });
        assert!(inside, "a white-water particle left the closed tank");
    }
}

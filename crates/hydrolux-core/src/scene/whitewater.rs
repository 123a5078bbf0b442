//! White water's settings (`[whitewater]`, seed 003 §4.4–4.6): the foam
//! field, and the particle pool shared by bubbles and spray. The physics is
//! `crate::whitewater`.

use super::rules::range;
use super::{CLOCK_HZ, Quality, Scene, SceneError, WaterModel};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WhitewaterDesc {
    /// Foam that lives on the surface (breaking crests, wakes, splashes).
    pub foam: bool,
    /// Bubbles and spray.
    pub particles: bool,
    /// Foam cells per side (a power of two, 32 to 1024).
    pub resolution: u32,
    /// Side (m) of the foam's square window around the camera; 0 = the
    /// interactive water's domain where there is interactive water, else
    /// 256 m. An FFT ocean without interactive water tiles its foam with
    /// the ocean's patch instead (see `Scene::foam_tiles`).
    pub extent: f32,
    /// Foam lifetime τ (s); 0 = from `water.salinity` (Monahan: 3.85 s in
    /// sea water, 2.54 s in fresh water).
    pub life: f32,
    /// Most particles alive at once (1024 to 4194304; the quality tier caps it).
    pub budget: u32,
    /// Simulation steps per second (a divisor of the clock's 120 Hz).
    pub rate: u32,
    /// How far back (s) a jump in time is simulated from: older foam has
    /// decayed (e^(−memory/τ)) and older particles have landed.
    pub memory: f32,
    /// Spray and bubble particles per second born from a fully breaking
    /// square metre of sea.
    pub spray_rate: f32,
    pub bubble_rate: f32,
    /// Drawn size (m) of a spray parcel and of a bubble cloud particle.
    pub spray_size: f32,
    pub bubble_size: f32,
    /// Water in a spray parcel, by volume (0.01: dense spray by a splash or
    /// a breaking crest; spume blown off a crest is thinner). With the
    /// parcel's size it sets how many drops it holds, how much water lands
    /// with it, and how much light it stops.
    pub spray_water: f32,
}

impl Default for WhitewaterDesc {
    fn default() -> Self {
        WhitewaterDesc {
            foam: true,
            particles: true,
            resolution: 256,
            extent: 0.0,
            life: 0.0,
            budget: 262_144,
            rate: 20,
            memory: 12.0,
            spray_rate: 2.0,
            bubble_rate: 2.0,
            spray_size: 0.06,
            bubble_size: 0.012,
            spray_water: crate::coupling::SPRAY_LIQUID_FRACTION as f32,
        }
    }
}

impl WhitewaterDesc {
    /// This section as quality tier `q` renders it ([`Quality::apply`]).
    pub fn apply_quality(&mut self, q: Quality) {
        match q {
            Quality::Low => {
                self.resolution = self.resolution.min(128);
                self.budget = self.budget.min(16_384);
                self.memory = self.memory.min(6.0);
                self.rate = self.rate.min(10);
            }
            Quality::Medium => self.budget = self.budget.min(65_536),
            Quality::Ultra => {
                self.budget = self.budget.max(1 << 20);
                self.resolution = self.resolution.max(512);
            }
            Quality::High | Quality::Auto => {}
        }
    }

    pub fn validate(&self) -> Result<(), SceneError> {
        let w = self;
        if !(32..=1024).contains(&w.resolution) || !w.resolution.is_power_of_two() {
            return Err(SceneError::OutOfRange {
                key: "whitewater.resolution".into(),
                value: w.resolution.to_string(),
                allowed: "must be a power of two from 32 to 1024".into(),
            });
        }
        range(
            "whitewater.extent",
            w.extent,
            (0.0..=10_000.0).contains(&w.extent),
            "must be 0 (automatic) to 10000 m",
        )?;
        range(
            "whitewater.life",
            w.life,
            (0.0..=600.0).contains(&w.life),
            "must be 0 (from water.salinity) to 600 s",
        )?;
        if !(1024..=4_194_304).contains(&w.budget) {
            return Err(SceneError::OutOfRange {
                key: "whitewater.budget".into(),
                value: w.budget.to_string(),
                allowed: "must be 1024 to 4194304 particles".into(),
            });
        }
        if w.rate == 0 || !CLOCK_HZ.is_multiple_of(w.rate) {
            return Err(SceneError::OutOfRange {
                key: "whitewater.rate".into(),
                value: w.rate.to_string(),
                allowed:
                    "must divide 120 (1, 2, 3, 4, 5, 6, 8, 10, 12, 15, 20, 24, 30, 40, 60, 120)"
                        .into(),
            });
        }
        range(
            "whitewater.memory",
            w.memory,
            (0.0..=120.0).contains(&w.memory),
            "must be 0 to 120 s",
        )?;
        for (key, v) in
            [("whitewater.spray_rate", w.spray_rate), ("whitewater.bubble_rate", w.bubble_rate)]
        {
            range(key, v, (0.0..=1000.0).contains(&v), "must be 0 to 1000 per m² per s")?;
        }
        for (key, v) in
            [("whitewater.spray_size", w.spray_size), ("whitewater.bubble_size", w.bubble_size)]
        {
            range(key, v, v > 0.0 && v <= 10.0, "must be in (0, 10] m")?;
        }
        range(
            "whitewater.spray_water",
            w.spray_water,
            w.spray_water > 0.0 && w.spray_water <= 0.1,
            "must be in (0, 0.1] (water's share of a spray parcel's volume)",
        )?;
        Ok(())
    }
}

impl Scene {
    /// Whether the scene has white water to simulate: foam or particles on
    /// water that moves (waves, the interactive water or moving bodies).
    pub fn has_whitewater(&self) -> bool {
        let w = &self.whitewater;
        let moving = matches!(self.water.model, WaterModel::Fft | WaterModel::Sines)
            || self.water.dynamic
            || self.objects.iter().any(|o| o.moving());
        self.has_water() && (w.foam || w.particles) && moving
    }

    /// Foam lifetime τ (s): `whitewater.life`, or Monahan's by salinity.
    pub fn foam_life(&self) -> f32 {
        match self.whitewater.life {
            0.0 => crate::whitewater::foam_life(self.water.salinity as f64) as f32,
            l => l,
        }
    }

    /// Whether the foam field tiles the plane with the FFT ocean's patch
    /// (its whitecaps repeat as the waves do). Only an ocean without
    /// interactive water: a wake or a splash is foam at one place, and in
    /// a tiling field it came back every patch across the sea (the far
    /// "white ovals" under `wake`'s 3.5 m/s breeze, which raises almost no
    /// whitecaps: Monahan's cover there is 0.03%). With interactive water
    /// the foam's window is its domain and follows it.
    pub fn foam_tiles(&self) -> bool {
        self.water.model == WaterModel::Fft && !self.has_interactive_water()
    }

    /// Side (m) of the foam's window (when it does not tile).
    pub fn foam_extent(&self) -> f32 {
        match self.whitewater.extent {
            0.0 if self.has_interactive_water() => self.ripples.extent,
            0.0 => 256.0,
            e => e,
        }
    }
}

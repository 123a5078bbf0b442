//! What one simulation hands another within a batch of steps, declared
//! here so that neither side owns the other's types: the interactive water
//! (`ripples`) hands the white water the splashes its drops and bodies make
//! and where its window is; the physics of each hand-over is the core's
//! (`hydrolux_core::whitewater::{drop_splash, body_splash}`).

use hydrolux_core::coupling::{BodyMove, Drop};
use hydrolux_core::whitewater::{Splash, body_splash, drop_splash};

/// The hand-overs of one batch of steps.
#[derive(Default)]
pub(crate) struct Couplings {
    /// Splashes made by the steps followed since the white water's last
    /// step, in step order (what is left after a batch is the white
    /// water's to keep for its next step).
    pub splashes: Vec<Splash>,
    /// Centre (m, x z) of the interactive water's window after its last
    /// step (`None`: no interactive water): the foam window follows it.
    pub water_centre: Option<[f32; 2]>,
}

impl Couplings {
    /// The splashes of one step of the interactive water (of `dt` s): its
    /// drops' and its bodies' moves'.
    pub fn add_step(&mut self, drops: &[Drop], moves: &[BodyMove], dt: f64) {
        self.splashes.extend(drops.iter().filter_map(drop_splash));
        self.splashes.extend(moves.iter().filter_map(|m| body_splash(m, dt)));
    }
}

//! One module per pass, in frame order: ocean (simulate) → sky (bake,
//! background) → water → tonemap; probe answers queries outside the frame.

pub mod mips;
pub mod ocean;
pub mod probe;
pub mod sky;
pub mod tonemap;
pub mod water;

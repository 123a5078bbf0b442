// One path of light through a medium, drawn as a god-ray ribbon: a photon
// in the water (passes/godrays) or sunlight leaving a refractive object
// (passes/water_object). Twin: hydrolux_core::godrays::BeamTube; Rust
// layout: passes::godrays::TUBE_BYTES.

struct Tube {
    // xyz where it starts, w length (m).
    start: vec4<f32>,
    // xyz unit direction, w flux relative to the sun's irradiance (m²; 0: none).
    dir: vec4<f32>,
    // rgb colour of its light (what absorption left), w unused.
    tint: vec4<f32>,
}

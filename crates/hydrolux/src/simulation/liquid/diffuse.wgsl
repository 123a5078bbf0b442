// One particle of the liquid's white-water pool (Rust:
// `hydrolux_core::fluid::white_water::Diffuse`), as its step writes them
// (white_water.wgsl) and its draw reads them (white_water_draw.wgsl).
struct Diffuse {
    position: vec3<f32>,
    // PARTICLE_DEAD, PARTICLE_BUBBLE, PARTICLE_SPRAY, PARTICLE_FOAM.
    kind: u32,
    velocity: vec3<f32>,
    // Seconds of foam left.
    life: f32,
}

// One of the volumetric liquid's marker particles (liquid.wgsl; Rust:
// `LiquidParticle`), as the step writes them and the draws read them.
struct LiquidParticle {
    position: vec3<f32>,
    // 1 while the slot holds liquid (a nozzle's slots wait empty; a drain
    // empties them).
    alive: u32,
    velocity: vec3<f32>,
    _pad1: f32,
}

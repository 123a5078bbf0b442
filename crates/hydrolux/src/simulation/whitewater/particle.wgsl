// One particle of the white-water pool, laid out as hydrolux-core's
// `whitewater::Particle` (checked by size against naga), shared by the
// simulation (whitewater.wgsl) and the draw (particles.wgsl).
// Kinds: PARTICLE_DEAD, PARTICLE_BUBBLE, PARTICLE_SPRAY (generated from the core's).
#import modes
struct Particle {
    position: vec3<f32>,
    radius: f32,
    velocity: vec3<f32>,
    kind: u32,
    id: u32,
    age: f32,
    volume: u32,
    gained: u32,
    // Bubbles: where the surface above was displaced to when last looked
    // at, from here (the next step's water motion).
    carried: vec3<f32>,
    pad: u32,
}


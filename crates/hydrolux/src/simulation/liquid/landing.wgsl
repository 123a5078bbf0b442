// The volumetric liquid's landings in the interactive water (issue #29):
// a particle that falls under the water's mean level becomes that water.
// The liquid's `advance` appends them to the log after its solve state
// (liquid.wgsl `LiquidState`); the interactive water's `land_liquid`
// (ripples.wgsl) takes each in the water step that covers its clock step,
// the white water's `plunge` (whitewater.wgsl) in its own step.
// Twin: hydrolux_core::fluid::Landing.
//
// The log's layout in the liquid's state buffer (bytes): the solve state
// (0..32), the water's indirect dispatch over the log (32..44), the count
// (44..48), then the landings.

struct Landing {
    // World (x, z) where it fell under the level (m).
    position: vec2<f32>,
    // Its downward speed there (m/s).
    down_speed: f32,
    // The clock step it landed in.
    step: u32,
}

// The log as a reader binds the liquid's state buffer.
struct LandingLog {
    solve: array<u32, 8>,
    dispatch: array<u32, 3>,
    count: u32,
    landings: array<Landing>,
}

// Threads per workgroup of the water's pass over the log.
const LANDING_WG: u32 = 64u;

// What ray tracing reads (passes/raytrace): the ground and the water
// surface as heightfields (shaders/heightfield_trace.wgsl), and the ground's
// material for shading where a ray hits it.
#import heightfield_trace

struct TracedParams {
    ground: Heightfield,
    water: Heightfield,
    // rgb the ground's albedo, w its pattern's tile size (m)
    ground_albedo: vec4<f32>,
    // rgb the pattern's second colour, w the pattern (0 none, 1 tiles, 2 checker)
    ground_pattern: vec4<f32>,
    // x 1 if there is ground, y the furthest a ray is traced (m)
    flags: vec4<f32>,
}

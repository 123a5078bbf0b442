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

// An object traced as its unit primitive (box [−½, ½]³, sphere of radius ½,
// cylinder of radius ½ and height 1 along y), transformed.
struct TracedObject {
    inverse_model: mat4x4<f32>,
    // rgb albedo, w the pattern's tile size (m)
    albedo: vec4<f32>,
    // rgb the pattern's second colour, w the pattern (0 none, 1 tiles, 2 checker)
    pattern: vec4<f32>,
    // x the shape: PRIMITIVE_SPHERE, PRIMITIVE_BOX, PRIMITIVE_CYLINDER (ray_primitive.wgsl)
    shape: vec4<u32>,
}

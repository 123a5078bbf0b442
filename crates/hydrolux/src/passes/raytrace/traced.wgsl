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
    // x 1 if there is ground, y the furthest a ray is traced (m), z the
    // traced objects
    flags: vec4<f32>,
    // The traced caustics' window (caustics.wgsl): xy world (x, z) of its
    // corner, z its cell (m), w cells per side (0: off)
    caustics: vec4<f32>,
    // Their photons: xy the rest position of the first one's cell corner,
    // z the spacing (m), w the energy of one in units of a cell's
    // (spacing² / cell²)
    emission: vec4<f32>,
    // x, y photons per row and column
    emission_count: vec4<u32>,
}

// An object traced as its unit primitive (box [−½, ½]³, sphere of radius ½,
// cylinder of radius ½ and height 1 along y), transformed.
struct TracedObject {
    inverse_model: mat4x4<f32>,
    // rgb albedo, w the pattern's tile size (m)
    albedo: vec4<f32>,
    // rgb the pattern's second colour, w the pattern (0 none, 1 tiles, 2 checker)
    pattern: vec4<f32>,
    // x the shape: PRIMITIVE_SPHERE, PRIMITIVE_BOX, PRIMITIVE_CYLINDER
    // (ray_primitive.wgsl) or TRACED_PLANE (traced_hits.wgsl)
    shape: vec4<u32>,
}

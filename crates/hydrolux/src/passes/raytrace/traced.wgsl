// What ray tracing reads (passes/raytrace): the ground and the water
// surface as heightfields (shaders/heightfield_trace.wgsl), and the ground's
// material for shading where a ray hits it.
#import heightfield_trace

struct TracedParams {
    ground: Heightfield,
    water: Heightfield,
    // The ground's albedo and its pattern's tile size (m).
    ground_albedo: vec3<f32>,
    ground_tile_size: f32,
    // The pattern's second colour, and the pattern (PATTERN_*).
    ground_pattern_color: vec3<f32>,
    ground_pattern: u32,
    // 1 if there is ground, the furthest a ray is traced (m), the traced objects.
    has_ground: u32,
    reach: f32,
    object_count: u32,
    // The ground's specular parameters (shaders/pbr.wgsl's Material).
    ground_roughness: f32,
    // The traced caustics' window (caustics.wgsl): world (x, z) of its
    // corner, its cell (m), cells per side (0: off).
    caustic_corner: vec2<f32>,
    caustic_cell: f32,
    caustic_cells: u32,
    // Their photons: the rest position of the first one's cell corner, the
    // spacing (m), the energy of one in units of a cell's (spacing² / cell²).
    emission_origin: vec2<f32>,
    emission_spacing: f32,
    photon_energy: f32,
    // Photons per row and column.
    emission_count: vec2<u32>,
    ground_metalness: f32,
    ground_specular: f32,
}

// An object traced as its unit primitive (box [−½, ½]³, sphere of radius ½,
// cylinder of radius ½ and height 1 along y), transformed.
struct TracedObject {
    inverse_model: mat4x4<f32>,
    // Albedo, and the pattern's tile size (m).
    albedo: vec3<f32>,
    tile_size: f32,
    // The pattern's second colour, and the pattern (PATTERN_*).
    pattern_color: vec3<f32>,
    pattern: u32,
    // The shape: PRIMITIVE_SPHERE, PRIMITIVE_BOX, PRIMITIVE_CYLINDER
    // (ray_primitive.wgsl), PRIMITIVE_PLANE or PRIMITIVE_MESH
    // (traced_hits.wgsl).
    shape: u32,
    // A mesh's tree and triangles in `traced_meshes` (vec4 indices): its
    // nodes (two each) and its triangles (three corners each).
    mesh_nodes: u32,
    mesh_triangles: u32,
    // Its specular parameters (shaders/pbr.wgsl's Material).
    roughness: f32,
    metalness: f32,
    specular: f32,
    // Its place among frame.occlusion's occluders (none: 0xffffffff).
    occluder: u32,
    _pad1: u32,
}

// Inputs shared by the geometry pass's colour and shadow shaders.

struct View {
    view_proj: mat4x4<f32>,
    // Kept where dot(clip_plane.xyz, world) + clip_plane.w ≥ 0.
    clip_plane: vec4<f32>,
    // The view's eye (m): the reflection's is mirrored below the water plane.
    eye: vec3<f32>,
    _pad0: f32,
}

struct Object {
    model: mat4x4<f32>,
    // Inverse-transpose of the model's upper 3×3, as columns.
    normal_matrix: mat3x3<f32>,
    albedo: vec3<f32>,
    // Texture coordinate scale.
    uv_scale: f32,
    // Second pattern colour (grout), and the tile size (m).
    pattern_color: vec3<f32>,
    tile_size: f32,
    // Pattern (0 none, 1 tiles, 2 checker); index of refraction (0: opaque).
    pattern: u32,
    ior: f32,
    // Specular parameters (shaders/pbr.wgsl's Material).
    roughness: f32,
    metalness: f32,
    specular: f32,
    // Its place among frame.occlusion's occluders (none: 0xffffffff).
    occluder: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(1) @binding(0) var<uniform> view: View;
@group(2) @binding(0) var<uniform> object: Object;
@group(2) @binding(1) var albedo_tex: texture_2d<f32>;
@group(2) @binding(2) var albedo_sampler: sampler;

struct VsIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
}


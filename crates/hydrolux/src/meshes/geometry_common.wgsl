// Inputs shared by the geometry pass's colour and shadow shaders.

struct View {
    view_proj: mat4x4<f32>,
    // Kept where dot(clip_plane.xyz, world) + clip_plane.w ≥ 0.
    clip_plane: vec4<f32>,
}

struct Object {
    model: mat4x4<f32>,
    // Inverse-transpose of the model's upper 3×3, as columns.
    normal_matrix: mat3x3<f32>,
    // rgb albedo; w texture coordinate scale.
    albedo: vec4<f32>,
    // rgb second pattern colour (grout); w tile size (m).
    pattern_color: vec4<f32>,
    // x pattern (0 none, 1 tiles, 2 checker).
    flags: vec4<u32>,
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


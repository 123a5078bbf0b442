// Bake the sky-view table (either model) into an environment cube map
// (seed 000 §3.1.2): radiance in kcd/m², no sun disk (the sun is added
// analytically).
#import constants, sky_model, atmosphere

@group(0) @binding(0) var<uniform> sky: SkyParams;
@group(0) @binding(1) var cube_out: texture_storage_2d_array<rgba16float, write>;
@group(0) @binding(2) var sky_view: texture_2d<f32>;
@group(0) @binding(3) var sky_view_sampler: sampler;

@compute @workgroup_size(8, 8, 1)
fn bake(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(cube_out);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let u = 2.0 * (f32(id.x) + 0.5) / f32(size.x) - 1.0;
    let v = 2.0 * (f32(id.y) + 0.5) / f32(size.y) - 1.0;
    let dir = cube_direction(id.z, u, v);
    textureStore(cube_out, vec2<i32>(id.xy), i32(id.z), vec4<f32>(sky_from_view_table(sky_view, sky_view_sampler, sky, dir), 1.0));
}

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

// The cube's smaller levels: the sky filtered for the specular lobes of
// rough surfaces (issue #32 item 1; Karis, *Real Shading in Unreal Engine
// 4*, 2013). Level k holds roughness k / (SPECULAR_LEVELS − 1) (levels past
// them roughness 1): the sky over GGX's lobe about the texel's direction r,
// taken as normal and view alike, weighted by n·l — PREFILTER_SAMPLES
// Hammersley directions at level 1, doubled per level up to 1024 (wider
// lobes, fewer texels), read straight from the smooth sky-view table, not
// from the cube (so no level is filtered twice). Twin:
// hydrolux_core::pbr::prefiltered.
@compute @workgroup_size(8, 8, 1)
fn prefilter(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(cube_out);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let level = countTrailingZeros(SKY_CUBE_SIZE) - countTrailingZeros(size.x);
    let roughness = min(f32(level) / f32(SPECULAR_LEVELS - 1u), 1.0);
    let alpha = roughness * roughness;
    let samples = min(PREFILTER_SAMPLES << min(level - 1u, 4u), 1024u);
    let u = 2.0 * (f32(id.x) + 0.5) / f32(size.x) - 1.0;
    let v = 2.0 * (f32(id.y) + 0.5) / f32(size.y) - 1.0;
    let r = cube_direction(id.z, u, v);
    let t = select(vec3<f32>(1.0, 0.0, 0.0), normalize(cross(vec3<f32>(0.0, 1.0, 0.0), r)), abs(r.y) < 0.999);
    let b = cross(r, t);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var i = 0u; i < samples; i++) {
        let e1 = (f32(i) + 0.5) / f32(samples);
        let e2 = f32(reverseBits(i)) / 4294967296.0;
        let cos_h = sqrt((1.0 - e1) / (1.0 + (alpha * alpha - 1.0) * e1));
        let sin_h = sqrt(max(1.0 - cos_h * cos_h, 0.0));
        let phi = 2.0 * PI * e2;
        let h = normalize(t * (sin_h * cos(phi)) + b * (sin_h * sin(phi)) + r * cos_h);
        let l = 2.0 * dot(r, h) * h - r;
        let n_l = dot(r, l);
        if (n_l > 0.0) {
            sum += sky_from_view_table(sky_view, sky_view_sampler, sky, l) * n_l;
            weight += n_l;
        }
    }
    textureStore(cube_out, vec2<i32>(id.xy), i32(id.z), vec4<f32>(sum / max(weight, 1e-6), 1.0));
}

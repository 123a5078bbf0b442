// Opaque surfaces' physically based light in the air (issue #32 item 1):
// a diffuse part and a microfacet specular part — GGX normals, Smith's
// height-correlated masking, Schlick's Fresnel with f90 faded out below
// F0 = 2% — lit by the sun (its lobe widened to the sun's disc) and by the
// sky: the irradiance's nine coefficients for the diffuse part, the sky cube
// filtered for the roughness (passes/sky/bake.wgsl `prefilter`) times the
// split sum's directional albedo for the specular part (Karis 2013). The
// diffuse part keeps what the specular part does not take; metals have none.
// Twin: hydrolux-core pbr (environment_radiance, specular_brdf).
#import constants, frame, lighting, sky_bindings, occlusion

// hydrolux_core::pbr::{ENVIRONMENT_TABLE_SIZE, SPECULAR_LEVELS, MIN_ROUGHNESS}
// (a test keeps them equal).
const ENVIRONMENT_TABLE_SIZE: u32 = 32u;
const SPECULAR_LEVELS: u32 = 5u;
const MIN_ROUGHNESS: f32 = 0.02;

// The split sum's (scale, bias) at n·v across and roughness up, texel
// centres at (i + ½)/size: two texels per vec4, row by row
// (pbr::environment_table_packed). A uniform, not a texture: the water
// pass already binds WebGPU's 16 sampled textures.
struct EnvironmentBrdf {
    table: array<vec4<f32>, 512>,
}
@group(0) @binding(9) var<uniform> environment_brdf: EnvironmentBrdf;

// A surface's specular parameters (hydrolux_core::pbr::Surface).
struct Material {
    base_color: vec3<f32>,
    roughness: f32,
    metalness: f32,
    specular: f32,
}

fn environment_texel(i: u32, j: u32) -> vec2<f32> {
    let k = j * ENVIRONMENT_TABLE_SIZE + i;
    let pair = environment_brdf.table[k / 2u];
    return select(pair.xy, pair.zw, (k & 1u) == 1u);
}

// The table read bilinearly between texel centres, clamped at the edges
// (twin: pbr::environment_lookup).
fn environment_lookup(n_v: f32, roughness: f32) -> vec2<f32> {
    let last = f32(ENVIRONMENT_TABLE_SIZE - 1u);
    let t = clamp(vec2<f32>(n_v, roughness) * f32(ENVIRONMENT_TABLE_SIZE) - 0.5, vec2<f32>(0.0), vec2<f32>(last));
    let i = min(vec2<u32>(floor(t)), vec2<u32>(ENVIRONMENT_TABLE_SIZE - 2u));
    let f = t - vec2<f32>(i);
    let low = mix(environment_texel(i.x, i.y), environment_texel(i.x + 1u, i.y), f.x);
    let high = mix(environment_texel(i.x, i.y + 1u), environment_texel(i.x + 1u, i.y + 1u), f.x);
    return mix(low, high, f.y);
}

fn material_f0(m: Material) -> vec3<f32> {
    return mix(vec3<f32>(0.08 * m.specular), m.base_color, m.metalness);
}

fn material_f90(f0: vec3<f32>) -> f32 {
    return clamp(50.0 * (f0.x + f0.y + f0.z) / 3.0, 0.0, 1.0);
}

fn ggx_distribution(n_h: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let d = n_h * n_h * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

fn smith_visibility(n_v: f32, n_l: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let gv = n_l * sqrt(n_v * n_v * (1.0 - a2) + a2);
    let gl = n_v * sqrt(n_l * n_l * (1.0 - a2) + a2);
    return 0.5 / max(gv + gl, 1e-7);
}

// The sky cube's level filtered for `roughness` (pbr::cube_level).
fn specular_cube_lod(roughness: f32) -> f32 {
    return clamp(roughness, 0.0, 1.0) * f32(SPECULAR_LEVELS - 1u);
}

// The environment over the specular lobe of `roughness` about the mirror
// direction r: the filtered sky, and for the part of the lobe below the
// horizon the grey world's light (what the diffuse part's coefficients
// assume down there).
fn environment_specular(r: vec3<f32>, roughness: f32) -> vec3<f32> {
    let sky_part = textureSampleLevel(sky_cube, sky_sampler, r, specular_cube_lod(roughness)).rgb * exposure();
    let width = clamp(2.0 * roughness * roughness, 0.01, 1.0);
    let below = 1.0 - smoothstep(-width, width, r.y);
    return mix(sky_part, below_horizon_radiance(), below);
}

// What an opaque surface in the air at p sends towards v (unit, from the
// surface to the eye) with normal n: the sun (times `sun_factor`, its
// visibility and what else bends light onto the point) and the sky — less
// what the scene's primitives but its own (`own_occluder`) hide of it
// (shaders/occlusion.wgsl) — each diffuse and specular.
fn air_surface_radiance(m: Material, p: vec3<f32>, n: vec3<f32>, v: vec3<f32>, sun_factor: vec3<f32>, own_occluder: u32) -> vec3<f32> {
    let n_v = clamp(dot(n, v), 1e-4, 1.0);
    let roughness = max(m.roughness, MIN_ROUGHNESS);
    let f0 = material_f0(m);
    let f90 = material_f90(f0);
    let split = environment_lookup(n_v, roughness);
    let specular_albedo = f0 * split.x + f90 * split.y;
    let l = frame.light.sun_dir;
    let n_l = max(dot(n, l), 0.0);
    let sky_seen = sky_visibility(p, n, own_occluder);
    let irradiance = frame.light.sun_illuminance * n_l * sun_factor + sky_irradiance(n) * sky_seen;
    let diffuse = m.base_color * (1.0 - specular_albedo) * (1.0 - m.metalness) / PI * irradiance;
    // The cube at the surface's own roughness: a mirror reads the sky itself.
    let sky_specular = environment_specular(reflect(-v, n), m.roughness) * specular_albedo * sky_seen;
    // The sun's specular: GGX widened to at least the sun disc's radius.
    let h = normalize(l + v);
    let sun_radius = sqrt(max(2.0 * (1.0 - frame.light.cos_sun_radius), 0.0));
    let alpha = max(roughness * roughness, sun_radius);
    let fresnel = f0 + (vec3<f32>(f90) - f0) * pow(1.0 - clamp(dot(v, h), 0.0, 1.0), 5.0);
    let brdf = fresnel * (ggx_distribution(max(dot(n, h), 0.0), alpha) * smith_visibility(n_v, max(n_l, 1e-4), alpha));
    let sun_specular = brdf * frame.light.sun_illuminance * n_l * sun_factor;
    return diffuse + sky_specular + sun_specular;
}

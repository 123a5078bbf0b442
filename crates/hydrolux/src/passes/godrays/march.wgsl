// God rays, the ray-marched alternative (`godrays.method = "march"`): each
// texel of the buffer marches its view ray through the water up to the
// drawn distance or the scene, sampling the refracted sun's irradiance
// from the caustic layers (the light-space slices of seed 003 §4.3) and
// the shadow map, and integrates the single scattering towards the eye.
// Each step adds the closed form of its segment times the focusing and
// visibility sampled in it, so flat water gives exactly the uniform
// in-scattering; needs the caustic layers (a floor and caustics on) to show
// any focusing.
#import godrays_common, fullscreen, shadow_space, shadow_lookup, caustics_lookup

@group(1) @binding(0) var<uniform> params: GodRayParams;
// The scene's depth at the buffer's size, as the bits of an f32.
@group(2) @binding(0) var scene_depth: texture_2d<u32>;

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(fullscreen_ndc(i), 0.0, 1.0);
}

// A buffer texel's view ray, marched up to the drawn distance or the scene.
struct MarchRay {
    eye: vec3<f32>,
    view: vec3<f32>,
    // Step length (m) and the texel's offset of the samples within a step.
    ds: f32,
    jitter: f32,
}

fn march_ray(pos: vec2<f32>) -> MarchRay {
    let texel = vec2<i32>(pos);
    let ndc = texel_ndc(vec2<f32>(texel), vec2<f32>(params.buffer_size));
    var r: MarchRay;
    r.eye = frame.view.position;
    r.view = normalize(world_at(ndc, 0.5) - r.eye);
    let end = min(params.distance, scene_distance(ndc, bitcast<f32>(textureLoad(scene_depth, texel, 0).r)));
    r.ds = end / f32(params.steps);
    // Banding turned into fine noise, which the upsampling smooths.
    r.jitter = interleaved_gradient_noise(pos);
    return r;
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let r = march_ray(pos.xy);
    let eye = r.eye;
    let view = r.view;
    let ds = r.ds;
    let jitter = r.jitter;
    let steps = params.steps;
    // Each step: the closed form of its segment (exact for flat water)
    // times the focusing and visibility sampled in it.
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < steps; i++) {
        let s0 = f32(i) * ds;
        let p = eye + view * (s0 + jitter * ds);
        if (p.y > 0.0) {
            continue;
        }
        sum += caustic_factor(p) * sun_visibility_point(p) * sun_in_scatter(-eye.y, view, s0, s0 + ds);
    }
    return vec4<f32>(sum, 1.0);
}

// The fog in the air (`[air]`): the sun scattered towards the eye over the
// fog's reach, with the shadow map's visibility at each sample, so objects
// cast shadows into it (seed 003 §4.3's slices, with one slice per sample).
@fragment
fn fs_fog(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let r = march_ray(pos.xy);
    let eye = r.eye;
    let view = r.view;
    let ds = r.ds;
    let jitter = r.jitter;
    let steps = params.steps;
    // Each step: the closed form of its segment, ∫ e^(−σk·s) ds, times the
    // visibility sampled in it.
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < steps; i++) {
        let s0 = f32(i) * ds;
        let p = eye + view * (s0 + jitter * ds);
        let k = max(params.extinction, vec3<f32>(1e-6));
        let segment = (medium_transmittance(s0) - medium_transmittance(s0 + ds)) / k;
        sum += scattered_to_eye(vec3<f32>(sun_visibility_point(p)), -frame.light.sun_dir, view, 0.0) * segment;
    }
    return vec4<f32>(sum, 1.0);
}

// Shared by the god-ray shaders: their parameters and the buffer's
// geometry. Layout twin: GodRayUniforms (mod.rs). Each shader binds its
// `params`.
#import constants, frame, medium, tube

struct GodRayParams {
    // Photons per side (0: the fog is marched), march steps per texel.
    photons: u32,
    steps: u32,
    // The buffer's size (texels).
    buffer_size: vec2<u32>,
    // Centre (x, z) of the traced square of surface and its half side (m).
    region_centre: vec2<f32>,
    region_half: f32,
    // Half-width (m) of a ribbon.
    ribbon_half_width: f32,
    // Distance from the eye within which shafts are drawn (m); depth at
    // which tubes end (m).
    distance: f32,
    end_depth: f32,
    // The medium drawn (stencil value: 0 air, 1 water).
    medium: u32,
    // 1 when tubes are tested against the shadow map (in the water).
    shadow_tested: u32,
    // The medium the light scatters in: scattering σs (m⁻¹) and the
    // Henyey–Greenstein g.
    scattering: vec3<f32>,
    phase_g: f32,
    // Extinction σk (m⁻¹).
    extinction: vec3<f32>,
    _pad0: f32,
}

fn medium_transmittance(distance: f32) -> vec3<f32> {
    return exp(-params.extinction * max(distance, 0.0));
}

// Where the view ray at NDC `ndc` meets depth `z` (reversed-Z).
fn world_at(ndc: vec2<f32>, z: f32) -> vec3<f32> {
    let h = frame.view.inv_view_proj * vec4<f32>(ndc, z, 1.0);
    return h.xyz / h.w;
}

// NDC of the centre of texel `texel` of a buffer of `size` texels.
fn texel_ndc(texel: vec2<f32>, size: vec2<f32>) -> vec2<f32> {
    let uv = (texel + 0.5) / size;
    return vec2<f32>(2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y);
}

// Distance from the eye to the scene at NDC `ndc` with depth `z`
// (infinite where nothing was drawn).
fn scene_distance(ndc: vec2<f32>, z: f32) -> f32 {
    if (z <= 0.0) {
        return 1e9;
    }
    return distance(world_at(ndc, z), frame.view.position);
}

// Light of the refracted sun scattered towards the eye per metre of a view
// ray along `view`, by a beam of irradiance `e_perp` (relative to the sun's)
// travelling along `travel`, `s` m from the eye.
fn scattered_to_eye(e_perp: vec3<f32>, travel: vec3<f32>, view: vec3<f32>, s: f32) -> vec3<f32> {
    let phase = henyey_greenstein(dot(travel, -view), params.phase_g);
    return params.scattering * phase * e_perp * frame.light.sun_illuminance * medium_transmittance(s);
}

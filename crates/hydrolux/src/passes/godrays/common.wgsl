// Shared by the god-ray shaders: their parameters and the buffer's
// geometry. Layout twin: GodRayUniforms (mod.rs). Each shader binds its
// `params`.
#import constants, frame, medium, tube

struct GodRayParams {
    // x photons per side, y march steps, zw buffer size (texels).
    counts: vec4<u32>,
    // xy centre of the traced square of surface, z its half side (m),
    // w ribbon half-width (m).
    region: vec4<f32>,
    // x distance from the eye within which shafts are drawn (m), y depth at
    // which tubes end (m), z the medium drawn (stencil value: 0 air, 1
    // water), w 1 when tubes are tested against the shadow map.
    limits: vec4<f32>,
    // The medium the light scatters in: rgb scattering σs (m⁻¹), w
    // Henyey–Greenstein g.
    scattering: vec4<f32>,
    // rgb extinction σk (m⁻¹).
    extinction: vec4<f32>,
}

fn medium_transmittance(distance: f32) -> vec3<f32> {
    return exp(-params.extinction.rgb * max(distance, 0.0));
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
    let phase = henyey_greenstein(dot(travel, -view), params.scattering.w);
    return params.scattering.rgb * phase * e_perp * frame.light.sun_illuminance * medium_transmittance(s);
}

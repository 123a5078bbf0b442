// The sky behind everything: the sky-view table per pixel (sharper at the
// horizon than the cube map) plus the sun's disk with limb darkening. Drawn at the far plane
// (reversed Z: depth 0) so the water covers it. Pixels that look out from
// inside the water get `fs_deep` instead: the water's own in-scattered light
// along an endless path (seed 000 eq. 3.8 with nothing behind).
#import constants, frame, fullscreen, sky_model, sky_bindings, medium, fog, atmosphere

@group(1) @binding(0) var sky_view: texture_2d<f32>;
@group(1) @binding(1) var sky_view_sampler: sampler;


struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
}

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> VsOut {
    let xy = fullscreen_ndc(i);
    var out: VsOut;
    out.clip = vec4<f32>(xy, 0.0, 1.0);
    out.ndc = xy;
    return out;
}

fn view_ray(ndc: vec2<f32>) -> vec3<f32> {
    let far = frame.view.inv_view_proj * vec4<f32>(ndc, 1e-6, 1.0);
    return normalize(far.xyz / far.w - frame.view.position);
}

// Sun disk radiance (pre-exposed) towards `dir`, limb-darkened.
fn sun_disk(dir: vec3<f32>) -> vec3<f32> {
    let cos_a = dot(dir, frame.light.sun_dir);
    let cos_r = frame.light.cos_sun_radius;
    if (cos_a < cos_r) {
        return vec3<f32>(0.0);
    }
    let r = sqrt(max(1.0 - cos_a * cos_a, 0.0)) / sqrt(max(1.0 - cos_r * cos_r, 1e-12));
    let mu = sqrt(max(1.0 - r * r, 0.0));
    let limb = 1.0 - 0.6 * (1.0 - mu);
    return frame.light.sun_illuminance * frame.light.inv_sun_solid_angle * limb / 0.8;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    let dir = view_ray(in.ndc);
    var l = sky_from_view_table(sky_view, sky_view_sampler, sky, dir) * exposure();
    if (dir.y > 0.0) {
        l += sun_disk(dir);
    }
    // Through the whole depth of the fog, if any.
    let eye = frame.view.position;
    l = through_fog(eye, eye + dir * 1e6, l);
    return vec4<f32>(min(l, vec3<f32>(60000.0)), 1.0);
}

@fragment
fn fs_deep(in: VsOut) -> @location(0) vec4<f32> {
    let dir = view_ray(in.ndc);
    let eye = frame.view.position;
    // Rays that rise end at the surface (which the water pass draws over
    // this); those that do not go on for ever.
    var s = 1e5;
    if (dir.y > 1e-4 && eye.y < 0.0) {
        s = -eye.y / dir.y;
    }
    return vec4<f32>(eye_in_scatter(-eye.y, dir, s), 1.0);
}

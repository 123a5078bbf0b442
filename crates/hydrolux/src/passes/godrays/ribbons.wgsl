// God rays, step 2 (lines method): each beam tube drawn as a screen-facing
// ribbon (an instanced quad: WebGPU has no geometry shaders and its lines
// are one pixel wide) into the reduced-resolution buffer, additively. Each
// fragment finds where its view ray passes the tube's axis and shades
// seed 000 eq. 4.2 made exact in energy:
//   L = σs·p(θ)·Φ·(1 − |u|)/(a·sin α)·e^(−σk(d + s))
// (see hydrolux_core::godrays), occluded by the scene's depth and by the
// shadow map.
#import godrays_common, shadow_space, shadow_lookup

@group(1) @binding(0) var<uniform> params: GodRayParams;
@group(1) @binding(1) var<storage, read> tubes: array<Tube>;
// The scene's depth at the buffer's size, as the bits of an f32.
@group(2) @binding(0) var scene_depth: texture_2d<u32>;

struct RibbonOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) @interpolate(flat) tube: u32,
}

@vertex
fn vs_ribbon(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> RibbonOut {
    let t = tubes[ii];
    var out: RibbonOut;
    out.tube = ii;
    out.clip = vec4<f32>(0.0, 0.0, 0.0, 1.0);
    out.world = vec3<f32>(0.0);
    if (t.dir.w <= 0.0) {
        return out;
    }
    // Two triangles: (end, side) corners.
    let corner = array<vec2<f32>, 6>(vec2(0.0, -1.0), vec2(1.0, -1.0), vec2(1.0, 1.0), vec2(0.0, -1.0), vec2(1.0, 1.0), vec2(0.0, 1.0))[vi];
    let mid = t.start.xyz + t.dir.xyz * (0.5 * t.start.w);
    let to_mid = mid - frame.view.position;
    var side = cross(t.dir.xyz, to_mid);
    if (dot(side, side) < 1e-12) {
        side = cross(t.dir.xyz, vec3<f32>(0.0, 1.0, 0.0));
    }
    // A half-width and a half to spare: the view ray's closest approach to
    // the axis is not exactly along `side` away from the ribbon's middle.
    side = normalize(side) * params.ribbon_half_width * 1.5;
    // Past the ends by a half-width too, for the same reason.
    let ends = t.dir.xyz * params.ribbon_half_width;
    let world = t.start.xyz - ends + (t.dir.xyz * t.start.w + 2.0 * ends) * corner.x + side * corner.y;
    out.world = world;
    out.clip = frame.view.view_proj * vec4<f32>(world, 1.0);
    return out;
}

@fragment
fn fs_ribbon(in: RibbonOut) -> @location(0) vec4<f32> {
    let t = tubes[in.tube];
    let eye = frame.view.position;
    let view = normalize(in.world - eye);
    // Closest approach of the view ray and the tube's axis
    // (twin: hydrolux_core::godrays::ribbon_hit).
    let w0 = eye - t.start.xyz;
    let b = dot(view, t.dir.xyz);
    let denom = 1.0 - b * b;
    if (denom < 1e-6) {
        discard;
    }
    let dv = dot(view, w0);
    let dt = dot(t.dir.xyz, w0);
    let s = (b * dt - dv) / denom;
    let d = (dt - b * dv) / denom;
    let u = length(w0 + view * s - t.dir.xyz * d) / params.ribbon_half_width;
    if (s <= 0.0 || d < 0.0 || d > t.start.w || u > 1.0 || s > params.distance) {
        discard;
    }
    let texel = vec2<i32>(in.clip.xy);
    let size = vec2<f32>(params.buffer_size);
    let z = bitcast<f32>(textureLoad(scene_depth, texel, 0).r);
    if (s > scene_distance(texel_ndc(vec2<f32>(texel), size), z)) {
        discard;
    }
    let p = eye + view * s;
    let profile = (1.0 - u) / (params.ribbon_half_width * max(sqrt(denom), MIN_SIN_ALPHA));
    var visible = 1.0;
    if (params.shadow_tested != 0u) {
        visible = sun_visibility_point(p);
    }
    let e = t.dir.w * profile * visible * t.tint.rgb * medium_transmittance(d);
    return vec4<f32>(scattered_to_eye(e, t.dir.xyz, view, s), 1.0);
}

// Twin: hydrolux_core::godrays::MIN_SIN_ALPHA.
const MIN_SIN_ALPHA: f32 = 0.1;

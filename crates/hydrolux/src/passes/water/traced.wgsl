// The water's ray-traced shading (`water.method = "raytrace"`, seed 003
// §3.3.1): what the traced reflected and refracted rays meet (the ground's
// heightfield, the traced objects), lit as the geometry pass lights the
// scene (the shared `lighting` module). Part of the water shader (its
// group 3 bindings are declared there).

#import constants, frame, lighting, pbr, medium, shadow_lookup, caustics_lookup, heightfield_trace, traced, traced_hits

// How much of the pattern's second colour shows at q (normal n) over a
// footprint of `footprint` metres: the procedural pattern as the geometry
// pass draws it (on the plane facing the dominant normal axis; grout lines
// 6% of a tile, checkers), faded to its mean where a pixel covers a good
// part of a tile.
fn pattern_at(q: vec3<f32>, n: vec3<f32>, tile: f32, kind: u32, footprint: f32) -> f32 {
    let t = pattern_plane(q, n) / tile;
    return pattern_coverage(t, vec2<f32>(footprint / tile), kind);
}

// The sunbeam's cosine on traced ground at q (normal n) under the water,
// shadow and caustics included: the traced photons' light where their
// window covers q (factor × n_y × the flat beam's cosine: the photons'
// density per horizontal area holds the slope's own cosine), elsewhere the
// layered caustic maps and the shadow map.
fn ground_sun_cosine(q: vec3<f32>, n: vec3<f32>) -> f32 {
    let light = traced_ground_light(q);
    if (light >= 0.0) {
        return light * n.y * frame.light.sun_travel_cos;
    }
    return max(dot(n, -frame.light.sun_travel), 0.0) * traced_sun_visibility(q, n) * caustic_factor(q);
}

// Whether the sun reaches q (normal n) on traced ground or a traced object,
// by a traced shadow ray: under the mean level up the flat-refracted
// sunbeam to it, then along the sun's direction; the ground and the traced
// objects block it (meshes cast no shadow in traced frames). The photons'
// window (ground_sun_cosine) is exact under waves; this ray is for flat
// water.
fn traced_sun_visibility(q: vec3<f32>, n: vec3<f32>) -> f32 {
    var o = q + n * 0.02;
    if (o.y < 0.0) {
        let up = -frame.light.sun_travel;
        let t_surface = -o.y / max(up.y, 1e-3);
        if (trace_ground(o, up) < t_surface || objects_block(o, up, t_surface)) {
            return 0.0;
        }
        o += up * t_surface;
    }
    let l = frame.light.sun_dir;
    if (trace_ground(o, l) != NO_ROOT || objects_block(o, l, traced.reach)) {
        return 0.0;
    }
    return 1.0;
}

// What a surface of material `m` at q (normal n) sends back towards v (as
// the geometry pass shades it): below the mean level, on a Lambertian
// surface of its base colour, the light field under the surface with the
// caustics and the sun's traced shadow (for the ground, the traced
// photons'); above it, sun and sky, diffuse and specular (shaders/pbr.wgsl).
fn lit_radiance(q: vec3<f32>, n: vec3<f32>, v: vec3<f32>, m: Material, ground: bool, own_occluder: u32) -> vec3<f32> {
    if (q.y < 0.0) {
        var sun_cosine: f32;
        if (ground) {
            sun_cosine = ground_sun_cosine(q, n);
        } else {
            sun_cosine = max(dot(n, -frame.light.sun_travel), 0.0) * traced_sun_visibility(q, n) * caustic_factor(q);
        }
        return m.base_color / PI * underwater_irradiance_sun(-q.y, n, sun_cosine);
    }
    return air_surface_radiance(m, q, n, v, vec3<f32>(traced_sun_visibility(q, n)), own_occluder);
}

// A traced object's light at its hit.
fn object_radiance(o: vec3<f32>, d: vec3<f32>, hit: ObjectHit, footprint: f32) -> vec3<f32> {
    let obj = traced_objects[hit.index];
    let q = o + d * hit.t;
    let w = pattern_at(q, hit.normal, obj.tile_size, obj.pattern, footprint);
    let m = Material(mix(obj.albedo, obj.pattern_color, w), obj.roughness, obj.metalness, obj.specular);
    return lit_radiance(q, hit.normal, -d, m, false, obj.occluder);
}

// The light the ground sends back at q towards v, seen over `footprint` metres.
fn ground_radiance(q: vec3<f32>, v: vec3<f32>, footprint: f32) -> vec3<f32> {
    let n = ground_normal(q.x, q.z);
    let w = pattern_at(q, vec3<f32>(0.0, 1.0, 0.0), traced.ground_tile_size, traced.ground_pattern, footprint);
    let albedo = mix(traced.ground_albedo, traced.ground_pattern_color, w);
    let m = Material(albedo, traced.ground_roughness, traced.ground_metalness, traced.ground_specular);
    return lit_radiance(q, n, v, m, true, 0xffffffffu);
}

// What a traced ray o + t·d meets first, ground (within t_ground) or an
// object, lit, seen over a pixel of `pixel_angle` at `before` metres from
// the eye; `hit.x` NO_ROOT if neither.
fn traced_scene(o: vec3<f32>, d: vec3<f32>, t_ground: f32, before: f32, pixel_angle: f32) -> vec4<f32> {
    let obj = trace_objects(o, d, t_ground);
    if (obj.t < NO_ROOT && obj.t <= t_ground) {
        return vec4<f32>(object_radiance(o, d, obj, pixel_angle * (before + obj.t)), obj.t);
    }
    if (t_ground < NO_ROOT) {
        return vec4<f32>(ground_radiance(o + d * t_ground, -d, pixel_angle * (before + t_ground)), t_ground);
    }
    return vec4<f32>(0.0, 0.0, 0.0, NO_ROOT);
}

// What the reflected ray r from surface point p (normal n) sees, traced:
// an object (primitive or mesh), the ground where it rises out of the
// water, the next wave, or the sky.
fn traced_reflection(p: vec3<f32>, n: vec3<f32>, r: vec3<f32>, sky_reflected: vec3<f32>, e_down: vec3<f32>, pixel_angle: f32) -> vec3<f32> {
    // Start on the traced water's side above: the drawn mesh and the
    // resampled heightfield differ by a little, and beyond the window the
    // heightfield is the mean level, which a trough lies under.
    var o = p + n * 0.02;
    o.y = max(o.y, hf_height(traced.water, o.x, o.z) + 0.02);
    let tw = trace_heightfield(traced.water, o, r, traced.reach);
    let seen = traced_scene(o, r, min(trace_ground(o, r), tw), distance(frame.view.position, p), pixel_angle);
    if (seen.w < NO_ROOT) {
        return through_fog(p, o + r * seen.w, seen.rgb);
    }
    if (tw < NO_ROOT) {
        // Another wave: what it reflects of the sky (one more bounce, by
        // its heightfield's normal) over the water's own colour.
        let q = o + r * tw;
        let e = traced.water.spacing;
        let hx = hf_height(traced.water, q.x + e, q.z) - hf_height(traced.water, q.x - e, q.z);
        let hz = hf_height(traced.water, q.x, q.z + e) - hf_height(traced.water, q.x, q.z - e);
        let m = normalize(vec3<f32>(-hx, 2.0 * e, -hz));
        var r2 = reflect(r, m);
        r2.y = abs(r2.y);
        let ior = frame.water.ior;
        let f2 = fresnel(frame.modes.fresnel, frame.water.fresnel_power, abs(dot(r, m)), 1.0, ior);
        let sky2 = textureSampleLevel(sky_cube, sky_sampler, r2, 0.0).rgb * exposure();
        var body = path_in_scatter(vec3<f32>(0.0, -1.0, 0.0), 1e5) / (ior * ior);
        if (frame.modes.optics == OPTICS_SIMPLE) {
            body = frame.water.body_color * e_down / PI;
        }
        return f2 * sky2 + (1.0 - f2) * body;
    }
    return sky_reflected;
}

// The light that comes up through the surface at p along t_dir, where
// `seen` is what the ray meets (rgb) and how far (w; NO_ROOT: bottomless
// water).
fn traced_transmitted(p: vec3<f32>, t_dir: vec3<f32>, e_down: vec3<f32>, seen: vec4<f32>) -> vec3<f32> {
    let ior = frame.water.ior;
    let t = seen.w;
    if (t >= NO_ROOT) {
        if (frame.modes.optics == OPTICS_SIMPLE) {
            return frame.water.body_color * e_down / PI;
        }
        return path_in_scatter(t_dir, 1e5) / (ior * ior);
    }
    if (frame.modes.optics == OPTICS_SIMPLE) {
        let c_water = frame.water.body_color * e_down / PI;
        return c_water + exp(-t * frame.water.simple_attenuation) * (seen.rgb - c_water);
    }
    return (seen.rgb * transmittance(t) + path_in_scatter_with_shafts(p, t_dir, t)) / (ior * ior);
}

// Samples of the god rays seen from above.
const SHAFT_STEPS: u32 = 16u;


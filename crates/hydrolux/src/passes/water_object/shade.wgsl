// Refractive objects seen by the camera, as clear water or glass (what seed
// 004 left undone; the two-sided image-space refraction of Wyman 2005):
// `fs_back` records each pixel's farthest back face (outward normal,
// distance from the eye); `fs_front` shades the front face: Fresnel
// reflection of the sky, and the scene behind seen through two refractions
// — in at the front face, out at the back face found by the thickness the
// back-face pass measured — attenuated by the water inside, then through
// the fog.
//
// From inside (a camera whose lens is in the liquid or in a clear object):
// `fs_count` counts every face into the stencil (+1 leaving, −1 entering,
// no depth test: the above/below division of the surface water, seed 000
// §4.2, for closed meshes), so 1 marks the pixels whose near-plane point is
// inside. There `fs_inside` shades the nearest back face as the surface
// seen from below (Fresnel from water to air: Snell's window, total
// internal reflection beyond it), and `fs_inside_medium` the pixels where
// the opaque scene comes first (a floor under the liquid); both carry the
// light back to the eye through the water (attenuated, in-scattered).
#import constants, frame, optics, sky_model, sky_bindings, medium, fog, geometry_common, lighting, screen_lookup, fullscreen

@group(3) @binding(0) var behind_tex: texture_2d<f32>;
@group(3) @binding(1) var scene_depth: texture_2d<f32>;
@group(3) @binding(2) var back_tex: texture_2d<f32>;

struct ShadeOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

@vertex
fn vs_object(v: VsIn) -> ShadeOut {
    let world = (object.model * vec4<f32>(v.position, 1.0)).xyz;
    var out: ShadeOut;
    out.clip = view.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    out.normal = object.normal_matrix * v.normal;
    return out;
}

@fragment
fn fs_back(in: ShadeOut) -> @location(0) vec4<f32> {
    return vec4<f32>(normalize(in.normal), distance(in.world, frame.view.position));
}

@fragment
fn fs_front(in: ShadeOut) -> @location(0) vec4<f32> {
    let px = vec2<i32>(in.clip.xy);
    // Behind the opaque scene (reversed Z: smaller is farther).
    if (in.clip.z < textureLoad(scene_depth, px, 0).r) {
        discard;
    }
    let eye = frame.view.position;
    let v = normalize(in.world - eye);
    let n0 = normalize(in.normal);
    // ior stored as bits in flags.y (geometry upload).
    let ior = object.ior;
    let cos0 = max(-dot(v, n0), 0.0);
    let r0 = fresnel_exact(cos0, 1.0, ior);
    let reflected = sky_towards(reflect(v, n0));
    let t1 = refract(v, n0, 1.0 / ior);
    let size = vec2<f32>(textureDimensions(back_tex));
    // The opaque scene under this pixel: the light inside cannot have come
    // from beyond it (a thin sheet of liquid on a floor has back faces
    // under the floor).
    let z_here = textureLoad(scene_depth, px, 0).r;
    let uv_here = (in.clip.xy + 0.5) / size;
    let h_here = frame.view.inv_view_proj
        * vec4<f32>(2.0 * uv_here.x - 1.0, 1.0 - 2.0 * uv_here.y, max(z_here, 1e-7), 1.0);
    let to_scene = select(1e9, distance(h_here.xyz / h_here.w, eye), z_here > 0.0);
    let front = distance(in.world, eye);
    let thickness = clamp(textureLoad(back_tex, px, 0).w - front, 0.005, max(to_scene - front, 0.005));
    let p1 = in.world + t1 * thickness;
    let at_exit = screen_uv(p1);
    let exit_texel = texel_at(at_exit.xy, size);
    let b = textureLoad(back_tex, exit_texel, 0);
    // The back face's normal where the ray leaves; where the back-face
    // record is empty there, this pixel's own back face, or the front's.
    let here = textureLoad(back_tex, px, 0);
    var n1 = select(here.xyz, b.xyz, (at_exit.z > 0.5) & (b.w > 0.0));
    n1 = select(n0, normalize(n1), dot(n1, n1) > 0.25);
    // A record the ray cannot leave through (its outward normal against the
    // ray: another layer's face, where a thin sheet or a second body lies
    // behind): leave as through a slab, parallel to the way in.
    n1 = select(n1, -n0, dot(t1, n1) <= 0.0);
    let refracted_out = refract(t1, -n1, ior);
    let tir = dot(refracted_out, refracted_out) < 0.5;
    // The liquid lying on the opaque scene (a floor, a table): where the
    // ray leaves, the back face is within CONTACT of the scene behind it, so
    // there is no air between and no second interface — the ray goes on
    // through the water until it meets the scene. (Otherwise a mesh that
    // stands off the floor by half a particle spacing would reflect the
    // floor totally at its bumpy underside: a chrome puddle.)
    let on_scene = (at_exit.z > 0.5) & (b.w > 0.0) & (b.w + CONTACT > scene_distance(exit_texel));
    // Totally reflected at the back: follow the reflected ray instead.
    let t2 = select(select(refracted_out, reflect(t1, -n1), tir), t1, on_scene);
    let r1 = select(select(fresnel_exact(max(dot(t1, n1), 0.0), ior, 1.0), 0.0, tir), 0.0, on_scene);
    // What lies behind along t2: guess its distance from the scene's depth
    // under the exit point, then look it up where that point projects.
    let z = textureLoad(scene_depth, exit_texel, 0).r;
    let ndc = vec2<f32>(2.0 * at_exit.x - 1.0, 1.0 - 2.0 * at_exit.y);
    let h = frame.view.inv_view_proj * vec4<f32>(ndc, max(z, 1e-7), 1.0);
    let gap = max(distance(h.xyz / h.w, eye) - distance(p1, eye), 0.05);
    let q = screen_uv(p1 + t2 * gap);
    let zq = textureLoad(scene_depth, texel_at(q.xy, size), 0).r;
    let seen = textureSampleLevel(behind_tex, sky_sampler, clamp(q.xy, vec2<f32>(0.0), vec2<f32>(1.0)), 0.0).rgb;
    // Where the lookup fails: the sky that way, or, over the opaque scene,
    // what lies straight behind this pixel.
    let fallback = select(sky_towards(t2), textureLoad(behind_tex, px, 0).rgb, z_here > 0.0);
    let found = (at_exit.z > 0.5) & (z > 0.0) & (q.z > 0.5) & (zq > 0.0);
    // In contact, the scene where the refracted ray meets it, through the
    // water all the way.
    let through = along_to_scene(in.world, t1, thickness);
    let seen_through = textureSampleLevel(behind_tex, sky_sampler, clamp(through.xy, vec2<f32>(0.0), vec2<f32>(1.0)), 0.0).rgb;
    let behind = select(select(fallback, seen, found), select(fallback, seen_through, through.z > 0.5), on_scene);
    let depth_inside = select(thickness, through.w, on_scene & (through.z > 0.5));
    let inside = exp(-frame.water.absorption * depth_inside);
    let color = r0 * reflected + (1.0 - r0) * (1.0 - r1) * inside * behind;
    let shaded = clamp(through_air(eye, in.world, color), vec3<f32>(0.0), vec3<f32>(60000.0));
    // The normals debug view as a select, not a branch on the uniform (see
    // `through_fog`).
    let normals_view = frame.modes.debug_view == VIEW_NORMALS;
    return vec4<f32>(select(shaded, n0 * 0.5 + 0.5, normals_view), 1.0);
}

// The stencil count needs no colour (the pipeline writes none).
@fragment
fn fs_count() -> @location(0) vec4<f32> {
    return vec4<f32>(0.0);
}

// The distance from the eye to the opaque scene under `px` (far where the
// buffer is empty).
fn scene_distance(px: vec2<i32>) -> f32 {
    let z = textureLoad(scene_depth, px, 0).r;
    let size = vec2<f32>(textureDimensions(scene_depth));
    let uv = (vec2<f32>(px) + 0.5) / size;
    let h = frame.view.inv_view_proj * vec4<f32>(2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y, max(z, 1e-7), 1.0);
    return select(1e5, distance(h.xyz / h.w, frame.view.position), z > 0.0);
}

// Where a ray from `start` along `dir` meets the opaque scene, found in
// the image: from a first guess of its length, three rounds of projecting
// the point, reading the scene's depth there and taking the distance to
// that scene point along the ray. (uv, 1 where it found the scene, length.)
fn along_to_scene(start: vec3<f32>, dir: vec3<f32>, guess: f32) -> vec4<f32> {
    let size = vec2<f32>(textureDimensions(scene_depth));
    var gap = guess;
    var found = false;
    var q = screen_uv(start + dir * gap);
    for (var i = 0; i < 3; i++) {
        let z = textureLoad(scene_depth, texel_at(q.xy, size), 0).r;
        found = (q.z > 0.5) & (z > 0.0);
        let ndc = vec2<f32>(2.0 * q.x - 1.0, 1.0 - 2.0 * q.y);
        let h = frame.view.inv_view_proj * vec4<f32>(ndc, max(z, 1e-7), 1.0);
        gap = select(gap, clamp(dot(h.xyz / h.w - start, dir), 0.02, 1e4), found);
        q = screen_uv(start + dir * gap);
    }
    let z = textureLoad(scene_depth, texel_at(q.xy, size), 0).r;
    found = (q.z > 0.5) & (z > 0.0);
    return vec4<f32>(q.xy, select(0.0, 1.0, found), gap);
}

// What a ray from `start` along `dir` inside the water sees: the scene
// where it meets it, carried back through the water. Where the lookup
// leaves the screen or finds the sky, the ray leaves the liquid (a body in
// the air, not an ocean) after about `guess` metres and sees the sky or
// the ground that way.
fn seen_in_water(start: vec3<f32>, dir: vec3<f32>, guess: f32) -> vec3<f32> {
    let hit = along_to_scene(start, dir, guess);
    let seen = textureSampleLevel(behind_tex, sky_sampler, clamp(hit.xy, vec2<f32>(0.0), vec2<f32>(1.0)), 0.0).rgb;
    let found = hit.z > 0.5;
    let length = select(guess, hit.w, found);
    return to_eye_in_water(select(sky_towards(dir), seen, found), dir, length);
}

// Light reaching the eye through `d` metres of water along `dir`: `l`
// attenuated, plus what the water scatters into the path. The light in the
// liquid is that just under a flat surface in the sun (depth 0): a liquid
// in a tank is shallow.
fn to_eye_in_water(l: vec3<f32>, dir: vec3<f32>, d: f32) -> vec3<f32> {
    return l * transmittance(d) + view_in_scatter(0.0, dir, d);
}

// A back face closer than this (m, along the ray) to the opaque scene
// behind it is the liquid lying against it (a liquid's mesh stands off a
// wall or floor by up to half a particle spacing): there is no air between,
// so the scene is seen through the water alone (`fs_inside_medium`).
const CONTACT: f32 = 0.02;

@fragment
fn fs_inside(in: ShadeOut) -> @location(0) vec4<f32> {
    let px = vec2<i32>(in.clip.xy);
    let eye = frame.view.position;
    let d = distance(in.world, eye);
    if (scene_distance(px) < d + CONTACT) {
        discard;
    }
    let v = (in.world - eye) / max(d, 1e-6);
    // Outward: away from the eye on a back face.
    let n = normalize(in.normal);
    let ior = object.ior;
    let cos_i = max(dot(v, n), 0.0);
    // Water to air: 1 beyond the critical angle (total internal reflection).
    let r = fresnel_exact(cos_i, ior, 1.0);
    // Back into the water, mirrored (first guess: as far again as the eye).
    let reflected = seen_in_water(in.world, reflect(v, n), d);
    // Out through Snell's window into the image as it was in the air; the
    // radiance gains n² entering the denser medium (as under the surface
    // water). Branch-free: beyond the critical angle r is 1 and t zero.
    let t = refract(v, -n, ior);
    let out = along_to_scene(in.world, t, max(scene_distance(px) - d, 0.05));
    let seen = textureSampleLevel(behind_tex, sky_sampler, clamp(out.xy, vec2<f32>(0.0), vec2<f32>(1.0)), 0.0).rgb;
    let air = select(sky_towards(t), seen, out.z > 0.5);
    let through = (1.0 - r) * air * ior * ior;
    let color = to_eye_in_water(r * reflected + through, v, d);
    let shaded = clamp(color, vec3<f32>(0.0), vec3<f32>(60000.0));
    let normals_view = frame.modes.debug_view == VIEW_NORMALS;
    return vec4<f32>(select(shaded, n * 0.5 + 0.5, normals_view), 1.0);
}

// A triangle over the screen just off the far plane (reversed Z: depth 0),
// drawn where no back face was: the depth test Greater passes only where
// the cleared 0 is left. (An Equal test against 0 fails on lavapipe.)
@vertex
fn vs_far(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(fullscreen_ndc(i), 1e-6, 1.0);
}

// The opaque scene inside the water: seen through it.
@fragment
fn fs_inside_medium(@builtin(position) clip: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(clip.xy);
    let uv = clip.xy / vec2<f32>(textureDimensions(behind_tex));
    let eye = frame.view.position;
    let h = frame.view.inv_view_proj * vec4<f32>(2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y, 1.0, 1.0);
    let v = normalize(h.xyz / h.w - eye);
    let d = scene_distance(px);
    let color = to_eye_in_water(textureLoad(behind_tex, px, 0).rgb, v, d);
    return vec4<f32>(clamp(color, vec3<f32>(0.0), vec3<f32>(60000.0)), 1.0);
}

// Screen-space fluid rendering (`fluid.surface = "screen_space"`; van der
// Laan, Green & Sainz 2009, the narrow-range filter of Truong & Yuksel
// 2018; CPU twin `hydrolux_core::fluid::screen_space`):
// 1. `fs_depth`: each particle a sphere ray-cast in an instanced quad; the
//    nearest front's clip w per pixel (depth-tested), hidden by the opaque
//    scene;
// 2. `fs_thickness`: the spheres' chords along each pixel's ray, each
//    weighted by its particle's share of the sphere, added (cut where the
//    opaque scene lies nearer): the liquid's thickness;
// 3. `fs_filter_across`, `fs_filter_down`: the narrow-range filter of the
//    depths and a Gaussian of the thickness, across then down;
// 4. `fs_shade`: normals from the filtered depths (the front) and from the
//    depths plus the thickness (the back), shaded as clear water — Fresnel,
//    the sky and the sun's glint mirrored, the scene behind seen through
//    two refractions (in at the front, out at the back) and absorbed over
//    the thickness, the light the water scatters, the sun's shadow, the fog.
// From the sun (CPU twin `SunView`), for the liquid's caustics: steps 1–3
// again in the refractive things' orthographic light view, where
// passes/water_object traces their light paths: `fs_depth_sun` splats the
// nearest front and `fs_back_sun` the farthest back, the same filter
// smooths both (its reach the same at every depth; the back over the
// liquid's texels alone), and `fs_sun_front` / `fs_sun_back` write the faces the
// light enters and leaves (outward normal × the index of refraction, the
// light view's z) into that pass's face images, depth-tested with the
// glasses' faces. Depths there are metres along the light from the view's
// near plane.
#import liquid_particle, constants, frame, modes, sky_bindings, medium, optics, lighting, fog, shadow_space, shadow_lookup, screen_lookup, fullscreen

struct ScreenSpaceParams {
    // The sun's view (world → clip, and back) when the maps are made from
    // the sun; unused for the camera's.
    sun_view_proj: mat4x4<f32>,
    sun_inv_view_proj: mat4x4<f32>,
    // The spheres (m), and the share of each that its particle's liquid
    // fills (each chord is weighted by it).
    radius: f32,
    volume_share: f32,
    // The filter's radius as a world length (m), its range and clamp (m).
    filter_radius: f32,
    threshold: f32,
    clamp: f32,
    // Pixels per metre at unit depth, down the screen.
    pixels_per_metre: f32,
    // The filter's widest reach (pixels either side).
    max_reach: u32,
    count: u32,
    // 1: the camera's maps (depth the clip w, the filter's reach shrinking
    // with it); 0: the sun's (depth in metres, the same reach everywhere).
    perspective: u32,
    // The sun's view: texels per side, the depth (m) its z spans, and the
    // water's index of refraction (the faces' normals' length).
    sun_resolution: f32,
    sun_span: f32,
    ior: f32,
}

// A storage buffer, not a uniform one (see points.wgsl).
@group(1) @binding(0) var<storage, read> params: ScreenSpaceParams;
// The splats read the particles and the scene's depth; the filter passes
// their sources; the shading the filtered maps, the scene's depth and the
// image behind the liquid.
@group(1) @binding(1) var<storage, read> particles: array<LiquidParticle>;
@group(1) @binding(2) var scene_depth: texture_2d<f32>;
// The depths and the filtered maps are float bits in integer images
// (downlevel OpenGL renders no 32-bit float colour).
@group(1) @binding(3) var depth_source: texture_2d<u32>;
@group(1) @binding(4) var thickness_source: texture_2d<f32>;
@group(1) @binding(5) var behind_tex: texture_2d<f32>;

struct SplatOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) @interpolate(flat) centre: vec3<f32>,
}

@vertex
fn vs_sphere(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> SplatOut {
    let p = particles[i];
    let world = sphere_quad_corner(p.position, params.radius, frame.view.position, v);
    var out: SplatOut;
    out.clip = frame.view.view_proj * vec4<f32>(world, 1.0);
    if (p.alive == 0u) {
        // An empty slot: behind the far plane, clipped.
        out.clip = vec4<f32>(0.0, 0.0, 2.0, 1.0);
    }
    out.world = world;
    out.centre = p.position;
    return out;
}

// The pixel's ray through the sphere: (entry, exit) distances along it and
// how the clip w grows per metre of it; entry < 0 where it misses.
struct Chord {
    dir: vec3<f32>,
    t0: f32,
    t1: f32,
    w_per_metre: f32,
    // The opaque scene's clip w under the pixel.
    limit: f32,
}

fn chord(in: SplatOut) -> Chord {
    let eye = frame.view.position;
    var c: Chord;
    c.dir = normalize(in.world - eye);
    let oc = eye - in.centre;
    let b = dot(oc, c.dir);
    let disc = b * b - (dot(oc, oc) - params.radius * params.radius);
    let s = sqrt(max(disc, 0.0));
    c.t0 = select(-1.0, -b - s, disc >= 0.0);
    c.t1 = -b + s;
    let m = frame.view.view_proj;
    c.w_per_metre = dot(vec3<f32>(m[0][3], m[1][3], m[2][3]), c.dir);
    c.limit = scene_w(in.clip.xy, textureLoad(scene_depth, vec2<i32>(in.clip.xy), 0).r);
    return c;
}

struct DepthOut {
    @location(0) w: u32,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn fs_depth(in: SplatOut) -> DepthOut {
    let c = chord(in);
    let front = c.t0 * c.w_per_metre;
    if (c.t0 <= 0.0 || front > c.limit) {
        discard;
    }
    let hit = frame.view.view_proj * vec4<f32>(frame.view.position + c.t0 * c.dir, 1.0);
    var out: DepthOut;
    out.w = bitcast<u32>(front);
    out.depth = hit.z / hit.w;
    return out;
}

@fragment
fn fs_thickness(in: SplatOut) -> @location(0) vec4<f32> {
    let c = chord(in);
    if (c.t0 <= 0.0 || c.t0 * c.w_per_metre > c.limit) {
        discard;
    }
    let back = min(c.t1, c.limit / max(c.w_per_metre, 1e-12));
    return vec4<f32>(params.volume_share * (back - c.t0), 0.0, 0.0, 0.0);
}

// The (depth, thickness) of a filtered image's pixel.
fn maps_at(px: vec2<i32>) -> vec2<f32> {
    return bitcast<vec2<f32>>(textureLoad(depth_source, px, 0).xy);
}

// One pass of the filter along `step`; the thickness comes from the
// splat's own image (the first pass) or the first pass's second channel.
fn filtered(px: vec2<i32>, step: vec2<i32>, first: bool) -> vec2<f32> {
    let zc = bitcast<f32>(textureLoad(depth_source, px, 0).x);
    if (zc <= 0.0) {
        return vec2<f32>(0.0);
    }
    let size = vec2<i32>(textureDimensions(depth_source));
    var reach = 0;
    if (params.filter_radius > 0.0) {
        let scale = params.pixels_per_metre / select(1.0, zc, params.perspective != 0u);
        reach = i32(min(ceil(params.filter_radius * scale), f32(params.max_reach)));
    }
    let sigma = 0.5 * f32(max(reach, 1));
    var z_sum = 0.0;
    var z_weight = 0.0;
    var t_sum = 0.0;
    var t_weight = 0.0;
    for (var k = -reach; k <= reach; k++) {
        let s = px + k * step;
        if (any(s < vec2<i32>(0)) || any(s >= size)) {
            continue;
        }
        let g = exp(-f32(k * k) / (2.0 * sigma * sigma));
        let source = textureLoad(depth_source, s, 0);
        var thickness = bitcast<f32>(source.y);
        if (first) {
            thickness = textureLoad(thickness_source, s, 0).x;
        }
        var z = bitcast<f32>(source.x);
        // From the sun the second channel is the farthest back's depth,
        // averaged over the liquid's texels alone (an empty one has none:
        // counted as 0 it would lift the back near every outline).
        if (params.perspective != 0u || z > 0.0) {
            t_sum += g * thickness;
            t_weight += g;
        }
        // Another layer in front: not this surface.
        if (z > 0.0 && z < zc - params.threshold) {
            continue;
        }
        // Behind the range, or the background: the layer's edge bends
        // away by the clamp.
        if (z <= 0.0 || z > zc + params.threshold) {
            z = zc + params.clamp;
        }
        z_sum += g * z;
        z_weight += g;
    }
    return vec2<f32>(z_sum / z_weight, t_sum / max(t_weight, 1e-20));
}

@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(fullscreen_ndc(i), 0.0, 1.0);
}

@fragment
fn fs_filter_across(@builtin(position) p: vec4<f32>) -> @location(0) vec4<u32> {
    return vec4<u32>(bitcast<vec2<u32>>(filtered(vec2<i32>(p.xy), vec2<i32>(1, 0), true)), 0u, 0u);
}

@fragment
fn fs_filter_down(@builtin(position) p: vec4<f32>) -> @location(0) vec4<u32> {
    return vec4<u32>(bitcast<vec2<u32>>(filtered(vec2<i32>(p.xy), vec2<i32>(0, 1), false)), 0u, 0u);
}

// The surface under pixel `px` of the filtered maps: its front (depth
// `maps.x`) or its back (the front carried along the pixel's ray by the
// thickness `maps.y`: the back of a single layer).
// From the sun, along the light from texel `px`'s origin.
fn surface_point(px: vec2<i32>, maps: vec2<f32>, back: bool, from_sun: bool) -> vec3<f32> {
    if (from_sun) {
        // (maps.y: the back's depth.)
        let t = select(maps.x, max(maps.y, maps.x), back);
        return sun_origin(vec2<f32>(px) + 0.5) + sun_direction() * t;
    }
    let carried = select(0.0, max(maps.y, 0.0), back);
    let front = pixel_point(vec2<f32>(px) + 0.5, maps.x);
    return front + normalize(front - frame.view.position) * carried;
}

// The difference from `centre` (depth zc) towards the neighbour along
// `axis` whose depth is nearer zc, oriented along +axis, on the front or
// the back; w = 0 where both are other layers (or off the screen).
fn side(px: vec2<i32>, axis: vec2<i32>, zc: f32, centre: vec3<f32>, back: bool, from_sun: bool) -> vec4<f32> {
    let size = vec2<i32>(textureDimensions(depth_source));
    var best = vec4<f32>(0.0);
    var best_gap = params.threshold;
    for (var sign = -1; sign <= 1; sign += 2) {
        let s = px + sign * axis;
        if (any(s < vec2<i32>(0)) || any(s >= size)) {
            continue;
        }
        let maps = maps_at(s);
        let gap = abs(maps.x - zc);
        if (maps.x <= 0.0 || gap > best_gap || (best.w > 0.0 && gap >= best_gap)) {
            continue;
        }
        best_gap = gap;
        best = vec4<f32>((surface_point(s, maps, back, from_sun) - centre) * f32(sign), 1.0);
    }
    return best;
}

// The unit normal of the front (facing the eye) or of the back (facing
// away) at `px`, from the differences across and down; `fallback` where
// the pixel has no neighbour of its layer either way.
fn surface_normal(px: vec2<i32>, maps: vec2<f32>, back: bool, fallback: vec3<f32>, from_sun: bool) -> vec3<f32> {
    let centre = surface_point(px, maps, back, from_sun);
    let across = side(px, vec2<i32>(1, 0), maps.x, centre, back, from_sun);
    let down = side(px, vec2<i32>(0, 1), maps.x, centre, back, from_sun);
    var n = fallback;
    if (across.w > 0.0 && down.w > 0.0) {
        let c = cross(across.xyz, down.xyz);
        n = select(fallback, normalize(c), dot(c, c) > 1e-20);
    }
    // Turned to the side the fallback faces.
    return select(n, -n, dot(n, fallback) < 0.0);
}

@fragment
fn fs_shade(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(p.xy);
    let maps = maps_at(px);
    let w = maps.x;
    let z_scene = textureLoad(scene_depth, px, 0).r;
    if (w <= 0.0 || w > scene_w(p.xy, z_scene)) {
        discard;
    }
    let eye = frame.view.position;
    let world = pixel_point(p.xy, w);
    let dir = normalize(world - eye);
    // Step 3: normals from depth, facing the eye; the back's from the
    // depth plus the thickness, facing away.
    let n = surface_normal(px, maps, false, -dir, false);
    let n_back = surface_normal(px, maps, true, dir, false);
    let thickness = max(maps.y, 0.0);

    let ior = frame.water.ior;
    let cos_i = max(dot(-dir, n), 0.0);
    let reflectance = fresnel(frame.modes.fresnel, frame.water.fresnel_power, cos_i, 1.0, ior);
    let visibility = sun_visibility(world, n);
    let reflected = reflect(dir, n);
    var mirror = sky_towards(reflected);
    if (dot(reflected, frame.light.sun_dir) > frame.light.cos_sun_radius) {
        mirror += frame.light.sun_illuminance * frame.light.inv_sun_solid_angle * visibility;
    }
    // Through the liquid: bent in at the front, across its thickness, bent
    // out at the back (or reflected there, past the critical angle). What
    // lies that way: its distance guessed from the scene's depth under this
    // pixel, then looked up in the image as it was before the liquid.
    let inside = refract(dir, n, 1.0 / ior);
    let refracted_out = refract(inside, -n_back, ior);
    let tir = dot(refracted_out, refracted_out) < 0.5;
    let out_dir = select(refracted_out, reflect(inside, -n_back), tir);
    let leaving = select(fresnel_exact(max(dot(inside, n_back), 0.0), ior, 1.0), 0.0, tir);
    // Where that lies on the screen, as an offset from this pixel: the
    // refracted path's lateral departure from the straight ray, at the
    // distance of the scene behind this pixel, in pixels by the world
    // step one pixel makes at this depth (scaled to that distance).
    // Offsets from the pixel rather than projections of world points: a
    // lookup at a projected point made lavapipe's memory grow 2.5 MB a
    // frame (found by bisecting this shader; the cause inside Mesa was not
    // found; tests/memory.rs guards it).
    let across = pixel_point(p.xy + vec2<f32>(1.0, 0.0), w) - world;
    let down = pixel_point(p.xy + vec2<f32>(0.0, 1.0), w) - world;
    let to_world = distance(world, eye);
    let to_scene = scene_w(p.xy, z_scene) * to_world / w;
    let gap = clamp(to_scene - to_world - thickness, 0.05, 100.0);
    let seen_at = world + inside * thickness + out_dir * gap;
    let straight = world + dir * dot(seen_at - world, dir);
    let lateral = seen_at - straight;
    let scale = to_world / distance(straight, eye);
    let offset = vec2<f32>(dot(lateral, across) / dot(across, across), dot(lateral, down) / dot(down, down)) * scale;
    let size = vec2<f32>(textureDimensions(behind_tex));
    let q = p.xy + offset;
    let on_screen = all(q >= vec2<f32>(0.0)) & all(q < size);
    let seen = textureLoad(behind_tex, vec2<i32>(clamp(select(p.xy, q, on_screen), vec2<f32>(0.0), size - 1.0)), 0).rgb;
    let behind = select(sky_towards(out_dir), seen, on_screen) * (1.0 - leaving);
    let through = behind * transmittance(thickness);
    // Light the water itself scatters towards the eye over its thickness.
    let scatter = frame.water.scattering * thickness * air_irradiance(n, vec3<f32>(visibility)) / PI;
    let color = reflectance * mirror + (1.0 - reflectance) * (through + scatter);
    let shaded = clamp(through_air(eye, world, color), vec3<f32>(0.0), vec3<f32>(60000.0));
    // The normals debug view as a select, not a branch on the uniform (see
    // `through_fog`).
    let normals_view = frame.modes.debug_view == VIEW_NORMALS;
    return vec4<f32>(select(shaded, n * 0.5 + 0.5, normals_view), 1.0);
}

// ---- From the sun ----

// Where texel `pixel`'s ray (framebuffer position, y down) starts: on the
// sun's view's near plane.
fn sun_origin(pixel: vec2<f32>) -> vec3<f32> {
    let ndc = vec2<f32>(2.0 * pixel.x / params.sun_resolution - 1.0, 1.0 - 2.0 * pixel.y / params.sun_resolution);
    let h = params.sun_inv_view_proj * vec4<f32>(ndc, 0.0, 1.0);
    return h.xyz / h.w;
}

// The way the light travels (unit).
fn sun_direction() -> vec3<f32> {
    let q = params.sun_inv_view_proj;
    let near = q * vec4<f32>(0.0, 0.0, 0.0, 1.0);
    let far = q * vec4<f32>(0.0, 0.0, 1.0, 1.0);
    return normalize(far.xyz / far.w - near.xyz / near.w);
}

struct SunSplatOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) centre: vec3<f32>,
}

@vertex
fn vs_sphere_sun(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> SunSplatOut {
    let corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let p = particles[i];
    let m = params.sun_view_proj;
    // Orthographic: the sphere's disc is r times each row's scale across,
    // widened by a texel so every texel its ray meets is drawn.
    let scale = vec2<f32>(length(vec3<f32>(m[0][0], m[1][0], m[2][0])), length(vec3<f32>(m[0][1], m[1][1], m[2][1])));
    var out: SunSplatOut;
    out.clip = m * vec4<f32>(p.position, 1.0);
    out.clip = vec4<f32>(out.clip.xy + corners[v] * (params.radius * scale + 2.0 / params.sun_resolution), out.clip.zw);
    if (p.alive == 0u) {
        out.clip = vec4<f32>(0.0, 0.0, 2.0, 1.0);
    }
    out.centre = p.position;
    return out;
}

// The texel's ray through the sphere: (entry, exit) in metres from the
// near plane; `x` < 0 where it misses.
fn sun_chord(in: SunSplatOut) -> vec2<f32> {
    let origin = sun_origin(in.clip.xy);
    let oc = origin - in.centre;
    let b = dot(oc, sun_direction());
    let disc = b * b - (dot(oc, oc) - params.radius * params.radius);
    let s = sqrt(max(disc, 0.0));
    return select(vec2<f32>(-1.0), vec2<f32>(-b - s, -b + s), disc >= 0.0);
}

@fragment
fn fs_depth_sun(in: SunSplatOut) -> DepthOut {
    let c = sun_chord(in);
    if (c.x <= 0.0) {
        discard;
    }
    var out: DepthOut;
    out.w = bitcast<u32>(c.x);
    out.depth = c.x / params.sun_span;
    return out;
}

// The farthest back (blended by max): where the light leaves the spheres'
// union. (The chords' sum, the camera's thickness, ripples with the
// particles' lattice by ±10%, which would put the exit of a liquid resting
// on the floor now above it, now below.)
@fragment
fn fs_back_sun(in: SunSplatOut) -> @location(0) vec4<f32> {
    let c = sun_chord(in);
    if (c.x <= 0.0) {
        discard;
    }
    return vec4<f32>(c.y, 0.0, 0.0, 0.0);
}

struct FaceOut {
    // Outward normal × the index of refraction and the light view's z, as
    // float bits (passes/water_object/light.wgsl's faces).
    @location(0) face: vec4<u32>,
    @builtin(frag_depth) depth: f32,
}

// The face under texel `p` that the light enters (the front, facing the
// sun) or leaves (the back).
fn sun_face(p: vec4<f32>, back: bool) -> FaceOut {
    let px = vec2<i32>(p.xy);
    let maps = maps_at(px);
    if (maps.x <= 0.0) {
        discard;
    }
    let d = sun_direction();
    let n = surface_normal(px, maps, back, select(-d, d, back), true);
    let z = select(maps.x, max(maps.y, maps.x), back) / params.sun_span;
    var out: FaceOut;
    out.face = bitcast<vec4<u32>>(vec4<f32>(n * params.ior, z));
    out.depth = z;
    return out;
}

@fragment
fn fs_sun_front(@builtin(position) p: vec4<f32>) -> FaceOut {
    return sun_face(p, false);
}

@fragment
fn fs_sun_back(@builtin(position) p: vec4<f32>) -> FaceOut {
    return sun_face(p, true);
}

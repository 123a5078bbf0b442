// Light through refractive objects (seed 004 §3.2, after Hu et al. 2010 and
// Wyman 2005): one thread per texel of the objects' light view. Where the
// texel sees an object's front face at p0, the sunlight refracts in (Snell,
// Fresnel, the face's own index of refraction), is marched against the
// depth of the nearest back faces (where it leaves that object: a glass
// tank's wall hands its light on straight, not through the water beside
// it as if one body) to its exit point p1,
// refracts out (rays that would be totally reflected are dropped), and is
// marched against the opaque scene's depth from the light to where it lands,
// p2 (or meets the floor plane). The path p1 → p2 becomes a beam tube for
// the god-ray ribbons (the volume caustic in the fog) and its light is
// splatted where it lands (the caustic on the floor). A path whose exit
// lies behind the opaque scene or within a texel of it (water resting on
// the floor) lands where it meets the scene, inside the water. CPU twin of the path:
// hydrolux_core::water_object.
#import constants, frame, optics, tube

struct ObjectLightParams {
    // Light clip → world.
    inv_view_proj: mat4x4<f32>,
    // Texels per side of the light view (K), march steps.
    resolution: u32,
    march_steps: u32,
    _pad0: u32,
    _pad1: u32,
    // Texel area across the beam (m²), height of the floor plane (m),
    // longest path to march (m). (Each face carries its index of refraction
    // as its normal's length.)
    texel_area: f32,
    _pad4: f32,
    floor_y: f32,
    reach: f32,
    // Fixed-point scale of the splat; 1 if there is a floor plane.
    fixed_point_scale: f32,
    has_floor: u32,
    _pad2: f32,
    _pad3: f32,
}

@group(1) @binding(0) var<uniform> params: ObjectLightParams;
// Faces from the light: (normal, depth) as the bits of four f32.
@group(1) @binding(1) var front_tex: texture_2d<u32>;
@group(1) @binding(2) var back_tex: texture_2d<u32>;
@group(1) @binding(3) var scene_tex: texture_2d<f32>;
@group(1) @binding(4) var<storage, read_write> tubes: array<Tube>;
@group(1) @binding(5) var<storage, read_write> accum: array<atomic<u32>>;
@group(1) @binding(6) var map_out: texture_storage_2d<rgba16float, write>;

// World → (light uv, depth).
fn to_light(p: vec3<f32>) -> vec3<f32> {
    let clip = frame.objects.light_view_proj * vec4<f32>(p, 1.0);
    return vec3<f32>(0.5 + 0.5 * clip.x, 0.5 - 0.5 * clip.y, clip.z);
}

fn from_light(uv: vec2<f32>, z: f32) -> vec3<f32> {
    let h = params.inv_view_proj * vec4<f32>(2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y, z, 1.0);
    return h.xyz / h.w;
}

fn texel_of(uv: vec2<f32>) -> vec2<i32> {
    let k = i32(params.resolution);
    return clamp(vec2<i32>(floor(uv * f32(k))), vec2<i32>(0), vec2<i32>(k - 1));
}

fn load_back(texel: vec2<i32>) -> vec4<f32> {
    return bitcast<vec4<f32>>(textureLoad(back_tex, texel, 0));
}

fn in_view(uv: vec2<f32>) -> bool {
    return all(uv >= vec2<f32>(0.0)) && all(uv <= vec2<f32>(1.0));
}

// Depth of the back faces (which = 0; −1 where no object) or of the opaque
// scene (which = 1) under `uv`.
fn depth_at(uv: vec2<f32>, which: u32) -> f32 {
    if (which == 0u) {
        return load_back(texel_of(uv)).w;
    }
    return textureLoad(scene_tex, texel_of(uv), 0).r;
}

// Where along p + dir·t, between `lo` (in front of the depth map `which`)
// and `hi` (behind it), the ray passes behind it: `steps` halvings.
fn bisect(p: vec3<f32>, dir: vec3<f32>, lo_t: f32, hi_t: f32, which: u32, steps: i32) -> f32 {
    var lo = lo_t;
    var hi = hi_t;
    for (var k = 0; k < steps; k++) {
        let mid = 0.5 * (lo + hi);
        let m = to_light(p + dir * mid);
        if (m.z >= depth_at(m.xy, which)) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    return hi;
}

// March from p along dir until the ray passes behind the depth map `which`,
// then refine by bisection; the distance, or −1 if it leaves the view first.
fn march(p: vec3<f32>, dir: vec3<f32>, which: u32) -> f32 {
    let steps = params.march_steps;
    let dt = params.reach / f32(steps);
    var prev = 0.0;
    for (var i = 1u; i <= steps; i++) {
        let t = f32(i) * dt;
        let q = to_light(p + dir * t);
        if (!in_view(q.xy) || q.z > 1.0) {
            return -1.0;
        }
        if (q.z >= depth_at(q.xy, which)) {
            return bisect(p, dir, prev, t, which, 8);
        }
        prev = t;
    }
    return -1.0;
}

fn deposit(channel: u32, texel: vec2<i32>, value: f32) {
    let k = i32(params.resolution);
    if (any(texel < vec2<i32>(0)) || any(texel >= vec2<i32>(k))) {
        return;
    }
    let index = channel * u32(k * k) + u32(texel.y * k + texel.x);
    atomicAdd(&accum[index], u32(value * params.fixed_point_scale + 0.5));
}

// Add irradiance `e` (relative to the sun's, on a plane facing it) landing
// at p, with bilinear weights over the four nearest texels.
fn splat(p: vec3<f32>, e: vec3<f32>) {
    let k = f32(params.resolution);
    let f = to_light(p).xy * k - 0.5;
    let base = floor(f);
    let a = f - base;
    let t = vec2<i32>(base);
    for (var c = 0u; c < 3u; c++) {
        deposit(c, t, e[c] * (1.0 - a.x) * (1.0 - a.y));
        deposit(c, t + vec2<i32>(1, 0), e[c] * a.x * (1.0 - a.y));
        deposit(c, t + vec2<i32>(0, 1), e[c] * (1.0 - a.x) * a.y);
        deposit(c, t + vec2<i32>(1, 1), e[c] * a.x * a.y);
    }
}

@compute @workgroup_size(8, 8, 1)
fn clear(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = params.resolution;
    if (id.x < k && id.y < k) {
        for (var c = 0u; c < 3u; c++) {
            atomicStore(&accum[c * k * k + id.y * k + id.x], 0u);
        }
    }
}

@compute @workgroup_size(8, 8, 1)
fn trace(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = params.resolution;
    if (id.x >= k || id.y >= k) {
        return;
    }
    var tube: Tube;
    tube.start = vec4<f32>(0.0);
    tube.dir = vec4<f32>(0.0);
    tube.tint = vec4<f32>(0.0);
    let front = bitcast<vec4<f32>>(textureLoad(front_tex, vec2<i32>(id.xy), 0));
    let l = frame.light.sun_dir;
    let ior = length(front.xyz);
    let n0 = front.xyz / max(ior, 1e-6);
    let cos0 = dot(n0, l);
    if (front.w <= 1.0 && cos0 > 0.0) {
        let uv = (vec2<f32>(id.xy) + 0.5) / f32(k);
        let p0 = from_light(uv, front.w);
        let t1 = refract(-l, n0, 1.0 / ior);
        let s1 = march(p0, t1, 0u);
        // Where the exit lies behind the opaque scene, or within a texel of
        // it (a liquid resting on the floor: its surface there is as rough
        // as its particles), the path meets the scene inside the water and
        // lands there, through its entry alone: found by bisection along
        // p0 → p1.
        let span = distance(from_light(uv, 1.0), from_light(uv, 0.0));
        let contact = sqrt(params.texel_area) / span;
        let exit = to_light(p0 + t1 * max(s1, 0.0));
        let hidden = s1 > 0.0 && exit.z + contact >= depth_at(exit.xy, 1u);
        if (hidden) {
            let hi = bisect(p0, t1, 0.0, s1, 1u, 12);
            let transmitted = 1.0 - fresnel_exact(cos0, 1.0, ior);
            let tint = exp(-frame.water.absorption * hi);
            // No tube: the path never leaves the water into the air's fog.
            splat(p0 + t1 * hi, transmitted * tint);
        }
        if (s1 > 0.0 && !hidden) {
            let p1 = p0 + t1 * s1;
            let back = load_back(texel_of(to_light(p1).xy));
            let n1 = normalize(back.xyz);
            let cos1 = dot(t1, n1);
            let t2 = refract(t1, -n1, ior);
            if (back.w >= 0.0 && cos1 > 0.0 && dot(t2, t2) > 0.5) {
                let transmitted = (1.0 - fresnel_exact(cos0, 1.0, ior)) * (1.0 - fresnel_exact(cos1, ior, 1.0));
                let tint = exp(-frame.water.absorption * s1);
                var s2 = march(p1, t2, 1u);
                if (s2 < 0.0) {
                    s2 = params.reach;
                    if (params.has_floor != 0u && t2.y < -1e-4) {
                        s2 = min(s2, (params.floor_y - p1.y) / t2.y);
                    }
                }
                tube.start = vec4<f32>(p1, s2);
                tube.dir = vec4<f32>(t2, transmitted * params.texel_area);
                tube.tint = vec4<f32>(tint, 1.0);
                splat(p1 + t2 * s2, transmitted * tint);
            }
        }
    }
    tubes[id.y * k + id.x] = tube;
}

// A [1 2 1]/4 × [1 2 1]/4 filter into the map; alpha: the scene's depth.
@compute @workgroup_size(8, 8, 1)
fn resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = params.resolution;
    if (id.x >= k || id.y >= k) {
        return;
    }
    var sum = vec3<f32>(0.0);
    for (var dj = -1; dj <= 1; dj++) {
        for (var di = -1; di <= 1; di++) {
            let t = vec2<i32>(id.xy) + vec2<i32>(di, dj);
            if (any(t < vec2<i32>(0)) || any(t >= vec2<i32>(i32(k)))) {
                continue;
            }
            let w = (2.0 - f32(abs(di))) * (2.0 - f32(abs(dj))) / 16.0;
            for (var c = 0u; c < 3u; c++) {
                sum[c] += w * f32(atomicLoad(&accum[c * k * k + u32(t.y) * k + u32(t.x)])) / params.fixed_point_scale;
            }
        }
    }
    textureStore(map_out, vec2<i32>(id.xy), vec4<f32>(sum, textureLoad(scene_tex, vec2<i32>(id.xy), 0).r));
}

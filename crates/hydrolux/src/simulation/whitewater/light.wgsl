// How white water's particles are drawn and lit, shared by the surface
// water's (particles.wgsl) and the volumetric liquid's
// (liquid/white_water_draw.wgsl): the quad over a particle, spray's
// forward scattering and a bubble's bright rim.
#import constants, frame, sky_bindings, medium, hash, lighting

// Corner v (0–5, two triangles) of a quad, in [-1, 1]².
fn quad_corner(v: u32) -> vec2<f32> {
    let corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    return corners[v];
}

struct ParticleQuad {
    world: vec3<f32>,
    // Opacity that keeps a sub-pixel particle's energy (its area over the
    // pixel's), and how much the streak thins it.
    weight: f32,
    // How wide it is drawn (m), a pixel there (m), and how far it moves
    // across the view over the shutter (m; 0 when it is not streaked).
    drawn: f32,
    pixel: f32,
    travel: f32,
}

// Corner c (in [-1, 1]²) of a quad facing the eye over a particle `size`
// wide at `position` moving at `velocity`: at least `min_pixels` across
// (fainter by the area it lacks), stretched into a streak along its motion
// across the view over `shutter` s (fainter by the length it gains).
fn particle_quad(position: vec3<f32>, velocity: vec3<f32>, size: f32, shutter: f32, min_pixels: f32, c: vec2<f32>) -> ParticleQuad {
    let eye = frame.view.position;
    let dist = max(distance(position, eye), 1e-3);
    let pixel = 2.0 * dist / (frame.view.size.y * frame.view.view_proj[1][1]);
    let drawn = max(size, min_pixels * pixel);
    var weight = (size * size) / (drawn * drawn);
    let forward = (position - eye) / dist;
    var right = normalize(cross(forward, vec3<f32>(0.0, 1.0, 0.0)) + vec3<f32>(1e-6, 0.0, 0.0));
    var up = cross(right, forward);
    var half_length = 0.5 * drawn;
    let across = velocity - forward * dot(velocity, forward);
    var travel = length(across) * shutter;
    if (travel > 0.1 * drawn) {
        right = across / length(across);
        up = normalize(cross(right, forward));
        half_length = 0.5 * (drawn + travel);
        weight *= drawn / (drawn + travel);
    } else {
        travel = 0.0;
    }
    var q: ParticleQuad;
    q.world = position + right * c.x * half_length + up * c.y * 0.5 * drawn;
    q.weight = weight;
    q.drawn = drawn;
    q.pixel = pixel;
    q.travel = travel;
    return q;
}

// A parcel of spray close up is drops, far off their mist: the twin of
// hydrolux_core::whitewater::spray_look (same constants, checked by naga).
const DRAWN_DROPS: u32 = 24u;
const MIN_DROP_PIXELS: f32 = 0.6;
const MIST_BELOW_SPACING: f32 = 0.75;
const DROPS_FROM_SPACING: f32 = 1.5;
const SALT_RADIUS: u32 = 0x5A1Du;
const SALT_ANGLE: u32 = 0x7E11u;
const SPREAD: f32 = 2.0;

// A parcel as its quad is drawn, in the quad's units (half its width
// across the motion is 1; the quad spans the drops' SPREAD): its radius, a pixel, how far it moves either
// way over the shutter, how much of its disc its drops cover, and how many
// real drops it holds.
struct SprayShape {
    parcel: f32,
    pixel: f32,
    streak: f32,
    cover: f32,
    drops: f32,
}

fn spray_shape(q: ParticleQuad, size: f32, cover: f32, drops: f32) -> SprayShape {
    return SprayShape(size / q.drawn, q.pixel / (0.5 * q.drawn), q.travel / q.drawn, cover, drops);
}

// A drawn drop's radius in parcel radii: DRAWN_DROPS of them cover `cover`.
fn drawn_drop_radius(cover: f32) -> f32 {
    return sqrt(cover / f32(DRAWN_DROPS));
}

// Drop k of parcel `id`, in quad units: uniform over SPREAD parcel radii.
fn drop_centre(id: u32, k: u32, parcel: f32, drop_radius: f32) -> vec2<f32> {
    let r = sqrt(random(id, k, SALT_RADIUS)) * (SPREAD - drop_radius) * parcel;
    let a = TAU * random(id, k, SALT_ANGLE);
    return vec2<f32>(r * cos(a), r * sin(a));
}

// The parcel's drops at `quad`, each a capsule swept over the shutter, its
// opacity spread over what it is drawn on (the parcel's light is kept).
fn drops_opacity(quad: vec2<f32>, s: SprayShape, id: u32) -> f32 {
    let unit = drawn_drop_radius(s.cover);
    let a = unit * s.parcel;
    let drawn = max(a, MIN_DROP_PIXELS * s.pixel);
    // What a capsule with edges a pixel soft covers: π(A² + p²/12) + 4sA.
    let footprint = s.pixel * s.pixel / 12.0;
    let energy = PI * a * a / (PI * (drawn * drawn + footprint) + 4.0 * s.streak * drawn);
    let x = quad.x * (1.0 + s.streak);
    let y = quad.y;
    var covered = 0.0;
    for (var k = 0u; k < DRAWN_DROPS; k++) {
        let c = drop_centre(id, k, s.parcel, unit);
        let ex = max(abs(x - c.x) - s.streak, 0.0);
        let ey = y - c.y;
        let d = sqrt(ex * ex + ey * ey);
        covered += clamp((drawn - d) / s.pixel + 0.5, 0.0, 1.0);
    }
    return min(covered * energy, 1.0);
}

// The parcel's optical depth with its drops spread evenly.
fn mist_depth(quad: vec2<f32>, s: SprayShape) -> f32 {
    let r2 = quad.x * quad.x + quad.y * quad.y;
    if (r2 > 1.0) {
        return 0.0;
    }
    let density = (1.0 - r2) * (1.0 - r2);
    return 3.0 * s.cover * density * s.parcel * s.parcel / (1.0 + s.streak);
}

// The mist the drops make where they are too small to draw.
fn mist_opacity(quad: vec2<f32>, s: SprayShape) -> f32 {
    return 1.0 - exp(-mist_depth(quad, s));
}

// How much of the parcel is drawn as drops rather than mist: by its real
// drops' mean spacing in pixels (the drawn ones' where it has fewer).
fn drops_resolved(s: SprayShape) -> f32 {
    let spread = SPREAD * s.parcel;
    let drops = max(s.drops, f32(DRAWN_DROPS));
    let spacing = spread * sqrt(PI / drops) / s.pixel;
    let t = clamp((spacing - MIST_BELOW_SPACING) / (DROPS_FROM_SPACING - MIST_BELOW_SPACING), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// What the parcel hides of what is behind it, less what its drops pass on
// straight ahead (FORWARD_SHARE).
fn spray_opacity(quad: vec2<f32>, s: SprayShape, id: u32) -> f32 {
    let resolved = drops_resolved(s);
    if (resolved == 0.0) {
        return 1.0 - exp(-(1.0 - FORWARD_SHARE) * mist_depth(quad, s));
    }
    let drops = drops_opacity(quad, s, id);
    return (mist_opacity(quad, s) * (1.0 - resolved) + drops * resolved) * (1.0 - FORWARD_SHARE);
}

// Twins: hydrolux_core::whitewater::spray_look::{spray_asymmetry,
// spray_sky_share}. The delta-Eddington split: g² of what a drop scatters
// goes straight on (the background shows through), the rest with
// asymmetry g/(1 + g), forgotten over τ' = (1 − g²)τ scatterings.
const DROP_ASYMMETRY: f32 = 0.8;
const FORWARD_SHARE: f32 = DROP_ASYMMETRY * DROP_ASYMMETRY;

fn spray_asymmetry(tau: f32) -> f32 {
    let scattered = (1.0 - FORWARD_SHARE) * max(tau, 0.0);
    return DROP_ASYMMETRY / (1.0 + DROP_ASYMMETRY) / (1.0 + scattered);
}

fn spray_sky_share(view_y: f32, g_in: f32) -> f32 {
    let g = clamp(g_in, 0.01, 0.95);
    let up = (1.0 + g) / (2.0 * g) - (1.0 - g * g) / (2.0 * g * sqrt(1.0 + g * g));
    let b = 1.5 * pow((1.0 - g) / g, 1.12);
    return 0.5 + (up - 0.5) * (1.0 + b) * view_y / (abs(view_y) + b);
}

// Spray seen along `view` where its optical depth is `tau`: thin, its
// drops throw the sun and the sky forward, bright against the light;
// thick, the light inside has scattered many times and comes out evenly,
// white from every side. The sky is the mean radiance its irradiance
// gives (as foam is lit), the world below the grey world's bounce.
fn spray_radiance(view: vec3<f32>, tau: f32) -> vec3<f32> {
    let g = spray_asymmetry(tau);
    let phase = henyey_greenstein(dot(view, frame.light.sun_dir), g);
    let share = spray_sky_share(view.y, g);
    let sky = frame.light.sky_ambient / PI * share + below_horizon_radiance() * (1.0 - share);
    return frame.light.sun_illuminance * phase + sky;
}

// A sphere of air in water at quad radius² r2 (0 centre, 1 rim) in `light`
// (what reaches it, already dimmed by the water in front), premultiplied:
// total internal reflection makes its rim bright (grazing rays inside the
// water meet the air beyond the critical angle); its middle lets through
// what is behind.
fn bubble_look(r2: f32, light: vec3<f32>, weight: f32) -> vec4<f32> {
    let rim = smoothstep(0.55, 0.95, r2) * (1.0 - smoothstep(0.95, 1.0, r2));
    let glint = pow(max(1.0 - r2, 0.0), 8.0) * 0.5;
    let alpha = (0.15 + 0.85 * rim) * weight;
    return vec4<f32>(light * (0.6 + 2.5 * rim + glint) * alpha, alpha);
}

// The world point at pixel `frag` (framebuffer coordinates) and depth
// `depth` of the main view.
fn world_at_pixel(frag: vec2<f32>, depth: f32) -> vec3<f32> {
    let ndc = vec2<f32>(frag.x * frame.view.inv_size.x * 2.0 - 1.0, 1.0 - frag.y * frame.view.inv_size.y * 2.0);
    let h = frame.view.inv_view_proj * vec4<f32>(ndc, depth, 1.0);
    return h.xyz / h.w;
}

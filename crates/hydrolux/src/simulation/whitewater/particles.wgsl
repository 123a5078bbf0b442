// White water's particles drawn (seed 003 §4.5–4.6): instanced quads read
// from the alive list (an indirect draw: the count never comes back to the
// CPU). Spray is a soft, lit parcel of drops that scatters the sun forward
// (Henyey–Greenstein, bright against the light), stretched into a streak
// along its motion over the shutter; bubbles are spheres of air whose rim
// is bright by total internal reflection and whose middle lets through
// what is behind, seen through the water above them. The scene's depth
// is tested by hand: a bubble under the surface shows through it. Spray
// sits in the scene's fog like everything else (`through_fog`).
#import constants, frame, sky_bindings, medium, particle, fog, white_water_light

struct DrawParams {
    // Capacity C, which alive list is drawn (0, 1); how much of a spray
    // parcel's disc its drops cover and how many drops it holds
    // (hydrolux_core's `parcel_cover`, `parcel_drops`).
    capacity: u32,
    list: u32,
    spray_cover: f32,
    spray_drops: f32,
    // Spray parcel size (m), bubble cloud size (m), shutter (s), vertical
    // reach of the surface (m).
    spray_size: f32,
    bubble_size: f32,
    shutter: f32,
    vertical_reach: f32,
}

@group(1) @binding(0) var<uniform> params: DrawParams;
@group(1) @binding(1) var<storage, read> particles: array<Particle>;
@group(1) @binding(2) var<storage, read> slots: array<u32>;
@group(2) @binding(0) var scene_depth: texture_2d<f32>;


struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    // Quad coordinates: x along the streak, y across, in [-1, 1].
    @location(0) quad: vec2<f32>,
    @location(1) @interpolate(flat) kind: u32,
    @location(2) centre: vec3<f32>,
    // Opacity that keeps a sub-pixel particle's energy (its area over the
    // pixel's), and how much the streak thins it.
    @location(3) weight: f32,
    // Spray: the parcel's shape (SprayShape, less its drops, a uniform)
    // and which parcel it is; bubbles: x is how far its look is resolved
    // (1) or a soft blob (0).
    @location(4) @interpolate(flat) shape: vec4<f32>,
    @location(5) @interpolate(flat) id: u32,
}

// Least width (pixels) a spray parcel and a bubble are drawn: a bubble
// under this is a soft blob whose light is spread over it, never a
// single bright pixel.
const SPRAY_MIN_PIXELS: f32 = 1.5;
const BUBBLE_MIN_PIXELS: f32 = 3.0;
// A bubble's look averaged over its disc (bubble_look): opacity, and its
// light over its opacity, for the blob it becomes when unresolved.
const BUBBLE_MEAN_ALPHA: f32 = 0.341;
const BUBBLE_MEAN_GAIN: f32 = 1.91;

@vertex
fn vs_main(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> VertexOut {
    let slot = slots[params.list * params.capacity + i];
    let p = particles[slot];
    let c = quad_corner(v);
    let is_bubble = p.kind == PARTICLE_BUBBLE;
    let size = select(params.spray_size, max(params.bubble_size, 2.0 * p.radius), is_bubble);
    let min_pixels = select(SPRAY_MIN_PIXELS, BUBBLE_MIN_PIXELS, is_bubble);
    // A spray parcel's quad spans its drops' spread.
    let quad_size = select(SPREAD * size, size, is_bubble);
    let q = particle_quad(p.position, p.velocity, quad_size, params.shutter, min_pixels, c);
    var out: VertexOut;
    out.clip = frame.view.view_proj * vec4<f32>(q.world, 1.0);
    out.quad = c;
    out.kind = p.kind;
    out.centre = p.position;
    out.weight = q.weight;
    out.id = p.id;
    if (is_bubble) {
        // Resolved from 3 pixels across to 6.
        out.shape = vec4<f32>(smoothstep(3.0, 6.0, size / q.pixel), 0.0, 0.0, 0.0);
    } else {
        let s = spray_shape(q, size, params.spray_cover, params.spray_drops);
        out.shape = vec4<f32>(s.parcel, s.pixel, s.streak, s.cover);
    }
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let r2 = dot(in.quad, in.quad);
    let is_bubble = in.kind == PARTICLE_BUBBLE;
    if (r2 > 1.0 && is_bubble) {
        discard;
    }
    let eye = frame.view.position;
    let d = textureLoad(scene_depth, vec2<i32>(in.clip.xy), 0).x;
    let behind = world_at_pixel(in.clip.xy, d);
    let scene_distance = select(distance(behind, eye), 1e9, d >= 1.0);
    let particle_distance = distance(in.centre, eye);
    let view = (in.centre - eye) / max(particle_distance, 1e-4);
    if (is_bubble) {
        // Under the water the eye looks through: behind a surface point it
        // still shows, dimmed by the water between.
        var through = vec3<f32>(1.0);
        if (particle_distance > scene_distance) {
            let at_surface = abs(behind.y) < params.vertical_reach;
            if (!at_surface || eye.y < 0.0) {
                discard;
            }
            through = transmittance((particle_distance - scene_distance) * 1.0);
        }
        let depth = max(-in.centre.y, 0.0);
        let light = underwater_irradiance(depth, vec3<f32>(0.0, 1.0, 0.0), 1.0) / PI;
        let sharp = bubble_look(r2, light * through, in.weight);
        let blob_alpha = BUBBLE_MEAN_ALPHA * 3.0 * (1.0 - r2) * (1.0 - r2) * in.weight;
        let blob = vec4<f32>(light * through * BUBBLE_MEAN_GAIN * blob_alpha, blob_alpha);
        return mix(blob, sharp, in.shape.x);
    }
    if (particle_distance > scene_distance + 0.05) {
        discard;
    }
    // Soft where it meets what is behind it (no hard cut at the water).
    let soft = clamp((scene_distance - particle_distance) / 0.3, 0.0, 1.0);
    let shape = SprayShape(in.shape.x, in.shape.y, in.shape.z, in.shape.w, params.spray_drops);
    let alpha = spray_opacity(in.quad, shape, in.id) * soft;
    if (alpha <= 0.0) {
        discard;
    }
    let color = spray_radiance(view, mist_depth(in.quad, shape));
    // In the scene's fog: dimmed by the air between, and the fog's own glow
    // in front of it put back over what the parcel hides.
    return vec4<f32>(through_fog(eye, in.centre, color) * alpha, alpha);
}

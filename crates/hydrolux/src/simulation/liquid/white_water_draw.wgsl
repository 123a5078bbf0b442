// The liquid's white water drawn (seed 003 §4.4–4.6; its step is
// white_water.wgsl): one instanced quad per slot of the pool (dead slots
// fold to nothing), blended over the image after the clear things, tested
// by hand against the opaque scene's depth and the liquid surface's.
// - Spray: a soft parcel of drops scattering the sun forward, streaked
//   along its motion over the shutter, in the scene's fog.
// - Foam: a fleck of bubbles on the surface, rough and white: a sphere's
//   normal across the quad lit by the sun (shadowed) and the sky, at
//   foam's albedo; opaque where flecks crowd.
// - Bubbles: spheres of air in the liquid, seen through the water in front
//   of them (dimmed by it), bright at the rim.
#import constants, frame, sky_bindings, medium, fog, lighting, shadow_lookup, object_caustics, modes, liquid_diffuse, white_water_light

struct WhiteWaterDraw {
    // A foam fleck's width (m); the shutter (s); foam's albedo.
    size: f32,
    shutter: f32,
    foam_albedo: f32,
    _pad0: f32,
}

@group(1) @binding(0) var<uniform> params: WhiteWaterDraw;
@group(1) @binding(1) var<storage, read> pool: array<Diffuse>;
@group(2) @binding(0) var scene_depth: texture_2d<f32>;
@group(2) @binding(1) var liquid_depth: texture_2d<f32>;

// Width of each kind over a foam fleck's: drops and bubbles are smaller.
const SPRAY_WIDTH: f32 = 0.6;
const BUBBLE_WIDTH: f32 = 0.4;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) quad: vec2<f32>,
    @location(1) @interpolate(flat) kind: u32,
    @location(2) centre: vec3<f32>,
    @location(3) weight: f32,
    @location(4) size: f32,
}

@vertex
fn vs_main(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> VertexOut {
    let d = pool[i];
    var out: VertexOut;
    if (d.kind == PARTICLE_DEAD) {
        // Outside the clip volume: no fragments.
        out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
        return out;
    }
    let c = quad_corner(v);
    var size = params.size;
    var shutter = 0.0;
    if (d.kind == PARTICLE_SPRAY) {
        size *= SPRAY_WIDTH;
        shutter = params.shutter;
    } else if (d.kind == PARTICLE_BUBBLE) {
        size *= BUBBLE_WIDTH;
    }
    let q = particle_quad(d.position, d.velocity, size, shutter, 1.5, c);
    out.clip = frame.view.view_proj * vec4<f32>(q.world, 1.0);
    out.quad = c;
    out.kind = d.kind;
    out.centre = d.position;
    out.weight = q.weight;
    out.size = size;
    return out;
}

// How much of the sun reaches `p`: the shadow map's visibility, or, among
// the clear things (which the shadow map counts as shadowing), whether
// only they lie between it and the sun (their light view).
fn sun_at(p: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(max(sun_visibility_point(p), sun_past_opaque(p)));
}

// Distance from the eye to what the depth `d` at pixel `frag` holds (far
// away where nothing is drawn).
fn distance_at(frag: vec2<f32>, d: f32) -> f32 {
    return select(distance(world_at_pixel(frag, d), frame.view.position), 1e9, d >= 1.0);
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let r2 = dot(in.quad, in.quad);
    if (r2 > 1.0) {
        discard;
    }
    let eye = frame.view.position;
    let pixel = vec2<i32>(in.clip.xy);
    let scene_distance = distance_at(in.clip.xy, textureLoad(scene_depth, pixel, 0).x);
    let liquid_distance = distance_at(in.clip.xy, textureLoad(liquid_depth, pixel, 0).x);
    let particle_distance = distance(in.centre, eye);
    let view = (in.centre - eye) / max(particle_distance, 1e-4);
    // Behind the opaque scene: hidden (a particle's width of slack, so a
    // fleck on a wall is not cut in half).
    if (particle_distance > scene_distance + in.size) {
        discard;
    }
    let soft = clamp((scene_distance - particle_distance) / in.size + 1.0, 0.0, 1.0);
    // The water in front of it, if the liquid's surface is nearer.
    let under = max(particle_distance - liquid_distance, 0.0);
    if (in.kind == PARTICLE_BUBBLE) {
        let light = air_irradiance(vec3<f32>(0.0, 1.0, 0.0), sun_at(in.centre)) / PI;
        let look = bubble_look(r2, light * transmittance(under), in.weight * soft);
        return vec4<f32>(through_air(eye, in.centre, look.rgb / max(look.a, 1e-4)) * look.a, look.a);
    }
    if (in.kind == PARTICLE_FOAM) {
        // A fleck of many bubbles scatters light many times: lit as a
        // soft, flattened sphere (its normal half-way to the eye's and
        // wrapped towards the sky), its edge a Gaussian falloff, so that
        // crowded flecks merge into froth and lone ones thin into lace.
        let right = normalize(cross(view, vec3<f32>(0.0, 1.0, 0.0)) + vec3<f32>(1e-6, 0.0, 0.0));
        let up = cross(right, view);
        let bulge = normalize(0.5 * (right * in.quad.x + up * in.quad.y) - view * sqrt(1.0 - r2));
        let n = normalize(bulge + vec3<f32>(0.0, 0.5, 0.0));
        let sun = sun_at(in.centre);
        let radiance = params.foam_albedo * air_irradiance(n, sun) / PI * transmittance(under);
        let alpha = 0.95 * exp(-2.0 * r2) * (1.0 - r2) * in.weight * soft;
        return vec4<f32>(through_air(eye, in.centre, radiance) * alpha, alpha);
    }
    // Spray: soft where it meets what is behind it.
    let density = (1.0 - r2) * (1.0 - r2);
    let alpha = 0.4 * density * soft * in.weight * transmittance(under).g;
    return vec4<f32>(through_air(eye, in.centre, spray_radiance(view, -log(1.0 - min(alpha, 0.999)))) * alpha, alpha);
}

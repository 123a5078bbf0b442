// How white water's particles are drawn and lit, shared by the surface
// water's (particles.wgsl) and the volumetric liquid's
// (liquid/white_water_draw.wgsl): the quad over a particle, spray's
// forward scattering and a bubble's bright rim.
#import constants, frame, sky_bindings, medium

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
}

// Corner c (in [-1, 1]²) of a quad facing the eye over a particle `size`
// wide at `position` moving at `velocity`: at least 1.5 pixels across
// (fainter by the area it lacks), stretched into a streak along its motion
// across the view over `shutter` s (fainter by the length it gains).
fn particle_quad(position: vec3<f32>, velocity: vec3<f32>, size: f32, shutter: f32, c: vec2<f32>) -> ParticleQuad {
    let eye = frame.view.position;
    let dist = max(distance(position, eye), 1e-3);
    let pixel = 2.0 * dist / (frame.view.size.y * frame.view.view_proj[1][1]);
    let drawn = max(size, 1.5 * pixel);
    var weight = (size * size) / (drawn * drawn);
    let forward = (position - eye) / dist;
    var right = normalize(cross(forward, vec3<f32>(0.0, 1.0, 0.0)) + vec3<f32>(1e-6, 0.0, 0.0));
    var up = cross(right, forward);
    var half_length = 0.5 * drawn;
    let across = velocity - forward * dot(velocity, forward);
    let travel = length(across) * shutter;
    if (travel > drawn) {
        right = across / length(across);
        up = normalize(cross(right, forward));
        half_length = 0.5 * (drawn + travel);
        weight *= drawn / (drawn + travel);
    }
    var q: ParticleQuad;
    q.world = position + right * c.x * half_length + up * c.y * 0.5 * drawn;
    q.weight = weight;
    return q;
}

// A dense parcel of spray seen along `view`: drops scatter the sun mostly
// forward (g ≈ 0.8 for millimetre drops' halo), bright against the light,
// and the sky from above.
fn spray_radiance(view: vec3<f32>) -> vec3<f32> {
    let phase = henyey_greenstein(dot(view, frame.light.sun_dir), 0.8);
    let sky = textureSampleLevel(sky_cube, sky_sampler, vec3<f32>(0.0, 1.0, 0.0), 6.0).rgb;
    return frame.light.sun_illuminance * phase * 0.9 + sky * 0.85;
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

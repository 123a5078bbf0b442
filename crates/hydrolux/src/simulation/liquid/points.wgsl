// The liquid's particles drawn as spheres of water (issue #29's "points";
// seed 003 §2.3): one instanced quad per particle, the sphere found per
// pixel by an exact ray–sphere hit, written to the depth buffer so the
// particles hide each other and the scene as geometry does. Each sphere is
// water: the sky and the sun's glint reflected by Fresnel's law (the
// water's index), what lies beyond it refracted through the ball and
// absorbed along its chord by the water's medium, its own in-scattered
// light, and the sun's shadow. `--view fluid` colours each by its speed.
#import liquid_particle, constants, frame, modes, sky_bindings, medium, optics, lighting, fog, shadow_space, shadow_lookup

struct PointsParams {
    radius: f32,
    // Speed (m/s) drawn red in the fluid view.
    speed_scale: f32,
    count: u32,
    _pad0: u32,
}


// A storage buffer, not a uniform one: Mesa's lavapipe inlines a small
// uniform buffer's values into the shaders that branch on them and keeps a
// compiled copy per draw (about 1 MB a frame; tests/memory.rs).
@group(1) @binding(0) var<storage, read> params: PointsParams;
@group(1) @binding(1) var<storage, read> particles: array<LiquidParticle>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) @interpolate(flat) centre: vec3<f32>,
    @location(2) @interpolate(flat) speed: f32,
}

@vertex
fn vs_main(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> VertexOut {
    let p = particles[i];
    let world = sphere_quad_corner(p.position, params.radius, frame.view.position, v);
    var out: VertexOut;
    out.clip = frame.view.view_proj * vec4<f32>(world, 1.0);
    if (p.alive == 0u) {
        // An empty slot: behind the far plane, clipped.
        out.clip = vec4<f32>(0.0, 0.0, 2.0, 1.0);
    }
    out.world = world;
    out.centre = p.position;
    out.speed = length(p.velocity);
    return out;
}

struct FragmentOut {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

// Blue at rest through cyan, green and yellow to red at `params.speed_scale`.
fn speed_colour(speed: f32) -> vec3<f32> {
    let t = clamp(speed / params.speed_scale, 0.0, 1.0);
    let r = clamp(1.5 - abs(4.0 * t - 3.0), 0.0, 1.0);
    let g = clamp(1.5 - abs(4.0 * t - 2.0), 0.0, 1.0);
    let b = clamp(1.5 - abs(4.0 * t - 1.0), 0.0, 1.0);
    return vec3<f32>(r, g, b);
}

@fragment
fn fs_main(in: VertexOut) -> FragmentOut {
    let eye = frame.view.position;
    let dir = normalize(in.world - eye);
    let oc = eye - in.centre;
    let r = params.radius;
    let b = dot(oc, dir);
    let disc = b * b - (dot(oc, oc) - r * r);
    if (disc < 0.0) {
        discard;
    }
    let t = -b - sqrt(disc);
    let hit = eye + t * dir;
    let n = (hit - in.centre) / r;
    var out: FragmentOut;
    let clip = frame.view.view_proj * vec4<f32>(hit, 1.0);
    out.depth = clip.z / clip.w;
    if (frame.modes.debug_view == VIEW_FLUID) {
        let shade = 0.35 + 0.65 * max(dot(n, normalize(vec3<f32>(0.3, 1.0, 0.5))), 0.0);
        out.color = vec4<f32>(speed_colour(in.speed) * shade, 1.0);
        return out;
    }
    let cos_i = max(dot(-dir, n), 0.0);
    let ior = frame.water.ior;
    let reflectance = fresnel(frame.modes.fresnel, frame.water.fresnel_power, cos_i, 1.0, ior);
    let reflected = reflect(dir, n);
    let visibility = sun_visibility(hit, n);
    // The sky and the sun's disc mirrored (its radiance: illuminance over
    // the disc's solid angle).
    var mirror = textureSampleLevel(sky_cube, sky_sampler, reflected, 0.0).rgb * exposure();
    if (dot(reflected, frame.light.sun_dir) > frame.light.cos_sun_radius) {
        mirror += frame.light.sun_illuminance * frame.light.inv_sun_solid_angle * visibility;
    }
    // Through the ball: bent in, across the chord, bent out; what lies that
    // way is the sky above the horizon and the lighting's grey ground below
    // it (the liquid's neighbours and the scene beyond are not traced by
    // points), absorbed by the water on the way.
    let inside = refract(dir, n, 1.0 / ior);
    let chord = 2.0 * r * max(dot(-inside, n), 0.0);
    let exit_n = (hit + inside * chord - in.centre) / r;
    var out_dir = refract(inside, -exit_n, ior);
    if (dot(out_dir, out_dir) < 0.5) {
        out_dir = reflect(inside, -exit_n);
    }
    var beyond = textureSampleLevel(sky_cube, sky_sampler, out_dir, 2.0).rgb * exposure();
    if (out_dir.y < 0.0) {
        beyond = below_horizon_radiance();
    }
    let through = beyond * transmittance(chord);
    // Light the water itself scatters towards the eye along the chord.
    let scatter = frame.water.scattering * chord * air_irradiance(n, vec3<f32>(visibility)) / PI;
    let color = reflectance * mirror + (1.0 - reflectance) * (through + scatter);
    out.color = vec4<f32>(through_air(eye, hit, color), 1.0);
    return out;
}

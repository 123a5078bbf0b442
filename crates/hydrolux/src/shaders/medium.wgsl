// The water body as a participating medium. WGSL twin of
// hydrolux_core::medium (seed 000 §3.3, eq. 3.3–3.6): Beer–Lambert
// attenuation, single scattering with a Henyey–Greenstein phase function,
// and the light field under a flat surface. Needs `frame`.
#import constants, frame

const DIFFUSE_MEAN_COSINE: f32 = 0.85;
const PHASE_ISOTROPIC: f32 = 0.0795774715;

fn extinction() -> vec3<f32> {
    return frame.water.absorption + frame.water.scattering;
}

fn transmittance(distance: f32) -> vec3<f32> {
    return exp(-extinction() * max(distance, 0.0));
}

fn henyey_greenstein(cos_theta: f32, g: f32) -> f32 {
    let d = 1.0 + g * g - 2.0 * g * cos_theta;
    return (1.0 - g * g) / (4.0 * PI * d * sqrt(d));
}

// σs·p·e_top·(e^(−σk·t) − e^(−σk(t + (1+c)s))) / (σk(1+c)): light e_top that
// came t metres through the water to the path's start, scattered once into
// the path of length s; continuous at σk(1+c) → 0. 1 + c is negative for
// paths rising towards the light faster than they lose it; both exponents
// stay ≤ 0 (the end's is clamped there), so nothing overflows however deep
// the eye. Twin: Medium::in_scatter_from.
fn in_scatter_from(e_top: vec3<f32>, t: f32, phase: f32, c: f32, s: f32) -> vec3<f32> {
    let k = extinction();
    let a = max(k * t, vec3<f32>(0.0));
    let kc = k * (1.0 + c);
    let kcs = kc * max(s, 0.0);
    let small = abs(kcs) < vec3<f32>(1e-4);
    let safe_kc = select(kc, vec3<f32>(1.0), small);
    let exact = (exp(-a) - exp(-max(a + kcs, vec3<f32>(0.0)))) / safe_kc;
    let integral = select(exact, exp(-a) * max(s, 0.0) * (1.0 - 0.5 * kcs), small);
    return frame.water.scattering * phase * e_top * integral;
}

// Fraction of the downwelling light that comes back up from below (floor
// and water), lighting undersides, the least anywhere (deep water, a dark
// floor). Twin: medium::UPWELLING_FRACTION.
const UPWELLING_FRACTION: f32 = 0.15;

// Downwelling irradiance on a horizontal plane `depth` m down. Twin:
// UnderwaterLight::downwelling.
fn downwelling(depth: f32) -> vec3<f32> {
    let d = max(depth, 0.0);
    let cos_w = max(frame.light.sun_travel_cos, 1e-3);
    return frame.light.sun_underwater * transmittance(d / cos_w) * cos_w
        + frame.light.sky_underwater * transmittance(d / DIFFUSE_MEAN_COSINE);
}

// Upwelling irradiance on a downward-facing plane `depth` m down: the
// floor's diffuse reflection of the light that reaches it, dimmed on its
// way up, or the grey world's bounce, whichever is more. Twin:
// UnderwaterLight::upwelling.
fn upwelling(depth: f32) -> vec3<f32> {
    let d = max(depth, 0.0);
    let grey_world = UPWELLING_FRACTION * downwelling(d);
    let floor_depth = frame.light.floor_depth;
    if (floor_depth <= d) {
        return grey_world;
    }
    let from_floor = frame.light.floor_albedo * downwelling(floor_depth)
        * transmittance((floor_depth - d) / DIFFUSE_MEAN_COSINE);
    return max(grey_world, from_floor);
}

// Irradiance on a receiver with normal n, `depth` m under the mean surface.
fn underwater_irradiance(depth: f32, n: vec3<f32>, sun_visibility: f32) -> vec3<f32> {
    return underwater_irradiance_sun(depth, n, max(dot(n, -frame.light.sun_travel), 0.0) * sun_visibility);
}

// The same where the sunbeam's cosine on the receiver, its shadow and
// caustics included, is known (`sun_cosine`: traced ground).
fn underwater_irradiance_sun(depth: f32, n: vec3<f32>, sun_cosine: f32) -> vec3<f32> {
    let d = max(depth, 0.0);
    let cos_w = max(frame.light.sun_travel_cos, 1e-3);
    let sun_down = frame.light.sun_underwater * transmittance(d / cos_w);
    let sky_down = frame.light.sky_underwater * transmittance(d / DIFFUSE_MEAN_COSINE);
    let sun = sun_down * sun_cosine;
    let sky = sky_down * (0.5 + 0.5 * n.y);
    let up = upwelling(d) * (0.5 - 0.5 * n.y);
    return sun + sky + up;
}

// The sun's part of the light scattered once into a view ray along `dir`
// from an eye `depth` m under the mean surface, between distances s0 and s1
// (the depth changes by −dir.y per metre). Twin:
// UnderwaterLight::sun_in_scatter.
fn sun_in_scatter(depth: f32, dir: vec3<f32>, s0: f32, s1: f32) -> vec3<f32> {
    let cos_w = max(frame.light.sun_travel_cos, 1e-3);
    let d0 = max(depth - dir.y * s0, 0.0);
    let phase = henyey_greenstein(dot(frame.light.sun_travel, -dir), frame.water.phase_g);
    return transmittance(s0) * in_scatter_from(frame.light.sun_underwater, d0 / cos_w, phase, -dir.y / cos_w, s1 - s0);
}

// The diffuse skylight's part over the first s metres.
fn sky_in_scatter(depth: f32, dir: vec3<f32>, s: f32) -> vec3<f32> {
    let d = max(depth, 0.0);
    let sky_top = frame.light.sky_underwater / DIFFUSE_MEAN_COSINE;
    return in_scatter_from(sky_top, d / DIFFUSE_MEAN_COSINE, PHASE_ISOTROPIC, -dir.y / DIFFUSE_MEAN_COSINE, s);
}

// Light scattered once into a path of length s along `dir` that starts
// `depth` m under the mean surface, towards a viewer looking along `dir`
// (seed 000 eq. 3.7–3.8).
fn view_in_scatter(depth: f32, dir: vec3<f32>, s: f32) -> vec3<f32> {
    return sun_in_scatter(depth, dir, 0.0, s) + sky_in_scatter(depth, dir, s);
}

// The same for a ray leaving the eye: where god rays are drawn (the first
// frame.volume.godray_distance metres), they replace the uniform sun term.
fn eye_in_scatter(depth: f32, dir: vec3<f32>, s: f32) -> vec3<f32> {
    return sun_in_scatter(depth, dir, min(frame.volume.godray_distance, s), s) + sky_in_scatter(depth, dir, s);
}

// The same from just under the surface (a downward refracted ray).
fn path_in_scatter(dir: vec3<f32>, s: f32) -> vec3<f32> {
    return view_in_scatter(0.0, dir, s);
}

// What a viewer inside the water at `eye` (the camera) sees of radiance `l` (in-medium)
// leaving `p`: attenuated on the way, plus the light scattered into the path.
fn through_water(eye: vec3<f32>, p: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let d = distance(eye, p);
    let dir = (p - eye) / max(d, 1e-6);
    return l * transmittance(d) + eye_in_scatter(-eye.y, dir, d);
}

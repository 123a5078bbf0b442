// Fog in the air (`[air]`): a grey, non-absorbing participating medium of
// scattering σ (frame.fog.scattering) filling the first frame.fog.distance metres around the
// eye, lit by the sky (uniformly) and the sun. Single scattering (seed 000
// §3.3 eq. 3.6 with σa = 0). The sun's part is marched through the shadow
// map by the god-ray pass when it runs (frame.volume.fog_marched = 1), so that objects
// cast shadows into the fog; otherwise it is the unshadowed closed form
// here. Needs `frame` and `medium` (henyey_greenstein).
#import constants, frame, medium, sky_bindings

// Radiance the fog settles to deep inside it, from the sky: isotropic
// scattering of a sky of radiance E/π over the upper half of the sphere and
// of the ground's GROUND_BOUNCE of it over the lower half.
const FOG_GROUND_BOUNCE: f32 = 0.15;

fn fog_sky_radiance() -> vec3<f32> {
    return frame.fog.sky_fraction * frame.light.sky_ambient / PI * 0.5 * (1.0 + FOG_GROUND_BOUNCE);
}

// What the eye sees of radiance `l` leaving `p` through the fog. Without
// branches on the frame's values (no fog gives t = 1, i.e. `l`): Mesa's
// lavapipe 22 recompiles a shader that branches on a uniform each time its
// bind groups are set, and keeps every copy.
fn through_fog(eye: vec3<f32>, p: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let sigma = max(frame.fog.scattering, 0.0);
    let full = distance(eye, p);
    let s = min(full, frame.fog.distance);
    let t = exp(-sigma * s);
    let dir = (p - eye) / max(full, 1e-6);
    let sun = frame.light.sun_illuminance * henyey_greenstein(dot(frame.light.sun_dir, dir), frame.fog.g);
    let glow = fog_sky_radiance() + select(vec3<f32>(0.0), sun, frame.volume.fog_marched == 0u);
    return l * t + glow * (1.0 - t);
}

// What the eye sees of radiance `l` leaving a surface at `p` through the air
// (aerial perspective, issue #32 item 3), then through the fog. The scene
// stands far below the aerosols' 1.2 km scale height, so the air along the
// way is as dense as at sea level: the path keeps e^(−σd) of `l` and takes
// the rest from the light an endless level path scatters towards the eye —
// the horizon's own radiance that way, read from the sky cube (the sky is
// that path's in-scattering). Negligible near the eye (1% at 100 m under a
// clear sky), it lets the far sea melt into the horizon's haze.
fn through_air(eye: vec3<f32>, p: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let d = distance(eye, p);
    let dir = (p - eye) / max(d, 1e-6);
    let level = vec2<f32>(dir.x, dir.z);
    let flat = select(vec2<f32>(1.0, 0.0), level / max(length(level), 1e-4), length(level) > 1e-4);
    let horizon_dir = normalize(vec3<f32>(flat.x, 0.01, flat.y));
    let horizon = textureSampleLevel(sky_cube, sky_sampler, horizon_dir, 0.0).rgb * exposure();
    let t = exp(-frame.fog.air_extinction * d);
    return through_fog(eye, p, l * t + horizon * (1.0 - t));
}

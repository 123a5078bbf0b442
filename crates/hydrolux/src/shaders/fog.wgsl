// Fog in the air (`[air]`): a grey, non-absorbing participating medium of
// scattering σ (frame.fog.x) filling the first frame.fog.z metres around the
// eye, lit by the sky (uniformly) and the sun. Single scattering (seed 000
// §3.3 eq. 3.6 with σa = 0). The sun's part is marched through the shadow
// map by the god-ray pass when it runs (frame.volume.z = 1), so that objects
// cast shadows into the fog; otherwise it is the unshadowed closed form
// here. Needs `frame` and `medium` (henyey_greenstein).

// Radiance the fog settles to deep inside it, from the sky: isotropic
// scattering of a sky of radiance E/π over the upper half of the sphere and
// of the ground's GROUND_BOUNCE of it over the lower half.
const FOG_GROUND_BOUNCE: f32 = 0.15;

fn fog_sky_radiance() -> vec3<f32> {
    return frame.fog.w * frame.sky_ambient.rgb / PI * 0.5 * (1.0 + FOG_GROUND_BOUNCE);
}

// What the eye sees of radiance `l` leaving `p` through the fog.
fn through_fog(eye: vec3<f32>, p: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let sigma = frame.fog.x;
    if (sigma <= 0.0) {
        return l;
    }
    let full = distance(eye, p);
    let s = min(full, frame.fog.z);
    let t = exp(-sigma * s);
    var glow = fog_sky_radiance();
    if (frame.volume.z < 0.5) {
        let dir = (p - eye) / max(full, 1e-6);
        glow += frame.sun_illuminance.rgb * henyey_greenstein(dot(frame.sun_dir.xyz, dir), frame.fog.y);
    }
    return l * t + glow * (1.0 - t);
}

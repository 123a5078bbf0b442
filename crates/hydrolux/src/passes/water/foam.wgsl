// The foam the white water leaves on the water (simulation/whitewater; seed
// 003 §4.4): how much shows where a pixel lands, filtered over its
// footprint, its debug views, and seen from below. Part of the water shader.

#import constants, frame, surface

// What a foam layer lets through from above, seen from below.
const FOAM_BELOW: f32 = 0.1;

// The foam debug view: its cover as grey over dark water, lit softly.
fn foam_view(foam: f32, n: vec3<f32>) -> vec4<f32> {
    let light = 0.6 + 0.4 * max(dot(n, normalize(vec3<f32>(0.4, 1.0, 0.3))), 0.0);
    return vec4<f32>(mix(vec3<f32>(0.02, 0.05, 0.1), vec3<f32>(1.0), foam) * light, 1.0);
}

// `render.view = "ripples"`: the interactive water's height (red up, blue
// down) on a signed log scale from 0.5 mm to 0.5 m (a linear ±5 mm scale
// turned the pool solid orange: the ball alone lifts its level by 1.2 cm),
// lit by the surface's normal so that waves show on any level.
fn ripple_view(p: vec2<f32>, n: vec3<f32>) -> vec4<f32> {
    var r = zero_sample();
    add_ripples(&r, p, 0.0);
    let h = r.disp.y;
    let t = sign(h) * min(log(1.0 + abs(h) / 0.0005) / log(1001.0), 1.0);
    let hue = mix(vec3<f32>(0.85), select(vec3<f32>(0.15, 0.35, 1.0), vec3<f32>(1.0, 0.25, 0.1), t > 0.0), abs(t));
    let light = 0.2 + 0.8 * pow(max(dot(n, normalize(vec3<f32>(0.4, 1.0, 0.3))), 0.0), 4.0);
    return vec4<f32>(hue * light, 1.0);
}

// Foam as seen in a pixel: its cover filtered over the footprint (the
// fraction of the pixel that is foam, so it never shimmers), broken up into
// lacy patches and bubbles by noise at three scales (5.6 m, 1.4 m, 0.35 m
// across the wind, `foam_streak` times longer along it: wind streaks): a
// cell of cover c shows foam where the noise lies below c, a dense sheet
// keeps a few holes. Each octave fades into its mean once a pixel's
// footprint (geometric mean of its two axes, so grazing views keep their
// detail across the view) nears its size, and with no octave left the
// pixel shows c itself. Only the look is noise: where and how much foam
// there is comes from the simulated field.
fn foam_seen(p: vec2<f32>, dpdx_p: vec2<f32>, dpdy_p: vec2<f32>) -> f32 {
    let c = foam_cover_grad(p, dpdx_p, dpdy_p);
    if (c <= 0.0) {
        return 0.0;
    }
    let footprint = sqrt(max(abs(dpdx_p.x * dpdy_p.y - dpdx_p.y * dpdy_p.x), 1e-8));
    // Noise space: along the wind shrunk by the streaks' length.
    let wind = surface.foam_wind;
    let q = vec2<f32>(dot(p, wind) / max(surface.foam_streak, 1.0), dot(p, vec2<f32>(-wind.y, wind.x)));
    var n = 0.5;
    var kept = 0.0;
    var scale = 5.6;
    var weight = 0.3;
    for (var k = 0; k < 3; k++) {
        let d = 1.0 - smoothstep(0.2, 0.7, footprint / scale);
        let offset = vec2<f32>(17.0, 3.0) * f32(k);
        n += weight * d * (value_noise(q / scale + offset) - 0.5);
        kept = max(kept, d);
        scale *= 0.25;
        weight *= 1.2;
    }
    if (kept <= 0.0) {
        return c;
    }
    let width = 0.12 + 0.4 * (1.0 - kept);
    let pattern = smoothstep(n - width, n + width, 0.05 + 0.85 * c);
    // Inside a patch the sheet is thicker and thinner (0.9 m blotches,
    // faded like the octaves), not one flat white.
    let blotch = 1.0 - smoothstep(0.2, 0.7, footprint / 0.9);
    let thickness = clamp(1.0 + blotch * (value_noise(q / 0.9 + vec2<f32>(31.0, 7.0)) - 0.6), 0.0, 1.0);
    // Far off, the mean of what the pattern shows (its mean cover).
    return mix(c, pattern * thickness, kept);
}

// Foam's brightness (0.6–1): bubbles of many sizes make its sheet lumpy,
// some of it in the shade of the rest. Noise at 0.5 m and 0.12 m, faded to
// its mean (0.85) as the pixel's footprint nears its size.
fn foam_shade(p: vec2<f32>, dpdx_p: vec2<f32>, dpdy_p: vec2<f32>) -> f32 {
    let footprint = sqrt(max(abs(dpdx_p.x * dpdy_p.y - dpdx_p.y * dpdy_p.x), 1e-8));
    var shade = 0.85;
    var scale = 0.5;
    for (var k = 0; k < 2; k++) {
        let d = 1.0 - smoothstep(0.2, 0.7, footprint / scale);
        shade += 0.25 * d * (value_noise(p / scale + vec2<f32>(5.0, 11.0) * f32(k + 1)) - 0.5);
        scale *= 0.25;
    }
    return clamp(shade, 0.6, 1.0);
}

fn value_noise(x: vec2<f32>) -> f32 {
    let i = floor(x);
    let f = x - i;
    let u = f * f * (3.0 - 2.0 * f);
    let a = noise_hash(i);
    let b = noise_hash(i + vec2<f32>(1.0, 0.0));
    let c = noise_hash(i + vec2<f32>(0.0, 1.0));
    let d = noise_hash(i + vec2<f32>(1.0, 1.0));
    return mix(mix(a, b, u.x), mix(c, d, u.x), u.y);
}

fn noise_hash(i: vec2<f32>) -> f32 {
    let k = vec2<u32>(vec2<i32>(i));
    var h = (k.x * 0x27d4eb2du) ^ (k.y * 0x165667b1u);
    h = (h ^ (h >> 15u)) * 0x2c1b3c6du;
    h = h ^ (h >> 12u);
    return f32(h & 0xffffu) / 65535.0;
}


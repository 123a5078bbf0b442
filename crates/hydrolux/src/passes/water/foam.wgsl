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

// How foam looks where the field puts it (twin:
// hydrolux_core::whitewater::foam_look, which says why). A raft of
// bubbles: a dense sheet with holes that tears into lace as it thins.
// The structure s(q) mixes a cell network's walls (Worley's F2 − F1,
// LACE_CELL across) with a breakup noise (BREAKUP across) in the wind's
// frame, along-wind shrunk by the streak length; foam covers s < t(c),
// t the structure's quantiles, so the covered fraction is the cover c.

// The field's cell the sizes below are for (m: the storm's, 800 m over
// 512 cells); they scale with the field's own cell.
const FOAM_REFERENCE_CELL: f32 = 1.5625;
const LACE_CELL: f32 = 0.5;
// The finest lace drawn (m; twin FINEST_LACE, look_units).
const FINEST_LACE: f32 = 0.02;
const BREAKUP: f32 = 3.0;
const LACE_WARP: f32 = 0.35;
const WARP_SCALE: f32 = 2.3;
const EDGE_SPAN: f32 = 0.6;
const LACE_WEIGHT: f32 = 0.5;
const THICK_SPAN: f32 = 0.1;
// A dense sheet is marbled: between MARBLE_FROM and MARBLE_TO of s (the
// bubble cells' middles) it thins by up to MARBLE (twin: marbling).
const MARBLE: f32 = 0.6;
const MARBLE_FROM: f32 = 0.45;
const MARBLE_TO: f32 = 0.7;
// The sun wraps this far past a lump's terminator; a film is this shade of
// a thick sheet (twins: FOAM_WRAP, FOAM_FILM_SHADE).
const FOAM_WRAP: f32 = 0.3;
const FOAM_FILM_SHADE: f32 = 0.65;
// The structure is magnified until its finer network's cells span this
// many pixels, up to 2^FOAM_MAX_LEVEL (16 times: 3 m lace cells at the
// storm's scale); beyond, the foam is its mean.
const FOAM_LEVEL_PIXELS: f32 = 4.0;
const FOAM_MAX_LEVEL: f32 = 4.0;
// How far inside a sheet (in s) its ridges keep rising.
const THICK_RELIEF: f32 = 0.3;
const FOAM_THRESHOLDS = array<f32, 17>(
    0.15, 0.273, 0.321, 0.354, 0.383, 0.408, 0.433, 0.456, 0.479, 0.502, 0.526, 0.552, 0.580, 0.612,
    0.651, 0.706, 1.0,
);
// The height of a thick sheet's lumps over its film (m): the slopes the
// sun catches at its edges and on its bubble clumps.
const FOAM_LUMP: f32 = 0.04;

struct FoamLook {
    // The fraction of the pixel that is foam (0–1).
    cover: f32,
    // How deep inside the foam it is, averaged (0 a film, 1 a thick sheet).
    thickness: f32,
    // The slope of the foam's lumpy top (d height / dx, dz, world).
    slope: vec2<f32>,
}

// The cover a cell shows (twin: hydrolux_core::whitewater::foam_look::
// shown_cover): a whitecap is where the cover passes ½ (as the calibration
// to Monahan counts it), a raft with an edge: full from 0.7, none below
// 0.3 but the residual lace of old foam (0.6·c).
fn foam_shown_cover(c: f32) -> f32 {
    return max(smoothstep(0.3, 0.7, c), 0.6 * c);
}

// What a foam layer hides of what lies beneath it: a thin film lets 40% of the
// water through, a thick sheet nothing.
fn foam_opacity(look: FoamLook) -> f32 {
    return look.cover * (0.6 + 0.4 * look.thickness);
}

fn foam_threshold(c: f32) -> f32 {
    let x = clamp(c, 0.0, 1.0) * 16.0;
    let k = min(u32(floor(x)), 15u);
    let f = x - f32(k);
    return FOAM_THRESHOLDS[k] + (FOAM_THRESHOLDS[k + 1u] - FOAM_THRESHOLDS[k]) * f;
}

// Value noise (0–1) with its gradient: (value, d/dx, d/dy).
fn value_noise_d(x: vec2<f32>) -> vec3<f32> {
    let i = floor(x);
    let f = x - i;
    let u = f * f * (3.0 - 2.0 * f);
    let du = 6.0 * f * (1.0 - f);
    let a = noise_hash(i);
    let b = noise_hash(i + vec2<f32>(1.0, 0.0));
    let c = noise_hash(i + vec2<f32>(0.0, 1.0));
    let d = noise_hash(i + vec2<f32>(1.0, 1.0));
    let k = a - b - c + d;
    let v = a + (b - a) * u.x + (c - a) * u.y + k * u.x * u.y;
    return vec3<f32>(v, du.x * ((b - a) + k * u.y), du.y * ((c - a) + k * u.x));
}

// A cell network's wall distance at x (cells), (F2 − F1)/EDGE_SPAN capped
// at 1, and its gradient (per cell): one jittered feature point per cell.
fn foam_walls(x: vec2<f32>) -> vec3<f32> {
    let base = floor(x);
    var f1 = 8.0;
    var f2 = 8.0;
    var g1 = vec2<f32>(0.0);
    var g2 = vec2<f32>(0.0);
    for (var j = -1; j <= 1; j++) {
        for (var i = -1; i <= 1; i++) {
            let cell = base + vec2<f32>(f32(i), f32(j));
            let jitter = vec2<f32>(noise_hash(cell + vec2<f32>(113.0, 71.0)), noise_hash(cell + vec2<f32>(37.0, 191.0)));
            let to = x - (cell + vec2<f32>(0.1) + 0.8 * jitter);
            let d = length(to);
            let g = to / max(d, 1e-6);
            if (d < f1) {
                f2 = f1;
                g2 = g1;
                f1 = d;
                g1 = g;
            } else if (d < f2) {
                f2 = d;
                g2 = g;
            }
        }
    }
    let edge = (f2 - f1) / EDGE_SPAN;
    if (edge < 1.0) {
        return vec3<f32>(edge, (g2 - g1) / EDGE_SPAN);
    }
    return vec3<f32>(1.0, 0.0, 0.0);
}

// The foam's structure at (along, across) the wind (m): s and its gradient
// (per m along, per m across). The breakup is stretched by the streak
// length, the lace by its square root, and the lace's walls wander by a
// warp LACE_WARP cells deep; two network scales give bubbles many sizes.
fn foam_structure(along: f32, across: f32, streak_length: f32) -> vec3<f32> {
    let streak = max(streak_length, 1.0);
    let lace_stretch = sqrt(streak);
    let r = vec2<f32>(along / lace_stretch, across) / LACE_CELL;
    let w1 = value_noise_d(r / WARP_SCALE + vec2<f32>(41.0, 7.0));
    let w2 = value_noise_d(r / WARP_SCALE + vec2<f32>(3.0, 53.0));
    let k = 2.0 * LACE_WARP / WARP_SCALE;
    let x = r + 2.0 * LACE_WARP * vec2<f32>(w1.x - 0.5, w2.x - 0.5);
    let jx = vec2<f32>(1.0 + k * w1.y, k * w1.z);
    let jy = vec2<f32>(k * w2.y, 1.0 + k * w2.z);
    let l1 = foam_walls(x);
    let l2 = foam_walls(x / 0.4 + vec2<f32>(19.0, 23.0));
    let e = 0.65 * l1.x + 0.35 * l2.x;
    let ge_x = 0.65 * l1.yz + 0.35 * l2.yz / 0.4;
    let ge_r = vec2<f32>(ge_x.x * jx.x + ge_x.y * jy.x, ge_x.x * jx.y + ge_x.y * jy.y);
    let ge = vec2<f32>(ge_r.x / (lace_stretch * LACE_CELL), ge_r.y / LACE_CELL);
    let q = vec2<f32>(along / streak, across);
    let m1 = value_noise_d(q / BREAKUP + vec2<f32>(17.0, 3.0));
    let m2 = value_noise_d(q / (0.35 * BREAKUP) + vec2<f32>(5.0, 29.0));
    let m = 0.65 * m1.x + 0.35 * m2.x;
    let gq = 0.65 * m1.yz / BREAKUP + 0.35 * m2.yz / (0.35 * BREAKUP);
    let gm = vec2<f32>(gq.x / streak, gq.y);
    return vec3<f32>(LACE_WEIGHT * e + (1.0 - LACE_WEIGHT) * m, LACE_WEIGHT * ge + (1.0 - LACE_WEIGHT) * gm);
}

// The mean thickness of the foam a cover c puts down, dense sheets'
// marbling counted (twin: mean_thickness).
fn foam_mean_thickness(c_in: f32) -> f32 {
    let c = clamp(c_in, 0.0, 1.0);
    let dense = max(c - 0.6, 0.0) / 0.4;
    return 0.3 + 0.65 * pow(c, 0.6) - 0.115 * dense * dense;
}

// How much of a dense sheet's thickness a point of structure s keeps: all
// on the network's walls, 1 − MARBLE in its cells' middles, so a whitecap
// is a network of thick walls over thinner film rather than a flat sheet
// (twin: marbling). Covers under about ½ never reach these s.
fn foam_marbling(s: f32) -> f32 {
    let x = clamp((s - MARBLE_FROM) / (MARBLE_TO - MARBLE_FROM), 0.0, 1.0);
    return 1.0 - MARBLE * x * x * (3.0 - 2.0 * x);
}

// The radiance foam sends to the eye (twin: foam_radiance, which says
// why): a diffuse raft of albedo FOAM_ALBEDO whose top faces `top`, lit
// by the sun (irradiance facing it, shadow applied) wrapped FOAM_WRAP past
// the terminator, and by the sky's irradiance on a level plane times the
// share of the dome the top sees, (1 + top.y)/2; a film is darker.
fn foam_radiance(top: vec3<f32>, thickness: f32, sun_dir: vec3<f32>, sun_irradiance: vec3<f32>, sky_irradiance_up: vec3<f32>) -> vec3<f32> {
    let lit = max((dot(top, sun_dir) + FOAM_WRAP) / (1.0 + FOAM_WRAP), 0.0) * step(0.0, sun_dir.y);
    let sky_seen = 0.5 * (1.0 + top.y);
    let shade = FOAM_FILM_SHADE + (1.0 - FOAM_FILM_SHADE) * clamp(thickness, 0.0, 1.0);
    return (sky_irradiance_up * sky_seen + sun_irradiance * lit) * (FOAM_ALBEDO * shade / PI);
}

// The structure magnified 2^level, at a pixel: how much of it is foam
// (its edge as soft as s changes across the pixel, so it never aliases),
// how deep inside, and the slope of its top: a sheet rises FOAM_LUMP over
// THICK_SPAN from its edge and half as much again over the next
// THICK_RELIEF of s inside it (ridges and hollows in a dense sheet),
// whatever the magnification.
fn foam_level(p: vec2<f32>, dpdx_p: vec2<f32>, dpdy_p: vec2<f32>, t: f32, level: f32) -> vec4<f32> {
    let wind = surface.foam_wind;
    let across = vec2<f32>(-wind.y, wind.x);
    let zoom = exp2(level);
    let s = foam_structure(dot(p, wind) / zoom, dot(p, across) / zoom, surface.foam_streak);
    let grad = (wind * s.y + across * s.z) / zoom;
    let soft = max(0.5 * (abs(dot(grad, dpdx_p)) + abs(dot(grad, dpdy_p))), 0.01);
    let inside = smoothstep(-soft, soft, t - s.x);
    let depth = clamp((t - s.x) / THICK_SPAN, 0.0, 1.0) * foam_marbling(s.x);
    var slope = vec2<f32>(0.0);
    let inner = t - s.x - THICK_SPAN;
    if (depth > 0.0 && depth < 1.0) {
        slope = -grad * (FOAM_LUMP / THICK_SPAN);
    } else if (inner > 0.0 && inner < THICK_RELIEF) {
        slope = -grad * (0.5 * FOAM_LUMP / THICK_RELIEF);
    }
    return vec4<f32>(inside, depth, slope);
}

// Foam as a pixel sees it. Its cover is the field's, filtered over the
// pixel's footprint and shown as a raft (foam_shown_cover). Foam has
// structure at every scale (lace, patches of lace, streaks of patches),
// so the structure is drawn magnified by the power of two at which its
// finer network spans FOAM_LEVEL_PIXELS of the pixel's longer axis (a
// grazing view's, along the view), blending two levels as mips do; its
// distribution is the same at every magnification, so the covered
// fraction stays c throughout. Beyond FOAM_MAX_LEVEL it fades into c, its
// own mean. Bubble clumps (0.3 m, 0.08 m) make a thick sheet lumpy.
fn foam_look(p_world: vec2<f32>, dpdx_world: vec2<f32>, dpdy_world: vec2<f32>) -> FoamLook {
    var look = FoamLook(0.0, 0.0, vec2<f32>(0.0));
    let c = foam_shown_cover(foam_cover_smooth(p_world, dpdx_world, dpdy_world));
    if (c <= 0.0) {
        return look;
    }
    // The look's sizes are for a field of FOAM_REFERENCE_CELL cells and
    // scale with the field's own (a pool's splash foam is finer than a
    // whitecap), its lace no finer than FINEST_LACE: work in those units
    // (slopes are ratios, they carry over).
    let units = max(surface.foam_side / f32(textureDimensions(foam_tex).x) / FOAM_REFERENCE_CELL, FINEST_LACE / LACE_CELL);
    let p = p_world / units;
    let dpdx_p = dpdx_world / units;
    let dpdy_p = dpdy_world / units;
    let longest = max(length(dpdx_p), length(dpdy_p));
    let wanted = log2(max(longest * FOAM_LEVEL_PIXELS / (0.4 * LACE_CELL), 1e-6));
    let kept = 1.0 - smoothstep(FOAM_MAX_LEVEL, FOAM_MAX_LEVEL + 1.0, wanted);
    // Far off: the pattern's means.
    look.cover = c;
    look.thickness = foam_mean_thickness(c);
    if (kept <= 0.0) {
        return look;
    }
    let level = clamp(wanted, 0.0, FOAM_MAX_LEVEL);
    let l0 = floor(level);
    let blend = level - l0;
    let t = foam_threshold(c);
    var f = foam_level(p, dpdx_p, dpdy_p, t, l0);
    if (blend > 0.0) {
        f = mix(f, foam_level(p, dpdx_p, dpdy_p, t, l0 + 1.0), blend);
    }
    let inside = f.x;
    let depth = f.y;
    var slope = f.zw;
    // Bubble clumps on the thick sheet, each octave faded by its size (at
    // the level's magnification, so a distant sheet is lumpy too).
    var lumps = 0.0;
    var scale = 0.3 * exp2(l0);
    for (var k = 0; k < 2; k++) {
        let fade = (1.0 - smoothstep(0.2, 0.6, longest / scale)) * depth;
        let n = value_noise_d(p / scale + vec2<f32>(5.0, 11.0) * f32(k + 1));
        lumps += fade * (n.x - 0.5);
        slope += fade * 0.5 * FOAM_LUMP * n.yz / scale;
        scale *= 0.27;
    }
    look.cover = mix(c, inside, kept);
    look.thickness = mix(foam_mean_thickness(c), clamp(depth * (1.0 + 0.6 * lumps), 0.0, 1.0), kept);
    look.slope = slope * kept;
    return look;
}

// The bubble cloud under foam (0–1): a breaker drives a plume of bubbles
// down under its whitecap, which spreads a little beyond the foam on top
// (the cover a mip down, two cells around) and rises out within seconds,
// so only dense, fresh foam has one under it (the cover squared).
fn bubble_cloud_at(p: vec2<f32>) -> f32 {
    let inside = foam_window(p);
    if (inside <= 0.0) {
        return 0.0;
    }
    let c = textureSampleLevel(foam_tex, surface_sampler_aniso, p / surface.foam_side, 1.0).x;
    return inside * c * c;
}

// The light a bubble cloud of `cloud` (0–1) sends up to just under the
// surface (twin: hydrolux_core::whitewater::bubble_cloud_radiance): its
// bubbles scatter back BUBBLE_CLOUD_REFLECTANCE of the light that reaches
// them, from BUBBLE_CLOUD_DEPTH down on average, the water absorbing on
// the way down and up: the pale aquamarine under and around a whitecap.
fn bubble_cloud_radiance(cloud: f32, e_water: vec3<f32>) -> vec3<f32> {
    return cloud * BUBBLE_CLOUD_REFLECTANCE * e_water / PI * exp(-2.0 * BUBBLE_CLOUD_DEPTH * frame.water.absorption);
}

// The field's cover at p over the pixel's footprint; where a pixel is
// smaller than a cell the cells are joined by a cubic B-spline (four
// bilinear taps; Sigg & Hadwiger, GPU Gems 2 ch. 20) so that the lace's
// threshold does not trace the bilinear cells' diamonds and steps.
// Every read of foam_tex here uses the anisotropic sampler, as
// foam_cover_grad does: OpenGL binds one sampler per image.
fn foam_cover_smooth(p: vec2<f32>, dpdx_p: vec2<f32>, dpdy_p: vec2<f32>) -> f32 {
    let filtered = foam_cover_grad(p, dpdx_p, dpdy_p);
    let inside = foam_window(p);
    if (inside <= 0.0) {
        return 0.0;
    }
    let cells = f32(textureDimensions(foam_tex).x);
    let cell = surface.foam_side / cells;
    let footprint = sqrt(max(abs(dpdx_p.x * dpdy_p.y - dpdx_p.y * dpdy_p.x), 1e-8));
    let smooth_weight = 1.0 - smoothstep(0.5, 1.0, footprint / cell);
    if (smooth_weight <= 0.0 || filtered <= 0.0) {
        return filtered;
    }
    // Texel coordinates (centres at +½), split into the cell and the way across.
    let x = p / cell - 0.5;
    let i = floor(x);
    let f = x - i;
    let w0 = (1.0 - f) * (1.0 - f) * (1.0 - f) / 6.0;
    let w1 = (4.0 - 6.0 * f * f + 3.0 * f * f * f) / 6.0;
    let w2 = (1.0 + 3.0 * f + 3.0 * f * f - 3.0 * f * f * f) / 6.0;
    let w3 = f * f * f / 6.0;
    let a = w0 + w1;
    let b = w2 + w3;
    let at_a = (i - 0.5 + w1 / a) / cells;
    let at_b = (i + 1.5 + w3 / b) / cells;
    let t00 = textureSampleLevel(foam_tex, surface_sampler_aniso, vec2<f32>(at_a.x, at_a.y), 0.0).x;
    let t10 = textureSampleLevel(foam_tex, surface_sampler_aniso, vec2<f32>(at_b.x, at_a.y), 0.0).x;
    let t01 = textureSampleLevel(foam_tex, surface_sampler_aniso, vec2<f32>(at_a.x, at_b.y), 0.0).x;
    let t11 = textureSampleLevel(foam_tex, surface_sampler_aniso, vec2<f32>(at_b.x, at_b.y), 0.0).x;
    let cubic = a.y * (a.x * t00 + b.x * t10) + b.y * (a.x * t01 + b.x * t11);
    return mix(filtered, inside * cubic, smooth_weight);
}

fn noise_hash(i: vec2<f32>) -> f32 {
    let k = vec2<u32>(vec2<i32>(i));
    var h = (k.x * 0x27d4eb2du) ^ (k.y * 0x165667b1u);
    h = (h ^ (h >> 15u)) * 0x2c1b3c6du;
    h = h ^ (h >> 12u);
    return f32(h & 0xffffu) / 65535.0;
}


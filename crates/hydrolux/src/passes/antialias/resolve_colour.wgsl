// Temporal anti-aliasing's per-pixel arithmetic (CPU twin:
// hydrolux_core::antialias): reprojecting a pixel into last frame's image,
// and blending the new frame into the history clipped to the new frame's
// 3×3 neighbourhood in YCoCg. Imported by the resolve and by the probe
// (the twin test). The constants are core's (a test keeps them equal).

const TAA_CURRENT_WEIGHT: f32 = 0.1;
const TAA_RESPONSIVE_WEIGHT: f32 = 0.5;
const TAA_CLIP_SIGMAS: f32 = 1.25;

fn taa_rgb_to_ycocg(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        0.25 * c.x + 0.5 * c.y + 0.25 * c.z,
        0.5 * c.x - 0.5 * c.z,
        -0.25 * c.x + 0.5 * c.y - 0.25 * c.z,
    );
}

fn taa_ycocg_to_rgb(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z);
}

fn taa_luma(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// `history` moved towards `centre` until it is inside centre ± extent.
fn taa_clip_to_box(history: vec3<f32>, centre: vec3<f32>, extent: vec3<f32>) -> vec3<f32> {
    let offset = history - centre;
    let units = abs(offset / max(extent, vec3<f32>(1e-6)));
    let largest = max(units.x, max(units.y, units.z));
    if (largest > 1.0) {
        return centre + offset / largest;
    }
    return history;
}

// Texture coordinate (x, y) of the same point in last frame's image, and
// z = 1 where there is one (in front of last frame's camera, on its image).
fn taa_reproject(reprojection: mat4x4<f32>, uv: vec2<f32>, depth: f32) -> vec3<f32> {
    let clip = reprojection * vec4<f32>(2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y, depth, 1.0);
    if (clip.w <= 1e-7) {
        return vec3<f32>(0.0);
    }
    let p = clip.xy / clip.w;
    let prev = vec2<f32>(0.5 * p.x + 0.5, 0.5 - 0.5 * p.y);
    let inside = all(prev >= vec2<f32>(0.0)) && all(prev <= vec2<f32>(1.0));
    return vec3<f32>(prev, select(0.0, 1.0, inside));
}

// The resolved colour: the new frame's 3×3 neighbourhood (the pixel at 4)
// and the reprojected history (used where has_history); trust (the HDR
// alpha) 1 where the pixel's colour follows the geometry, 0 where it
// changes by itself (the water's surface); min_share 1 / (frames + 1) for
// a history of that many frames; settled where neither the camera nor the
// time moved (the frames are then averaged evenly, unclipped).
fn taa_resolve(n: array<vec3<f32>, 9>, history: vec3<f32>, has_history: bool, trust: f32, min_share: f32, settled: bool) -> vec3<f32> {
    let current = n[4];
    if (!has_history) {
        return current;
    }
    if (settled) {
        return history + (current - history) * min_share;
    }
    var sum = vec3<f32>(0.0);
    var sum_sq = vec3<f32>(0.0);
    var lo = vec3<f32>(3.0e38);
    var hi = vec3<f32>(-3.0e38);
    for (var i = 0; i < 9; i++) {
        let y = taa_rgb_to_ycocg(n[i]);
        sum += y;
        sum_sq += y * y;
        lo = min(lo, y);
        hi = max(hi, y);
    }
    let mean = sum / 9.0;
    let sigma = sqrt(max(sum_sq / 9.0 - mean * mean, vec3<f32>(0.0)));
    let box_lo = max(mean - TAA_CLIP_SIGMAS * sigma, lo);
    let box_hi = min(mean + TAA_CLIP_SIGMAS * sigma, hi);
    // The box in YCoCg reaches outside the RGB gamut: radiance stays ≥ 0.
    let clipped = max(taa_ycocg_to_rgb(
        taa_clip_to_box(taa_rgb_to_ycocg(history), 0.5 * (box_lo + box_hi), 0.5 * (box_hi - box_lo)),
    ), vec3<f32>(0.0));
    let share = max(mix(TAA_RESPONSIVE_WEIGHT, TAA_CURRENT_WEIGHT, clamp(trust, 0.0, 1.0)), min_share);
    let wc = share / (1.0 + taa_luma(current));
    let wh = (1.0 - share) / (1.0 + taa_luma(clipped));
    return max((current * wc + clipped * wh) / (wc + wh), vec3<f32>(0.0));
}

// The water surface, whichever model makes it (group 1): FFT cascades read
// from textures, or a sum of directional (Gerstner) waves with analytic
// derivatives (seed 001), flat water, or a user's heightfield. Twins:
// hydrolux_core::waves. The models' and the interactive water's numbers
// (`MODEL_*`, `RIPPLES_*`) are generated (src/modes.rs).
#import constants, modes

// One directional wave of the sines model.
struct SineWave {
    // Wave vector (rad/m).
    k: vec2<f32>,
    amplitude: f32,
    // Phase now (rad).
    phase: f32,
}

struct SurfaceParams {
    // Patch size (m) of each FFT cascade; for a heightfield, xy its [Lx, Lz].
    cascade_sizes: vec4<f32>,
    // FFT cascades, surface model (MODEL_*),
    // sine waves, FFT resolution N.
    cascades: u32,
    model: u32,
    sine_count: u32,
    fft_resolution: u32,
    waves: array<SineWave, 64>,
    // Horizontal (Gerstner) amplitude Q·A of each wave, four per vec4.
    wave_q: array<vec4<f32>, 16>,
    // Interactive water (RIPPLES > 0): world point of the ripple texture's
    // uv (0, 0), its side (m), its cell (m).
    ripple_origin: vec2<f32>,
    ripple_side: f32,
    ripple_cell: f32,
    // The simulated domain: x min, z min, x max, z max (m).
    ripple_window: vec4<f32>,
    // White water's foam: world point of its window's low corner, its side
    // (m; 0: no foam), 1 if it tiles the plane (simulation/whitewater).
    foam_origin: vec2<f32>,
    foam_side: f32,
    foam_tiles: u32,
    // The wind's direction (unit, towards; the foam's streaks lie along
    // it), how much longer than wide its streaks are (1: round patches).
    foam_wind: vec2<f32>,
    foam_streak: f32,
    _pad0: f32,
}

@group(1) @binding(0) var<uniform> surface: SurfaceParams;
// Per cascade: Dx, h, Dz, ∂Dx/∂z
@group(1) @binding(1) var displacement_tex: texture_2d_array<f32>;
// Per cascade: ∂h/∂x, ∂h/∂z, ∂Dx/∂x, ∂Dz/∂z
@group(1) @binding(2) var derivative_tex: texture_2d_array<f32>;
// Per cascade: (∂h/∂x)², (∂h/∂z)², ∂h/∂x·∂h/∂z (LEAN-style moments; mips give slope variance)
@group(1) @binding(3) var moments_tex: texture_2d_array<f32>;
// Trilinear, for explicit-LOD reads (vertex and compute stages).
@group(1) @binding(4) var surface_sampler: sampler;
// Anisotropic, for gradient reads in fragments (explicit-LOD reads must not
// use it: some drivers then filter anisotropically anyway, i.e. blur).
@group(1) @binding(5) var surface_sampler_aniso: sampler;
// A user's heights (model 3): row = z, col = x, corner-sampled, periodic.
@group(1) @binding(6) var heightfield_tex: texture_2d<f32>;
// Interactive water: h, ∂h/∂x, ∂h/∂z per cell (simulation/ripples).
@group(1) @binding(7) var ripple_tex: texture_2d<f32>;
// Foam cover (0–1) per cell, stored modulo the window (mipmapped:
// the mips average cover, so a pixel sees the fraction of its footprint
// that is foam, whatever the distance).
@group(1) @binding(8) var foam_tex: texture_2d<f32>;

struct SurfaceSample {
    disp: vec3<f32>,
    slope: vec2<f32>,
    dxx: f32,
    dzz: f32,
    dxz: f32,
    // Variance of the slopes inside the filter footprint (x, z), from the moments.
    slope_variance: vec2<f32>,
}

fn zero_sample() -> SurfaceSample {
    return SurfaceSample(vec3<f32>(0.0), vec2<f32>(0.0), 0.0, 0.0, 0.0, vec2<f32>(0.0));
}

// Sum of directional waves, each faded out as its wavelength approaches the
// footprint (metres; 0 = exact) so distant short waves do not alias: their
// slope variance moves into `slope_variance`, i.e. into the roughness.
fn sines_sample(p: vec2<f32>, footprint: f32) -> SurfaceSample {
    var s = zero_sample();
    for (var i = 0u; i < surface.sine_count; i++) {
        let wave = surface.waves[i];
        let k = max(length(wave.k), 1e-6);
        let keep = 1.0 - smoothstep(0.2, 0.5, footprint * k / TAU);
        let w = vec4<f32>(wave.k, wave.amplitude * keep, wave.phase);
        let q = surface.wave_q[i / 4u][i % 4u] * keep;
        let lost = (1.0 - keep * keep) * 0.5 * wave.amplitude * wave.amplitude;
        s.slope_variance += lost * wave.k * wave.k;
        let u = w.xy / k;
        let arg = dot(w.xy, p) + w.w;
        let sn = sin(arg);
        let cs = cos(arg);
        s.disp.y += w.z * cs;
        s.slope -= w.z * w.xy * sn;
        s.disp.x -= q * u.x * sn;
        s.disp.z -= q * u.y * sn;
        s.dxx -= q * u.x * w.x * cs;
        s.dzz -= q * u.y * w.y * cs;
        s.dxz -= q * u.x * w.y * cs;
    }
    return s;
}

fn cascade_uv(p: vec2<f32>, c: u32) -> vec2<f32> {
    // Texel j holds the grid point x = j·L/N, i.e. uv = x/L + 0.5/N.
    return p / surface.cascade_sizes[c] + vec2<f32>(0.5 / f32(surface.fft_resolution));
}

fn add_cascade(s: ptr<function, SurfaceSample>, d: vec4<f32>, g: vec4<f32>, m: vec4<f32>) {
    (*s).disp += d.xyz;
    (*s).dxz += d.w;
    (*s).slope += g.xy;
    (*s).dxx += g.z;
    (*s).dzz += g.w;
    (*s).slope_variance += max(m.xy - g.xy * g.xy, vec2<f32>(0.0));
}

// FFT surface prefiltered over a square footprint of `footprint` metres
// (vertex and compute stages; 0 reads the finest level).
fn fft_sample_footprint(p: vec2<f32>, footprint: f32) -> SurfaceSample {
    var s = zero_sample();
    for (var c = 0u; c < surface.cascades; c++) {
        let uv = cascade_uv(p, c);
        let texel = surface.cascade_sizes[c] / f32(surface.fft_resolution);
        let lod = max(log2(max(footprint, 1e-6) / texel), 0.0);
        let d = textureSampleLevel(displacement_tex, surface_sampler, uv, c, lod);
        let g = textureSampleLevel(derivative_tex, surface_sampler, uv, c, lod);
        let m = textureSampleLevel(moments_tex, surface_sampler, uv, c, lod);
        add_cascade(&s, d, g, m);
    }
    return s;
}

// FFT surface with the footprint given by the screen derivatives of p
// (fragment stage: anisotropic filtering, no aliasing at the horizon).
fn fft_sample_grad(p: vec2<f32>, dpdx: vec2<f32>, dpdy: vec2<f32>) -> SurfaceSample {
    var s = zero_sample();
    for (var c = 0u; c < surface.cascades; c++) {
        let uv = cascade_uv(p, c);
        let l = surface.cascade_sizes[c];
        let gx = dpdx / l;
        let gy = dpdy / l;
        let d = textureSampleGrad(displacement_tex, surface_sampler_aniso, uv, c, gx, gy);
        let g = textureSampleGrad(derivative_tex, surface_sampler_aniso, uv, c, gx, gy);
        let m = textureSampleGrad(moments_tex, surface_sampler_aniso, uv, c, gx, gy);
        add_cascade(&s, d, g, m);
    }
    return s;
}

fn heightfield_texel(i: i32, j: i32) -> f32 {
    let dims = vec2<i32>(textureDimensions(heightfield_tex));
    return textureLoad(heightfield_tex, vec2<i32>(((i % dims.x) + dims.x) % dims.x, ((j % dims.y) + dims.y) % dims.y), 0).r;
}

// Bilinear height; sample (0, 0) sits at (−Lx/2, −Lz/2).
fn heightfield_height(p: vec2<f32>) -> f32 {
    let dims = vec2<f32>(textureDimensions(heightfield_tex));
    let f = (p / surface.cascade_sizes.xy + 0.5) * dims;
    let base = floor(f);
    let a = f - base;
    let i = i32(base.x);
    let j = i32(base.y);
    let top = mix(heightfield_texel(i, j), heightfield_texel(i + 1, j), a.x);
    let bottom = mix(heightfield_texel(i, j + 1), heightfield_texel(i + 1, j + 1), a.x);
    return mix(top, bottom, a.y);
}

// Heights and central-difference slopes one cell apart (twin:
// hydrolux_core::waves::heightfield::Heightfield::sample).
fn heightfield_sample(p: vec2<f32>) -> SurfaceSample {
    var s = zero_sample();
    let cell = surface.cascade_sizes.xy / vec2<f32>(textureDimensions(heightfield_tex));
    s.disp.y = heightfield_height(p);
    s.slope = vec2<f32>(
        (heightfield_height(p + vec2<f32>(cell.x, 0.0)) - heightfield_height(p - vec2<f32>(cell.x, 0.0))) / (2.0 * cell.x),
        (heightfield_height(p + vec2<f32>(0.0, cell.y)) - heightfield_height(p - vec2<f32>(0.0, cell.y))) / (2.0 * cell.y),
    );
    return s;
}

// The surface model as a pipeline constant, for pipelines built for one
// model (MODEL_*); SURFACE_MODEL_DYNAMIC
// reads it from the uniform. The renderer's pipelines are specialised: the
// dead models' code folds away, and Mesa's lavapipe 22 would otherwise
// recompile them (a switch on a uniform) each time their bind groups are
// set, keeping every copy: about 1 MB a frame.
override SURFACE_MODEL: u32 = 255u;
const SURFACE_MODEL_DYNAMIC: u32 = 255u;

fn surface_model() -> u32 {
    if (SURFACE_MODEL == SURFACE_MODEL_DYNAMIC) {
        return surface.model;
    }
    return SURFACE_MODEL;
}

// The interactive water as a pipeline constant: RIPPLES_NONE, RIPPLES_WALLS
// (the texture covers the domain, clamped at its edges), RIPPLES_OPEN (the
// texture tiles the plane; the window says which tile is simulated). Specialised
// like SURFACE_MODEL, so surfaces without it pay nothing.
override RIPPLES: u32 = 0u;

// The interactive water alone at p: h, ∂h/∂x, ∂h/∂z of the free surface,
// and w the fraction of cells a floating hull covers (0 outside its domain).
fn ripples_sample(p: vec2<f32>) -> vec4<f32> {
    if (RIPPLES == RIPPLES_NONE) {
        return vec4<f32>(0.0);
    }
    let w = surface.ripple_window;
    if (any(p < w.xy) || any(p > w.zw)) {
        return vec4<f32>(0.0);
    }
    let side = surface.ripple_side;
    var uv = (p - surface.ripple_origin) / side;
    if (RIPPLES == RIPPLES_WALLS) {
        let half_texel = surface.ripple_cell / (2.0 * side);
        uv = clamp(uv, vec2<f32>(half_texel), vec2<f32>(1.0 - half_texel));
    }
    return textureSampleLevel(ripple_tex, surface_sampler, uv, 0.0);
}

// The interactive water's (height, slope x, slope z) at world p.
fn ripples_at(p: vec2<f32>) -> vec3<f32> {
    return ripples_sample(p).xyz;
}

// The ripples' height and slopes at p, faded out where the footprint
// (m) spans several cells (their slopes then go into the roughness).
fn add_ripples(s: ptr<function, SurfaceSample>, p: vec2<f32>, footprint: f32) {
    if (RIPPLES == RIPPLES_NONE) {
        return;
    }
    let r = ripples_at(p);
    let keep = 1.0 - smoothstep(1.0, 4.0, footprint / surface.ripple_cell);
    (*s).disp.y += r.x;
    (*s).slope += r.yz * keep;
    (*s).slope_variance += r.yz * r.yz * (1.0 - keep * keep);
}

fn surface_sample_footprint(p: vec2<f32>, footprint: f32) -> SurfaceSample {
    var s = zero_sample();
    switch surface_model() {
        case MODEL_FFT: { s = fft_sample_footprint(p, footprint); }
        case MODEL_SINES: { s = sines_sample(p, footprint); }
        case MODEL_HEIGHTFIELD: { s = heightfield_sample(p); }
        default: {}
    }
    add_ripples(&s, p, footprint);
    return s;
}

fn surface_sample_grad(p: vec2<f32>, dpdx: vec2<f32>, dpdy: vec2<f32>) -> SurfaceSample {
    var s = zero_sample();
    let footprint = max(length(dpdx), length(dpdy));
    switch surface_model() {
        case MODEL_FFT: { s = fft_sample_grad(p, dpdx, dpdy); }
        case MODEL_SINES: { s = sines_sample(p, footprint); }
        case MODEL_HEIGHTFIELD: { s = heightfield_sample(p); }
        default: {}
    }
    add_ripples(&s, p, footprint);
    return s;
}

// Unit normal of the displaced surface: ∂p/∂z × ∂p/∂x.
fn surface_normal(s: SurfaceSample) -> vec3<f32> {
    let tx = vec3<f32>(1.0 + s.dxx, s.slope.x, s.dxz);
    let tz = vec3<f32>(s.dxz, s.slope.y, 1.0 + s.dzz);
    return normalize(cross(tz, tx));
}

fn surface_jacobian(s: SurfaceSample) -> f32 {
    return (1.0 + s.dxx) * (1.0 + s.dzz) - s.dxz * s.dxz;
}

// Foam's diffuse albedo (sea foam: 0.4–0.8 fresh to dense; Whitlock et
// al. 1982); twin hydrolux_core::whitewater::FOAM_ALBEDO.
const FOAM_ALBEDO: f32 = 0.8;

// The bubble cloud under fresh foam: the fraction of the light reaching it
// it scatters back up, and its bubbles' mean depth (m); twins
// hydrolux_core::whitewater::BUBBLE_CLOUD_REFLECTANCE, _DEPTH.
const BUBBLE_CLOUD_REFLECTANCE: f32 = 0.3;
const BUBBLE_CLOUD_DEPTH: f32 = 0.3;

// The fraction of sunlight a foam cover lets into the water: what a dense
// sheet does not scatter back (it absorbs next to nothing). Twin
// hydrolux_core::whitewater::foam_transmittance.
fn foam_transmittance(cover: f32) -> f32 {
    return 1.0 - FOAM_ALBEDO * cover;
}

// The foam's cover at p (any stage; the cells' own values, 0 without foam).
fn foam_cover_at(p: vec2<f32>) -> f32 {
    if (surface.foam_side <= 0.0) {
        return 0.0;
    }
    let uv = (p - surface.foam_origin) / surface.foam_side;
    if (surface.foam_tiles == 0u && (any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)))) {
        return 0.0;
    }
    return textureSampleLevel(foam_tex, surface_sampler, p / surface.foam_side, 0.0).x;
}

// How much of the foam window's cover shows at p: 1 inside a tiling
// window, faded out over a window's last 5% (not cut at its edge); 0 where
// there is no foam.
fn foam_window(p: vec2<f32>) -> f32 {
    if (surface.foam_side <= 0.0) {
        return 0.0;
    }
    if (surface.foam_tiles != 0u) {
        return 1.0;
    }
    let uv = (p - surface.foam_origin) / surface.foam_side;
    let edge = min(min(uv.x, 1.0 - uv.x), min(uv.y, 1.0 - uv.y));
    return clamp(edge / 0.05, 0.0, 1.0);
}

// The foam's cover at p, filtered over the footprint given by the screen
// derivatives of p (fragment stage); 0 where there is no foam.
fn foam_cover_grad(p: vec2<f32>, dpdx: vec2<f32>, dpdy: vec2<f32>) -> f32 {
    let inside = foam_window(p);
    if (inside <= 0.0) {
        return 0.0;
    }
    // The texture holds world cells modulo the window: sample at p / side.
    let st = p / surface.foam_side;
    return inside * textureSampleGrad(foam_tex, surface_sampler_aniso, st, dpdx / surface.foam_side, dpdy / surface.foam_side).x;
}

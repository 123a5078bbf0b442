// The water surface as a heightfield for ray tracing (seed 003 §3.3.1,
// Baboud & Décoret 2006): its min/max pyramid each frame (`reduce`; twin:
// hydrolux-core raytrace::MinMaxPyramid) from the samples `resample.wgsl`
// wrote; and `probe_rays`, which traces given rays against the ground for
// the GPU twin checks. The water shader traces against both
// (shaders/heightfield_trace.wgsl).
#import heightfield_trace, traced

@group(0) @binding(0) var<uniform> traced: TracedParams;
@group(0) @binding(1) var<storage, read_write> hf_heights: array<f32>;
@group(0) @binding(2) var<storage, read_write> hf_bounds: array<vec2<f32>>;
// x the level `reduce` writes (0: from the samples)
@group(1) @binding(0) var<uniform> level: vec4<u32>;

// Level k of the water's pyramid: at 0 each cell's corners' least and
// greatest height, above it the bounds of 2 × 2 entries of level k − 1.
@compute @workgroup_size(8, 8, 1)
fn reduce(@builtin(global_invocation_id) id: vec3<u32>) {
    let hf = traced.water;
    let k = level.x;
    let side = hf.cells >> k;
    if (id.x >= side || id.y >= side) {
        return;
    }
    let i = i32(id.x);
    let j = i32(id.y);
    var lo: f32;
    var hi: f32;
    if (k == 0u) {
        let a = hf_sample(hf, i, j);
        let b = hf_sample(hf, i + 1, j);
        let c = hf_sample(hf, i, j + 1);
        let d = hf_sample(hf, i + 1, j + 1);
        lo = min(min(a, b), min(c, d));
        hi = max(max(a, b), max(c, d));
    } else {
        let q = vec2<i32>(i, j) * 2;
        let a = hf_bounds_at(hf, k - 1u, q);
        let b = hf_bounds_at(hf, k - 1u, q + vec2<i32>(1, 0));
        let c = hf_bounds_at(hf, k - 1u, q + vec2<i32>(0, 1));
        let d = hf_bounds_at(hf, k - 1u, q + vec2<i32>(1, 1));
        lo = min(min(a.x, b.x), min(c.x, d.x));
        hi = max(max(a.y, b.y), max(c.y, d.y));
    }
    hf_bounds[hf_level_base(hf, k) + id.y * side + id.x] = vec2<f32>(lo, hi);
}

// GPU twin checks: each ray of `rays` (origin and reach; direction) traced
// against the ground; `hits` gets t (NO_ROOT: none).
@group(1) @binding(1) var<storage, read> rays: array<vec4<f32>>;
@group(1) @binding(2) var<storage, read_write> hits: array<f32>;

@compute @workgroup_size(64)
fn probe_rays(@builtin(global_invocation_id) id: vec3<u32>) {
    let count = arrayLength(&hits);
    if (id.x >= count) {
        return;
    }
    let o = rays[2u * id.x];
    let d = rays[2u * id.x + 1u];
    hits[id.x] = trace_heightfield(traced.ground, o.xyz, d.xyz, o.w);
}

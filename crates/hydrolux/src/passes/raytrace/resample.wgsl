// The water surface as a heightfield for ray tracing (seed 003 §3.3.1,
// Baboud & Décoret 2006): each frame its samples over a window around the
// camera, with the horizontal displacement undone (twin: hydrolux-core
// raytrace::Heightfield::resampled).
#import constants, surface, heightfield_trace, traced

@group(0) @binding(0) var<uniform> traced: TracedParams;
@group(0) @binding(1) var<storage, read_write> hf_heights: array<f32>;
@group(0) @binding(2) var<storage, read_write> hf_bounds: array<vec2<f32>>;

// Fixed-point steps that undo the choppy displacement: enough for the
// steepest FFT crests Hydrolux draws (|∂D/∂x| < 1 contracts the iteration).
const RESAMPLE_ITERATIONS: u32 = 6u;

@compute @workgroup_size(8, 8, 1)
fn resample(@builtin(global_invocation_id) id: vec3<u32>) {
    let hf = traced.water;
    let n = hf.samples;
    if (id.x >= n || id.y >= n) {
        return;
    }
    let x = hf.origin + vec2<f32>(id.xy) * hf.spacing;
    var rest = x;
    var s = surface_sample_footprint(rest, hf.spacing);
    for (var k = 0u; k < RESAMPLE_ITERATIONS; k++) {
        rest = x - s.disp.xz;
        s = surface_sample_footprint(rest, hf.spacing);
    }
    hf_heights[hf.first_sample + id.y * n + id.x] = s.disp.y;
}

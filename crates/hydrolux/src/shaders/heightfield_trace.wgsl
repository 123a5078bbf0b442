// Exact ray–heightfield intersection over a min/max pyramid (seed 003
// §3.3.1 after Baboud & Décoret 2006; the maximum-mipmap traversal of Tevs,
// Ihrke & Seidel 2008). Twin: hydrolux-core raytrace.rs (trace_hierarchical,
// cell_crossing, first_root), line by line.
//
// A heightfield lives in two storage arrays the importing shader declares,
// `hf_heights: array<f32>` (n × n corner samples, row = z, from
// `base.x`) and `hf_bounds: array<vec2<f32>>` (its min/max pyramid from
// `base.y`: level 0 one entry per cell holding its corners' least and
// greatest height, each next level the bounds of 2 × 2 entries below, the
// levels one after the other). Storage, not textures: the water shader has
// no sampled-texture slots left.

struct Heightfield {
    // World (x, z) of sample (0, 0), the sample spacing (m), the height
    // beyond the sampled square.
    origin: vec2<f32>,
    spacing: f32,
    outside: f32,
    // Cells per side at level 0 (a power of two), samples per side n, the
    // pyramid's top level, the most pyramid steps a ray takes
    // (water.trace_steps; spent without a hit, the ray misses).
    cells: u32,
    samples: u32,
    top_level: u32,
    max_steps: u32,
    // First sample in hf_heights, first bound in hf_bounds.
    first_sample: u32,
    first_bound: u32,
    _pad0: u32,
    _pad1: u32,
}

fn hf_sample(hf: Heightfield, i: i32, j: i32) -> f32 {
    let n = i32(hf.samples);
    if (i < 0 || j < 0 || i >= n || j >= n) {
        return hf.outside;
    }
    return hf_heights[hf.first_sample + u32(j * n + i)];
}

// Where level k of the pyramid starts: the levels below it hold
// Σ (side/2^l)² = (side² − (side/2^k)²)·4/3 entries.
fn hf_level_base(hf: Heightfield, k: u32) -> u32 {
    let side = hf.cells;
    let s = side >> k;
    return hf.first_bound + (side * side - s * s) / 3u * 4u;
}

fn hf_bounds_at(hf: Heightfield, k: u32, b: vec2<i32>) -> vec2<f32> {
    let s = i32(hf.cells >> k);
    return hf_bounds[hf_level_base(hf, k) + u32(b.y * s + b.x)];
}

// Bilinear height at world (x, z); the outside height off the grid.
fn hf_height(hf: Heightfield, x: f32, z: f32) -> f32 {
    let u = (x - hf.origin.x) / hf.spacing;
    let v = (z - hf.origin.y) / hf.spacing;
    let c = f32(hf.samples) - 1.0;
    if (!(u >= 0.0 && v >= 0.0 && u <= c && v <= c)) {
        return hf.outside;
    }
    let i = min(i32(floor(u)), i32(hf.samples) - 2);
    let j = min(i32(floor(v)), i32(hf.samples) - 2);
    let a = u - f32(i);
    let b = v - f32(j);
    let h00 = hf_sample(hf, i, j);
    let h10 = hf_sample(hf, i + 1, j);
    let h01 = hf_sample(hf, i, j + 1);
    let h11 = hf_sample(hf, i + 1, j + 1);
    return h00 * (1.0 - a) * (1.0 - b) + h10 * a * (1.0 - b) + h01 * (1.0 - a) * b + h11 * a * b;
}

const NO_ROOT: f32 = 3.4e38;

// The first t in [t0, t1] where c0 + c1·t + c2·t² changes sign (or is 0);
// NO_ROOT if none.
fn first_root(c0: f32, c1: f32, c2: f32, t0: f32, t1: f32) -> f32 {
    let f0 = c0 + t0 * (c1 + t0 * c2);
    let f1 = c0 + t1 * (c1 + t1 * c2);
    var r0 = NO_ROOT;
    var r1 = NO_ROOT;
    if (abs(c2) <= 1e-7 * max(abs(c1) + abs(c0), 1e-20)) {
        if (c1 != 0.0) {
            r0 = -c0 / c1;
        }
    } else {
        let disc = c1 * c1 - 4.0 * c2 * c0;
        if (disc >= 0.0) {
            let sgn = select(-1.0, 1.0, c1 >= 0.0);
            let q = -0.5 * (c1 + sgn * sqrt(disc));
            let a = q / c2;
            var b = NO_ROOT;
            if (q != 0.0) {
                b = c0 / q;
            }
            r0 = min(a, b);
            r1 = max(a, b);
        }
    }
    if (r0 >= t0 && r0 <= t1) {
        return r0;
    }
    if (r1 >= t0 && r1 <= t1) {
        return r1;
    }
    if (f1 == 0.0) {
        return t1;
    }
    if (f0 * f1 < 0.0) {
        return t0;
    }
    return NO_ROOT;
}

// The ray's first crossing of cell (i, j)'s bilinear patch in [t0, t1].
fn cell_crossing(hf: Heightfield, o: vec3<f32>, d: vec3<f32>, i: i32, j: i32, t0: f32, t1: f32) -> f32 {
    let h00 = hf_sample(hf, i, j);
    let h10 = hf_sample(hf, i + 1, j);
    let h01 = hf_sample(hf, i, j + 1);
    let h11 = hf_sample(hf, i + 1, j + 1);
    let a0 = (o.x - hf.origin.x) / hf.spacing - f32(i);
    let a1 = d.x / hf.spacing;
    let b0 = (o.z - hf.origin.y) / hf.spacing - f32(j);
    let b1 = d.z / hf.spacing;
    let ea = h10 - h00;
    let eb = h01 - h00;
    let k = h00 - h10 - h01 + h11;
    let c0 = o.y - (h00 + ea * a0 + eb * b0 + k * a0 * b0);
    let c1 = d.y - (ea * a1 + eb * b1 + k * (a0 * b1 + a1 * b0));
    let c2 = -k * a1 * b1;
    return first_root(c0, c1, c2, t0, t1);
}

// The first crossing (t; NO_ROOT if none) within t_max of the ray o + t·d
// with the heightfield, from whichever side the ray starts on.
fn trace_heightfield(hf: Heightfield, o: vec3<f32>, d: vec3<f32>, t_max: f32) -> f32 {
    var s = 1.0;
    if (o.y < hf_height(hf, o.x, o.z)) {
        s = -1.0;
    }
    let top = hf.top_level;
    let span = f32(hf.cells) * hf.spacing;
    let lo = hf.origin;
    var t_in = 0.0;
    var t_out = t_max;
    let oxz = vec2<f32>(o.x, o.z);
    let dxz = vec2<f32>(d.x, d.z);
    for (var k = 0; k < 2; k++) {
        if (abs(dxz[k]) < 1e-12) {
            if (oxz[k] < lo[k] || oxz[k] > lo[k] + span) {
                t_in = NO_ROOT;
            }
        } else {
            let ta = (lo[k] - oxz[k]) / dxz[k];
            let tb = (lo[k] + span - oxz[k]) / dxz[k];
            t_in = max(t_in, min(ta, tb));
            t_out = min(t_out, max(ta, tb));
        }
    }
    // Off the grid the heightfield is the plane y = outside.
    let c0 = o.y - hf.outside;
    if (t_in >= t_out) {
        return first_root(c0, d.y, 0.0, 0.0, t_max);
    }
    // A thousandth of a cell sideways along the ray: where it goes next.
    let nudge = 1e-3 * hf.spacing / max(max(abs(d.x), abs(d.z)), 1e-3);
    let before = first_root(c0, d.y, 0.0, 0.0, t_in);
    if (before != NO_ROOT) {
        return before;
    }
    // The grid's edge is a wall between it and the outside plane: a ray
    // that meets the grid already on the other side hits the wall.
    if (t_in > 0.0) {
        let q = o + d * (t_in + nudge);
        if (s * (o.y + t_in * d.y - hf_height(hf, q.x, q.z)) < 0.0) {
            return t_in;
        }
    }
    var t = t_in;
    var level = top;
    for (var guard = 0u; guard < hf.max_steps && t < t_out; guard++) {
        let size = hf.spacing * f32(1u << level);
        let p = o + d * (t + nudge);
        let n = i32(hf.cells >> level);
        let bi = clamp(i32(floor((p.x - lo.x) / size)), 0, n - 1);
        let bj = clamp(i32(floor((p.z - lo.y) / size)), 0, n - 1);
        var t_exit = t_out;
        let b = vec2<i32>(bi, bj);
        for (var k = 0; k < 2; k++) {
            if (abs(dxz[k]) > 1e-12) {
                let edge = lo[k] + f32(b[k] + select(0, 1, dxz[k] > 0.0)) * size;
                t_exit = min(t_exit, (edge - oxz[k]) / dxz[k]);
            }
        }
        t_exit = max(t_exit, t);
        let y0 = o.y + t * d.y;
        let y1 = o.y + t_exit * d.y;
        let bounds = hf_bounds_at(hf, level, b);
        var clear = max(y0, y1) < bounds.x;
        if (s > 0.0) {
            clear = min(y0, y1) > bounds.y;
        }
        if (clear) {
            t = t_exit;
            level = min(level + 1u, top);
            continue;
        }
        if (level > 0u) {
            level -= 1u;
            continue;
        }
        let r = cell_crossing(hf, o, d, bi, bj, t, t_exit);
        if (r != NO_ROOT) {
            return r;
        }
        t = t_exit;
    }
    if (t < t_out) {
        // The budget is spent short of the grid's far side.
        return NO_ROOT;
    }
    if (t_out < t_max && s * (o.y + t_out * d.y - hf.outside) < 0.0) {
        return t_out;
    }
    return first_root(c0, d.y, 0.0, t_out, t_max);
}

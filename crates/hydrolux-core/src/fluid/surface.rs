//! The liquid's surface by marching cubes (seed 003 §3.1, after Lorensen &
//! Cline 1987), the CPU twin of `simulation/liquid/surface.wgsl`.
//!
//! 1. **Splat** ([`splat`]): each particle adds the kernel
//!    W(r) = (1 − r²/R²)³ (r < R) to the grid's nodes, with R = 2 s for the
//!    particles' spacing s, scaled so that a liquid filled at one particle
//!    per s³ reads 1 (∫W dV = 64πR³/315): the density, channel 0. Channels
//!    1–3 sum the same weights times the particle's position (as a fraction
//!    of the grid's extent), so that each node also knows the weighted mean
//!    of the particles near it. The sums are in fixed point
//!    ([`DENSITY_FIXED_POINT`]) so that the GPU's atomic sums do not depend
//!    on the particles' order.
//! 2. **Level** ([`level`]), the field that is meshed at [`ISO_LEVEL`] = ½,
//!    one of two (`fluid.surface_field`):
//!    - `mean_position` (the default), after Zhu & Bridson 2005 ("Animating
//!      sand as a fluid", §3.3): φ = |x − x̄| − r, the distance to the
//!      particles' weighted mean x̄ less a radius r, mapped to ½ − φ/R. It
//!      does not depend on how many particles are near, only where they
//!      are, so the clumps and gaps a FLIP liquid settles into (a few
//!      particles more or less in a cell) do not bump its surface, and a
//!      lone particle or a thin sheet keeps a radius r. r = 0.55 s puts a
//!      lattice's flat face where its volume ends, half a spacing beyond
//!      the last layer.
//!    - `density`: the density itself, a blobby surface, which for a
//!      half-space of particles also lies half a spacing beyond the last
//!      layer; splashsurf's kind of field, kept to compare.
//!
//!    [`smooth`] then filters the level.
//! 3. **Cases** ([`case_table`]): a cell's eight corners in or out make one
//!    of 256 cases (15 up to symmetry). Rather than a typed-in table, each
//!    case's polygons are derived: on each of the cube's faces, every run
//!    of inside corners is cut off by one segment between the edges where
//!    it starts and ends (so a face with two opposite corners inside cuts
//!    them apart, and the neighbouring cell, reading the same four corners,
//!    makes the same cut: the surface is watertight). The segments chain
//!    into loops around the cube, each triangulated as a fan, wound so that
//!    the triangles face out of the liquid.
//! 4. **Vertices** on the grid's edges by linear interpolation of the field
//!    (eq. 18), one per edge shared by the four cells around it; normals by
//!    central differences of the field at the edge's two nodes (eq. 19–20),
//!    interpolated the same way, pointing down the field (out of the
//!    liquid).

use crate::scene::SurfaceField;
use std::sync::OnceLock;

/// The level of the normalised density that is the surface.
pub const ISO_LEVEL: f32 = 0.5;
/// The kernel's reach in particle spacings.
pub const KERNEL_SUPPORT_SPACINGS: f32 = 2.0;
/// Units of the density's fixed-point sum per unit of density.
pub const DENSITY_FIXED_POINT: f32 = 65536.0;
/// The splat's channels: the density, then its moments along x, y and z.
pub const CHANNELS: usize = 4;
/// r of the mean-position field in particle spacings: a lattice's flat
/// face lies half a spacing beyond its last layer (the weighted mean of a
/// half-space's particles within 2 spacings of a node there is 0.545 s
/// below it).
pub const PARTICLE_RADIUS_SPACINGS: f32 = 0.55;
/// Triangles a case has at most (with this table's face rule).
pub const MAX_CASE_TRIANGLES: usize = 5;

/// The corner offsets of cube corner `c` (bit 0 x, bit 1 y, bit 2 z).
pub const fn corner_offset(c: usize) -> [usize; 3] {
    [c & 1, (c >> 1) & 1, (c >> 2) & 1]
}

/// The cube's 12 edges as (lower corner, axis): edge `4·axis + k`.
pub fn cube_edge(e: usize) -> (usize, usize) {
    let axis = e / 4;
    let k = e % 4;
    // The two bits other than `axis`, in order, from k.
    let others: [usize; 2] = match axis {
        0 => [1, 2],
        1 => [0, 2],
        _ => [0, 1],
    };
    let lower = ((k & 1) << others[0]) | (((k >> 1) & 1) << others[1]);
    (lower, axis)
}

fn edge_between(a: usize, b: usize) -> usize {
    let diff = a ^ b;
    let axis = diff.trailing_zeros() as usize;
    let lower = a.min(b);
    (0..12).find(|&e| cube_edge(e) == (lower, axis)).expect("corners share an edge")
}

/// Each case's triangles as cube edges, three per triangle.
pub struct CaseTable {
    pub triangles: [Vec<[u8; 3]>; 256],
}

impl CaseTable {
    /// The table as the GPU reads it: per case, the triangle count then
    /// `3·MAX_CASE_TRIANGLES` edges (unused ones 0).
    pub fn packed(&self) -> Vec<u32> {
        let stride = 1 + 3 * MAX_CASE_TRIANGLES;
        let mut out = vec![0u32; 256 * stride];
        for (case, tris) in self.triangles.iter().enumerate() {
            out[case * stride] = tris.len() as u32;
            for (t, tri) in tris.iter().enumerate() {
                for (v, &e) in tri.iter().enumerate() {
                    out[case * stride + 1 + 3 * t + v] = e as u32;
                }
            }
        }
        out
    }
}

/// The 256 cases, derived once.
pub fn case_table() -> &'static CaseTable {
    static TABLE: OnceLock<CaseTable> = OnceLock::new();
    TABLE.get_or_init(|| {
        let faces = cube_faces();
        let mut triangles: [Vec<[u8; 3]>; 256] = std::array::from_fn(|_| Vec::new());
        for (case, tris) in triangles.iter_mut().enumerate() {
            let inside = |c: usize| case >> c & 1 == 1;
            // Segments (from edge, to edge): per face, from where an inside
            // run ends to where it began, walking the face counter-clockwise
            // seen from outside. A crossing ends one face's segment and
            // starts its neighbour's, which walks the edge the other way.
            let mut next = [usize::MAX; 12];
            for ring in &faces {
                for i in 0..4 {
                    let (a, b) = (ring[i], ring[(i + 1) % 4]);
                    if !inside(a) && inside(b) {
                        let enter = edge_between(a, b);
                        // Walk on to where the run leaves.
                        let mut j = (i + 1) % 4;
                        while inside(ring[(j + 1) % 4]) {
                            j = (j + 1) % 4;
                        }
                        let leave = edge_between(ring[j], ring[(j + 1) % 4]);
                        next[leave] = enter;
                    }
                }
            }
            let mut used = [false; 12];
            for start in 0..12 {
                if next[start] == usize::MAX || used[start] {
                    continue;
                }
                let mut lp = vec![start];
                used[start] = true;
                let mut e = next[start];
                while e != start {
                    used[e] = true;
                    lp.push(e);
                    e = next[e];
                }
                let mut loop_tris = Vec::new();
                assert!(triangulate(&lp, &mut loop_tris), "case {case} has a loop {lp:?}");
                // Reversed: the loop runs clockwise seen from outside the
                // liquid.
                tris.extend(loop_tris.iter().map(|t| [t[0] as u8, t[2] as u8, t[1] as u8]));
            }
        }
        CaseTable { triangles }
    })
}

/// Whether two cube edges lie on one face of the cube.
fn share_a_face(a: usize, b: usize) -> bool {
    let faces = |e: usize| {
        let (lower, axis) = cube_edge(e);
        let mut out = [(9, 9); 2];
        for (n, f) in (0..3).filter(|&f| f != axis).enumerate() {
            out[n] = (f, lower >> f & 1);
        }
        out
    };
    let (fa, fb) = (faces(a), faces(b));
    fa.iter().any(|f| fb.contains(f))
}

/// Triangles (in the loop's winding) covering the loop `poly` of cube
/// edges, with no diagonal between two vertices on one face of the cube:
/// the cell across that face may join them too (where it has two segments),
/// and the edge would then belong to four triangles.
fn triangulate(poly: &[usize], out: &mut Vec<[usize; 3]>) -> bool {
    let n = poly.len();
    if n < 3 {
        return n == 0;
    }
    if n == 3 {
        out.push([poly[0], poly[1], poly[2]]);
        return true;
    }
    // The triangle on the side poly[n-1] → poly[0]: its apex k.
    for k in 1..n - 1 {
        let ok = |i: usize, j: usize| j == i + 1 || !share_a_face(poly[i], poly[j]);
        if !(ok(0, k) && ok(k, n - 1)) {
            continue;
        }
        let mark = out.len();
        out.push([poly[0], poly[k], poly[n - 1]]);
        let left = if k > 1 { triangulate(&poly[..=k], out) } else { true };
        if left && (k >= n - 2 || triangulate(&poly[k..], out)) {
            return true;
        }
        out.truncate(mark);
    }
    false
}

/// The cube's six faces, each its four corners counter-clockwise seen from
/// outside the cube.
fn cube_faces() -> [[usize; 4]; 6] {
    let mut faces = [[0; 4]; 6];
    for axis in 0..3 {
        for side in 0..2 {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            // (u, v) then the right-handed order around +axis.
            let corner = |bu: usize, bv: usize| (side << axis) | (bu << u) | (bv << v);
            let mut ring = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
            if side == 0 {
                ring.reverse();
            }
            faces[axis * 2 + side] = ring;
        }
    }
    faces
}

/// The nodes the density lives on: `nodes` per axis from `origin`, `h`
/// apart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceGrid {
    pub origin: [f32; 3],
    pub h: f32,
    pub nodes: [u32; 3],
}

impl SurfaceGrid {
    /// A grid over the box `min..max` with `cells` along its longest side,
    /// widened by two cells all round: its outer nodes are outside the
    /// liquid, so the mesh is closed, and the nodes between them and the
    /// box carry the liquid through a closed wall ([`Walls`]).
    pub fn over(min: [f32; 3], max: [f32; 3], cells: u32) -> SurfaceGrid {
        let extent = [0, 1, 2].map(|a| max[a] - min[a]);
        let longest = extent.iter().fold(0.0f32, |m, &e| m.max(e));
        let h = longest / cells.max(1) as f32;
        let nodes = extent.map(|e| (e / h).ceil() as u32 + 5);
        SurfaceGrid { origin: [0, 1, 2].map(|a| min[a] - 2.0 * h), h, nodes }
    }

    pub fn node_count(&self) -> usize {
        self.nodes.iter().map(|&n| n as usize).product()
    }

    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        i + self.nodes[0] as usize * (j + self.nodes[1] as usize * k)
    }

    pub fn position(&self, i: usize, j: usize, k: usize) -> [f32; 3] {
        let ijk = [i, j, k];
        [0, 1, 2].map(|a| self.origin[a] + self.h * ijk[a] as f32)
    }
}

/// The kernel's weight per particle, normalised so that particles a spacing
/// s apart in every direction sum to 1: Σ W ≈ ∫W dV / s³ = 64πR³/(315 s³),
/// with R in spacings.
pub fn kernel_scale() -> f32 {
    let r = KERNEL_SUPPORT_SPACINGS;
    315.0 / (64.0 * std::f32::consts::PI * r * r * r)
}

/// One particle's fixed-point contribution at squared distance `d2`, with
/// the kernel's reach `reach` (m): its weight in units, before rounding
/// (0 beyond the reach).
pub fn contribution(d2: f32, reach: f32, scale: f32) -> f32 {
    let q2 = d2 / (reach * reach);
    if q2 >= 1.0 {
        return 0.0;
    }
    let w = (1.0 - q2) * (1.0 - q2) * (1.0 - q2);
    w * scale * DENSITY_FIXED_POINT
}

/// Units of a contribution `units` (from [`contribution`]) times `u`, the
/// fraction of the grid's extent along an axis, or times 1 for the density;
/// rounded half up (as `surface.wgsl`).
pub fn units_of(units: f32, u: f32) -> u32 {
    (units * u + 0.5) as u32
}

impl SurfaceGrid {
    /// The span from the first node to the last along each axis (m).
    pub fn extent(&self) -> [f32; 3] {
        [0, 1, 2].map(|a| self.h * (self.nodes[a] - 1) as f32)
    }

    /// `p`'s place in the grid as a fraction of its extent per axis.
    pub fn fraction(&self, p: [f32; 3]) -> [f32; 3] {
        let extent = self.extent();
        [0, 1, 2].map(|a| ((p[a] - self.origin[a]) / extent[a]).clamp(0.0, 1.0))
    }
}

/// The fixed-point splat of `particles` (m) spaced `spacing` (m) apart on
/// `grid`'s nodes: [`CHANNELS`] blocks of a value per node, the density
/// then its moments along x, y, z.
pub fn splat(grid: &SurfaceGrid, particles: &[[f32; 3]], spacing: f32) -> Vec<u32> {
    let n = grid.node_count();
    let mut sum = vec![0u32; CHANNELS * n];
    let reach = KERNEL_SUPPORT_SPACINGS * spacing;
    let scale = kernel_scale();
    for p in particles {
        let u = grid.fraction(*p);
        let lo = [0, 1, 2].map(|a| {
            (((p[a] - reach - grid.origin[a]) / grid.h).ceil().max(0.0) as usize)
                .min(grid.nodes[a] as usize)
        });
        let hi = [0, 1, 2].map(|a| {
            (((p[a] + reach - grid.origin[a]) / grid.h).floor() + 1.0)
                .clamp(0.0, grid.nodes[a] as f32) as usize
        });
        for k in lo[2]..hi[2] {
            for j in lo[1]..hi[1] {
                for i in lo[0]..hi[0] {
                    let x = grid.position(i, j, k);
                    let d2 = (0..3).map(|a| (x[a] - p[a]) * (x[a] - p[a])).sum::<f32>();
                    let units = contribution(d2, reach, scale);
                    if units == 0.0 {
                        continue;
                    }
                    let at = grid.index(i, j, k);
                    sum[at] = sum[at].wrapping_add(units_of(units, 1.0));
                    for a in 0..3 {
                        let c = (a + 1) * n + at;
                        sum[c] = sum[c].wrapping_add(units_of(units, u[a]));
                    }
                }
            }
        }
    }
    sum
}

/// `passes` rounds of the binomial filter (¼, ½, ¼) along x, then y, then z
/// over the level (`fluid.surface_smoothing`): it takes out the particles'
/// jitter, which would show as bumps the size of a spacing, and leaves a
/// linear field — a flat surface — where it was. (Filtering the level, not
/// the splat, keeps the mean-position field's flat faces where they are: a
/// wider kernel's mean would lie deeper and shrink the liquid.) Beyond the
/// grid's edge the level is taken as zero, outside.
pub fn smooth(grid: &SurfaceGrid, values: &mut [f32], passes: u32) {
    let n = grid.nodes.map(|v| v as usize);
    let stride = [1, n[0], n[0] * n[1]];
    let mut out = vec![0.0f32; values.len()];
    for _ in 0..passes {
        for axis in 0..3 {
            for k in 0..n[2] {
                for j in 0..n[1] {
                    for i in 0..n[0] {
                        let at = grid.index(i, j, k);
                        let c = [i, j, k][axis];
                        let lo = if c > 0 { values[at - stride[axis]] } else { 0.0 };
                        let hi = if c + 1 < n[axis] { values[at + stride[axis]] } else { 0.0 };
                        out[at] = filtered(lo, values[at], hi);
                    }
                }
            }
            values.copy_from_slice(&out);
        }
    }
}

/// One tap of the binomial filter (`surface.wgsl` the same).
pub fn filtered(lo: f32, mid: f32, hi: f32) -> f32 {
    0.25 * (lo + hi) + 0.5 * mid
}

/// The fixed-point splat's density (its first channel) as densities.
pub fn density(fixed: &[u32]) -> Vec<f32> {
    fixed[..fixed.len() / CHANNELS].iter().map(|&v| v as f32 / DENSITY_FIXED_POINT).collect()
}

/// The domain's closed walls as the level sees them. A liquid's particles
/// stop half a spacing short of a wall, so a surface of them alone stands
/// off it, rounded and bumped: an air gap between water and its glass,
/// which the eye reads as a crumpled mirror. Instead the liquid is carried
/// through a closed wall: a node nearer the wall than
/// [`WALL_BAND_SPACINGS`] has at least the level of the node that far
/// inside (`inner_lo`..`inner_hi`); a node beyond the wall is inside where
/// that node is and outside where it is not; the outermost node is outside. So the liquid meets the wall
/// square and ends flat beyond it, halfway between the last two nodes: in
/// a glass's wall, under a floor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Walls {
    pub inner_lo: [u32; 3],
    pub inner_hi: [u32; 3],
    /// The first node past the box's high side per axis (the nodes below
    /// 2 are past its low side: the grid starts two cells out).
    pub beyond_hi: [u32; 3],
    /// Bit 2a: the low side along axis a is closed; bit 2a + 1: the high.
    pub closed: u32,
}

/// How far inside a closed wall (in particle spacings) the level that is
/// carried through it is read: past the voids a FLIP liquid leaves along
/// its walls a spacing in, which would dimple the face.
pub const WALL_BAND_SPACINGS: f32 = 2.0;

/// How a node's level is found (`Walls::source`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LevelSource {
    /// Its own.
    Own,
    /// Outside (an outermost node past a closed wall).
    Outside,
    /// Past a closed wall: inside where node q is, outside elsewhere.
    Beyond([u32; 3]),
    /// Near a closed wall: at least node q's.
    AtLeast([u32; 3]),
}

impl Walls {
    /// The walls of the box `min..max` (all closed but `open`, per axis
    /// low and high) for particles `spacing` apart, on `grid`.
    pub fn of(
        grid: &SurfaceGrid,
        [min, max]: [[f32; 3]; 2],
        open: [[bool; 2]; 3],
        spacing: f32,
    ) -> Walls {
        let last = grid.nodes.map(|n| n.saturating_sub(1) as f32);
        let node = |x: f32, a: usize| (x - grid.origin[a]) / grid.h;
        let band = WALL_BAND_SPACINGS * spacing;
        let inner_lo = [0, 1, 2].map(|a| node(min[a] + band, a).ceil().clamp(2.0, last[a]));
        let inner_hi = [0, 1, 2].map(|a| node(max[a] - band, a).floor().clamp(0.0, last[a]));
        // A node within a thousandth of a cell of the wall is on it.
        let beyond_hi = [0, 1, 2].map(|a| (node(max[a], a) + 1e-3).floor() as u32 + 1);
        let mut closed = 0;
        for (a, sides) in open.iter().enumerate() {
            for (side, &is_open) in sides.iter().enumerate() {
                if !is_open {
                    closed |= 1 << (2 * a + side);
                }
            }
        }
        Walls {
            inner_lo: inner_lo.map(|v| v as u32),
            inner_hi: [0, 1, 2].map(|a| inner_hi[a].max(inner_lo[a]) as u32),
            beyond_hi,
            closed,
        }
    }

    /// How node `p` of a grid of `nodes` finds its level.
    pub fn source(&self, nodes: [u32; 3], p: [u32; 3]) -> LevelSource {
        if self.closed == 0 {
            return LevelSource::Own;
        }
        let mut q = p;
        let mut beyond = false;
        for a in 0..3 {
            let (low, high) =
                (self.closed >> (2 * a) & 1 != 0, self.closed >> (2 * a + 1) & 1 != 0);
            if (low && p[a] == 0) || (high && p[a] + 1 == nodes[a]) {
                return LevelSource::Outside;
            }
            if low {
                beyond |= p[a] < 2;
                q[a] = q[a].max(self.inner_lo[a]);
            }
            if high {
                beyond |= p[a] >= self.beyond_hi[a];
                q[a] = q[a].min(self.inner_hi[a]);
            }
        }
        match (beyond, q != p) {
            (true, _) => LevelSource::Beyond(q),
            (false, true) => LevelSource::AtLeast(q),
            (false, false) => LevelSource::Own,
        }
    }
}

/// The level outside the liquid (where no particle reaches).
pub fn outside_level(field: SurfaceField, spacing: f32) -> f32 {
    match field {
        SurfaceField::Density => 0.0,
        // As `node_level` holds it (the same arithmetic).
        SurfaceField::MeanPosition => {
            ISO_LEVEL - (PARTICLE_RADIUS_SPACINGS * spacing) / (KERNEL_SUPPORT_SPACINGS * spacing)
        }
    }
}

/// The level deep inside the liquid: a full liquid's density, or the mean
/// position's ½ + r/R.
pub fn inside_level(field: SurfaceField, spacing: f32) -> f32 {
    match field {
        SurfaceField::Density => 1.0,
        SurfaceField::MeanPosition => {
            ISO_LEVEL + (PARTICLE_RADIUS_SPACINGS * spacing) / (KERNEL_SUPPORT_SPACINGS * spacing)
        }
    }
}

/// The field that is meshed at [`ISO_LEVEL`], per node, from the splat of
/// particles `spacing` apart: the density, or ½ − φ/R with φ = |x − x̄| − r
/// from the particles' weighted mean x̄ (held within r/R of ½), carried
/// through the closed `walls`.
pub fn level(
    grid: &SurfaceGrid,
    fixed: &[u32],
    spacing: f32,
    field: SurfaceField,
    walls: &Walls,
) -> Vec<f32> {
    let n = grid.node_count();
    let reach = KERNEL_SUPPORT_SPACINGS * spacing;
    let radius = PARTICLE_RADIUS_SPACINGS * spacing;
    let extent = grid.extent();
    let own = |p: [u32; 3]| {
        let [i, j, k] = p.map(|v| v as usize);
        let at = grid.index(i, j, k);
        let moments = [fixed[n + at], fixed[2 * n + at], fixed[3 * n + at]];
        node_level(
            grid.position(i, j, k),
            fixed[at],
            moments,
            [grid.origin, extent],
            [reach, radius],
            field,
        )
    };
    let mut out = vec![0.0; n];
    for k in 0..grid.nodes[2] {
        for j in 0..grid.nodes[1] {
            for i in 0..grid.nodes[0] {
                let p = [i, j, k];
                out[grid.index(i as usize, j as usize, k as usize)] = match walls
                    .source(grid.nodes, p)
                {
                    LevelSource::Own => own(p),
                    LevelSource::Outside => outside_level(field, spacing),
                    LevelSource::Beyond(q) if own(q) > ISO_LEVEL => inside_level(field, spacing),
                    LevelSource::Beyond(_) => outside_level(field, spacing),
                    LevelSource::AtLeast(q) => own(p).max(own(q)),
                };
            }
        }
    }
    out
}

/// One node's level (`surface.wgsl`'s `node_level`, the same arithmetic):
/// at `x`, from its density `weight` and `moments` in fixed point, the
/// grid's `[origin, extent]`, the kernel's `[reach, radius]`.
pub fn node_level(
    x: [f32; 3],
    weight: u32,
    moments: [u32; 3],
    [origin, extent]: [[f32; 3]; 2],
    [reach, radius]: [f32; 2],
    field: SurfaceField,
) -> f32 {
    match field {
        SurfaceField::Density => weight as f32 / DENSITY_FIXED_POINT,
        SurfaceField::MeanPosition => {
            // Deep inside, x̄ = x and the level is ½ + r/R; outside it is
            // held as far below ½, so that the smoothing, which sees an
            // odd profile about the level, leaves a flat face where it is.
            let span = radius / reach;
            if weight == 0 {
                return ISO_LEVEL - span;
            }
            let w = weight as f32;
            let mut d2 = 0.0;
            for a in 0..3 {
                let mean = origin[a] + extent[a] * (moments[a] as f32 / w);
                d2 += (x[a] - mean) * (x[a] - mean);
            }
            (ISO_LEVEL - (d2.sqrt() - radius) / reach).max(ISO_LEVEL - span)
        }
    }
}

/// An indexed triangle mesh, wound counter-clockwise seen from outside.
#[derive(Clone, Debug, Default)]
pub struct SurfaceMesh {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub indices: Vec<u32>,
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| a[i] as f64 - b[i] as f64)
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

impl SurfaceMesh {
    pub fn triangles(&self) -> impl Iterator<Item = [[f32; 3]; 3]> + '_ {
        self.indices.chunks_exact(3).map(|t| [0, 1, 2].map(|v| self.positions[t[v] as usize]))
    }

    /// Total area (m²).
    pub fn area(&self) -> f64 {
        self.triangles()
            .map(|[a, b, c]| {
                let n = cross(sub(b, a), sub(c, a));
                0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
            })
            .sum()
    }

    /// The volume enclosed (m³), by the divergence theorem: positive for a
    /// closed mesh wound outwards.
    pub fn volume(&self) -> f64 {
        self.triangles()
            .map(|[a, b, c]| {
                let a = a.map(f64::from);
                let n = cross(sub(b, [0.0; 3]), sub(c, [0.0; 3]));
                (a[0] * n[0] + a[1] * n[1] + a[2] * n[2]) / 6.0
            })
            .sum()
    }
}

/// The level set `iso` of `values` (one per node of `grid`).
pub fn marching_cubes(grid: &SurfaceGrid, values: &[f32], iso: f32) -> SurfaceMesh {
    let table = case_table();
    let n = grid.nodes.map(|v| v as usize);
    let value = |i: usize, j: usize, k: usize| values[grid.index(i, j, k)];
    // ∇ by central differences (one-sided at the grid's border).
    let gradient = |i: usize, j: usize, k: usize| {
        let ijk = [i, j, k];
        [0, 1, 2].map(|a| {
            let (mut lo, mut hi) = (ijk, ijk);
            lo[a] = ijk[a].saturating_sub(1);
            hi[a] = (ijk[a] + 1).min(n[a] - 1);
            (value(hi[0], hi[1], hi[2]) - value(lo[0], lo[1], lo[2]))
                / ((hi[a] - lo[a]) as f32 * grid.h)
        })
    };
    let mut mesh = SurfaceMesh::default();
    // The vertex on each node's +x, +y, +z edge, when the level crosses it.
    let mut edge_vertex = vec![u32::MAX; grid.node_count() * 3];
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let v0 = value(i, j, k);
                for axis in 0..3 {
                    let mut o = [i, j, k];
                    o[axis] += 1;
                    if o[axis] >= n[axis] {
                        continue;
                    }
                    let v1 = value(o[0], o[1], o[2]);
                    if (v0 > iso) == (v1 > iso) {
                        continue;
                    }
                    let t = (iso - v0) / (v1 - v0);
                    let (p0, p1) = (grid.position(i, j, k), grid.position(o[0], o[1], o[2]));
                    let (g0, g1) = (gradient(i, j, k), gradient(o[0], o[1], o[2]));
                    let g = [0, 1, 2].map(|a| g0[a] + t * (g1[a] - g0[a]));
                    let len = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt().max(1e-20);
                    edge_vertex[grid.index(i, j, k) * 3 + axis] = mesh.positions.len() as u32;
                    mesh.positions.push([0, 1, 2].map(|a| p0[a] + t * (p1[a] - p0[a])));
                    mesh.normals.push(g.map(|c| -c / len));
                }
            }
        }
    }
    for k in 0..n[2] - 1 {
        for j in 0..n[1] - 1 {
            for i in 0..n[0] - 1 {
                let mut case = 0;
                for c in 0..8 {
                    let d = corner_offset(c);
                    if value(i + d[0], j + d[1], k + d[2]) > iso {
                        case |= 1 << c;
                    }
                }
                for tri in &table.triangles[case] {
                    for &e in tri {
                        let (lower, axis) = cube_edge(e as usize);
                        let d = corner_offset(lower);
                        let node = grid.index(i + d[0], j + d[1], k + d[2]);
                        mesh.indices.push(edge_vertex[node * 3 + axis]);
                    }
                }
            }
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;
    use std::collections::HashMap;

    #[test]
    fn the_table_covers_the_fifteen_classes_with_at_most_five_triangles() {
        let t = case_table();
        assert!(t.triangles[0].is_empty() && t.triangles[255].is_empty());
        let most = t.triangles.iter().map(Vec::len).max().unwrap();
        assert_eq!(most, MAX_CASE_TRIANGLES);
        // One corner in: one triangle over its three edges; a face's pair:
        // a quad, two triangles; four corners of a face: a quad.
        assert_eq!(t.triangles[1].len(), 1);
        assert_eq!(t.triangles[0b11].len(), 2);
        assert_eq!(t.triangles[0b1111].len(), 2);
        // The cube's symmetries (rotations, mirrors, in/out swapped) make
        // the 256 cases 15 classes (Lorensen & Cline's).
        let rotations = symmetries();
        let mut classes = std::collections::HashSet::new();
        for case in 0..256usize {
            let mut best = usize::MAX;
            for perm in &rotations {
                let mapped = (0..8).filter(|&c| case >> c & 1 == 1).map(|c| 1 << perm[c]).sum();
                best = best.min(mapped).min(255 - mapped);
            }
            classes.insert(best);
        }
        assert_eq!(classes.len(), 15);
    }

    /// The 24 rotations of the cube as corner permutations.
    fn symmetries() -> Vec<[usize; 8]> {
        let rot_x = |c: usize| {
            let [x, y, z] = corner_offset(c);
            x | (1 - z) << 1 | y << 2
        };
        let rot_y = |c: usize| {
            let [x, y, z] = corner_offset(c);
            z | y << 1 | (1 - x) << 2
        };
        let mut found: Vec<[usize; 8]> = vec![std::array::from_fn(|c| c)];
        let mut i = 0;
        while i < found.len() {
            let p = found[i];
            for r in [&rot_x as &dyn Fn(usize) -> usize, &rot_y] {
                let q: [usize; 8] = std::array::from_fn(|c| r(p[c]));
                if !found.contains(&q) {
                    found.push(q);
                }
            }
            i += 1;
        }
        assert_eq!(found.len(), 24);
        found
    }

    /// Every directed edge once, and its reverse once: closed and wound
    /// consistently.
    fn assert_closed(mesh: &SurfaceMesh) {
        let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
        for t in mesh.indices.chunks_exact(3) {
            for v in 0..3 {
                *edges.entry((t[v], t[(v + 1) % 3])).or_default() += 1;
            }
        }
        for (&(a, b), &count) in &edges {
            assert_eq!(count, 1, "edge {a}→{b} used {count} times");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}→{b} has no twin");
        }
    }

    fn sphere_field(grid: &SurfaceGrid, centre: [f32; 3], radius: f32) -> Vec<f32> {
        let mut v = vec![0.0; grid.node_count()];
        for k in 0..grid.nodes[2] as usize {
            for j in 0..grid.nodes[1] as usize {
                for i in 0..grid.nodes[0] as usize {
                    let p = grid.position(i, j, k);
                    let r = (0..3).map(|a| (p[a] - centre[a]).powi(2)).sum::<f32>().sqrt();
                    v[grid.index(i, j, k)] = ISO_LEVEL + (radius - r);
                }
            }
        }
        v
    }

    #[test]
    fn a_sphere_converges_in_area_and_volume_at_second_order() {
        let radius = 1.0f32;
        let (area, volume) = (4.0 * std::f64::consts::PI, 4.0 / 3.0 * std::f64::consts::PI);
        // Mean errors over a few centres, so that no lucky alignment hides
        // or fakes the order.
        let errors = |cells: u32| {
            let (mut ea, mut ev) = (0.0, 0.0);
            for s in 0..4 {
                let c = [0.013 * s as f32, 0.029 * s as f32, 0.007 * s as f32];
                let grid = SurfaceGrid::over([-1.3; 3], [1.3; 3], cells);
                let mesh = marching_cubes(&grid, &sphere_field(&grid, c, radius), ISO_LEVEL);
                assert_closed(&mesh);
                ea += (mesh.area() - area).abs() / 4.0;
                ev += (mesh.volume() - volume).abs() / 4.0;
            }
            (ea, ev)
        };
        let (a1, v1) = errors(12);
        let (a2, v2) = errors(24);
        let (a3, v3) = errors(48);
        // Halving the cell quarters the error (order 2: ratio 4; allowed
        // from 3).
        for (coarse, fine) in [(a1, a2), (a2, a3), (v1, v2), (v2, v3)] {
            assert!(coarse / fine > 3.0, "errors {a1} {a2} {a3} / {v1} {v2} {v3}");
        }
        assert!(a3 / area < 0.01 && v3 / volume < 0.01, "{a3} {v3}");
        // The normals point out, along the radius.
        let grid = SurfaceGrid::over([-1.3; 3], [1.3; 3], 24);
        let mesh = marching_cubes(&grid, &sphere_field(&grid, [0.0; 3], radius), ISO_LEVEL);
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            let cos = (p[0] * n[0] + p[1] * n[1] + p[2] * n[2]) / r;
            assert!(cos > 0.99, "{p:?} {n:?}");
        }
    }

    #[test]
    fn every_mesh_of_a_random_field_is_closed_and_wound_outwards() {
        let mut rng = SplitMix64::new(30);
        for trial in 0..20 {
            let grid = SurfaceGrid { origin: [0.0; 3], h: 0.1, nodes: [9, 8, 10] };
            let mut values = vec![0.0f32; grid.node_count()];
            for k in 1..9 {
                for j in 1..7 {
                    for i in 1..8 {
                        values[grid.index(i, j, k)] = rng.unit() as f32;
                    }
                }
            }
            let mesh = marching_cubes(&grid, &values, ISO_LEVEL);
            assert!(!mesh.indices.is_empty(), "trial {trial}");
            assert_closed(&mesh);
            // Wound outwards: the volume enclosed is positive, and about
            // the nodes inside (each a cell's worth, give or take the
            // interpolation).
            let inside = values.iter().filter(|&&v| v > ISO_LEVEL).count() as f64 * 1e-3;
            let v = mesh.volume();
            assert!(v > 0.3 * inside && v < 1.7 * inside, "trial {trial}: {v} vs {inside}");
        }
    }

    /// The heights of the vertices on the top face of the test blocks
    /// (20 × 12 × 16 cm), away from its edges.
    fn top_heights(mesh: &SurfaceMesh) -> Vec<f32> {
        mesh.positions
            .iter()
            .filter(|p| p[0] > 0.05 && p[0] < 0.15 && p[2] > 0.05 && p[2] < 0.11 && p[1] > 0.1)
            .map(|p| p[1])
            .collect()
    }

    #[test]
    fn smoothing_takes_out_the_jitter_and_keeps_the_volume() {
        // A jittered block of particles 1 cm apart: smoothed, its top is
        // flatter and its volume about the same, for either field.
        let s = 0.01f32;
        let mut rng = SplitMix64::new(3);
        let mut particles = Vec::new();
        for k in 0..16 {
            for j in 0..12 {
                for i in 0..20 {
                    let mut jitter = || 0.3 * s * (rng.unit() as f32 - 0.5);
                    let p = [i, j, k].map(|c| (c as f32 + 0.5) * s);
                    particles.push([p[0] + jitter(), p[1] + jitter(), p[2] + jitter()]);
                }
            }
        }
        // Surface cells a spacing wide, as the scenes mesh.
        let grid = SurfaceGrid::over([0.0; 3], [0.2, 0.12, 0.16], 20);
        let fixed = splat(&grid, &particles, s);
        let top_spread = |values: &[f32]| {
            let mesh = marching_cubes(&grid, values, ISO_LEVEL);
            assert_closed(&mesh);
            let top = top_heights(&mesh);
            assert!(top.len() > 20);
            let mean = top.iter().sum::<f32>() / top.len() as f32;
            let spread = (top.iter().map(|y| (y - mean) * (y - mean)).sum::<f32>()
                / top.len() as f32)
                .sqrt();
            (spread, mesh.volume())
        };
        for field in [SurfaceField::Density, SurfaceField::MeanPosition] {
            let values = level(&grid, &fixed, s, field, &Walls::default());
            let (rough, v0) = top_spread(&values);
            let mut smoothed = values.clone();
            smooth(&grid, &mut smoothed, 2);
            let (smooth_spread, v1) = top_spread(&smoothed);
            eprintln!("{field:?}: roughness {rough} → {smooth_spread} m, volume {v0} → {v1} m³");
            // The top's roughness (rms) halves.
            assert!(smooth_spread < 0.5 * rough, "{field:?}: {smooth_spread} vs {rough}");
            // Its edges and corners round a little more: a block 12
            // spacings high keeps its volume to 5% by the density (measured
            // −4.2%), to 10% by the mean position (measured −7.9%: its
            // level saturates within r of a face, so the filter rounds
            // the block's twelve edges further in).
            let allowed = if field == SurfaceField::Density { 0.05 } else { 0.1 };
            assert!((v1 / v0 - 1.0).abs() < allowed, "{field:?}: {v1} vs {v0}");
        }
        // A linear ramp is left as it is (away from the edges).
        let nx = grid.nodes[0] as usize;
        let mut ramp: Vec<f32> =
            (0..grid.node_count()).map(|n| 0.1 + 0.01 * (n % nx) as f32).collect();
        let before = ramp.clone();
        smooth(&grid, &mut ramp, 1);
        let at = grid.index(3, 5, 5);
        assert!((ramp[at] - before[at]).abs() < 1e-6);
    }

    #[test]
    fn a_block_of_particles_is_meshed_where_its_volume_ends() {
        // Particles 1 cm apart filling 20 × 12 × 16 cm (their cells' union).
        let s = 0.01f32;
        let mut particles = Vec::new();
        for k in 0..16 {
            for j in 0..12 {
                for i in 0..20 {
                    particles.push([i, j, k].map(|c| (c as f32 + 0.5) * s));
                }
            }
        }
        let grid = SurfaceGrid::over([0.0; 3], [0.2, 0.12, 0.16], 40);
        let fixed = splat(&grid, &particles, s);
        let rho = density(&fixed);
        // Deep inside, the density is 1.
        let centre = rho[grid.index(20, 13, 17)];
        assert!((centre - 1.0).abs() < 0.02, "{centre}");
        for field in [SurfaceField::Density, SurfaceField::MeanPosition] {
            let mesh = marching_cubes(
                &grid,
                &level(&grid, &fixed, s, field, &Walls::default()),
                ISO_LEVEL,
            );
            assert_closed(&mesh);
            let volume = 0.2 * 0.12 * 0.16;
            // The kernel rounds the edges and corners a little.
            let v = mesh.volume();
            assert!((v / volume - 1.0).abs() < 0.05, "{field:?}: {v} vs {volume}");
            // The top face is within a tenth of a spacing of y = 12 cm.
            let top = top_heights(&mesh);
            assert!(!top.is_empty());
            for y in top {
                assert!((y - 0.12).abs() < 0.1 * s, "{field:?}: {y}");
            }
        }
    }

    #[test]
    fn a_liquid_is_carried_flat_through_its_closed_walls() {
        // A block 20 × 6 × 16 cm filling the floor of a closed 20 × 12 ×
        // 16 cm domain, its particles jittered and a fifth of them taken
        // out (the voids a FLIP liquid leaves along its walls), open only
        // at the top. Carried through the walls, its sides and bottom are
        // flat planes past the walls (every vertex beyond a wall within
        // 0.15 cells of one plane), between the last two nodes; its top
        // still ends at 6 cm (a tenth of a spacing), right up to the walls;
        // the mesh is closed. Without walls the sides end at the box.
        let s = 0.01f32;
        let mut rng = SplitMix64::new(5);
        let mut particles = Vec::new();
        for k in 0..16 {
            for j in 0..6 {
                for i in 0..20 {
                    let mut jitter = || 0.2 * s * (rng.unit() as f32 - 0.5);
                    let p = [i, j, k].map(|c| (c as f32 + 0.5) * s);
                    let q = [p[0] + jitter(), p[1] + jitter(), p[2] + jitter()];
                    if rng.unit() > 0.2 || j == 5 {
                        particles.push(q);
                    }
                }
            }
        }
        let (min, max) = ([0.0; 3], [0.2, 0.12, 0.16]);
        let grid = SurfaceGrid::over(min, max, 40);
        let fixed = splat(&grid, &particles, s);
        let field = SurfaceField::MeanPosition;
        let open_top = [[false; 2], [false, true], [false; 2]];
        let walls = Walls::of(&grid, [min, max], open_top, s);
        let mesh = marching_cubes(&grid, &level(&grid, &fixed, s, field, &walls), ISO_LEVEL);
        assert_closed(&mesh);
        let h = grid.h;
        // Past the −x wall: one plane, between the nodes at −2h and −h.
        // (Away from its rim, where it turns into the top and the other
        // walls' faces.)
        let away = |p: &&[f32; 3], a: usize| p[a] > 0.01 && p[a] < [0.19, 0.05, 0.15][a];
        let past: Vec<f32> = (mesh.positions.iter())
            .filter(|p| p[0] < -0.1 * h && away(p, 1) && away(p, 2))
            .map(|p| p[0])
            .collect();
        assert!(past.len() > 50, "{} vertices past the wall", past.len());
        let (lo, hi) = past.iter().fold((f32::MAX, f32::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        assert!(hi - lo < 0.15 * h && lo > -2.0 * h && hi < -h, "{lo}..{hi} (h = {h})");
        // Under the floor: the same.
        let under: Vec<f32> = (mesh.positions.iter())
            .filter(|p| p[1] < -0.1 * h && away(p, 0) && away(p, 2))
            .map(|p| p[1])
            .collect();
        let (lo, hi) = under.iter().fold((f32::MAX, f32::MIN), |(a, b), &y| (a.min(y), b.max(y)));
        assert!(hi - lo < 0.15 * h && lo > -2.0 * h && hi < -h, "{lo}..{hi} (h = {h})");
        // The top at 6 cm, near the walls as well as away from them.
        let top: Vec<f32> = mesh
            .positions
            .iter()
            .filter(|p| p[1] > 0.045 && p[0] > -0.1 * h && p[0] < 0.2 && p[2] > 0.02 && p[2] < 0.14)
            .map(|p| p[1])
            .collect();
        assert!(top.len() > 100);
        let worst = top.iter().fold(0.0f32, |m, y| m.max((y - 0.06).abs()));
        assert!(worst < 0.25 * s, "the top strays {worst} m from 6 cm");
        // No walls: the sides end where the particles' volume does (within
        // a fifth of a spacing of the box, their jitter), not past it.
        let free =
            marching_cubes(&grid, &level(&grid, &fixed, s, field, &Walls::default()), ISO_LEVEL);
        let x_min = free.positions.iter().fold(f32::MAX, |m, p| m.min(p[0]));
        assert!(x_min > -0.2 * s, "{x_min}");
    }

    #[test]
    fn the_mean_position_field_is_flat_where_the_particles_clump() {
        // A settled FLIP liquid's particles, as the pour scene's are at 5 s
        // (its dump: 12.5-mm columns hold 24 to 88 particles where 40 fill
        // them, yet nine in ten end within 0.3 mm of the same height, pressed
        // against the air cells above): a block whose lattice sites hold 0
        // to 3 particles (a quarter each) jittered by a tenth of a spacing,
        // its top layer one or more. The density's top is bumped by the
        // count; the mean position's much less (under half the roughness:
        // measured 1.2 mm against 0.34 mm).
        let s = 0.01f32;
        let mut rng = SplitMix64::new(11);
        let mut particles = Vec::new();
        for k in 0..16 {
            for j in 0..12 {
                for i in 0..20 {
                    let copies = ((rng.unit() * 4.0) as usize).max(usize::from(j == 11));
                    for _ in 0..copies {
                        let mut jitter = || 0.1 * s * (rng.unit() as f32 - 0.5);
                        let p = [i, j, k].map(|c| (c as f32 + 0.5) * s);
                        particles.push([p[0] + jitter(), p[1] + jitter(), p[2] + jitter()]);
                    }
                }
            }
        }
        // A margin round the block: where three particles share a site the
        // density reaches past the usual one.
        let grid = SurfaceGrid::over([-0.03; 3], [0.23, 0.15, 0.19], 52);
        let fixed = splat(&grid, &particles, s);
        let roughness = |field| {
            let mesh = marching_cubes(
                &grid,
                &level(&grid, &fixed, s, field, &Walls::default()),
                ISO_LEVEL,
            );
            assert_closed(&mesh);
            let top = top_heights(&mesh);
            assert!(top.len() > 20);
            let mean = top.iter().sum::<f32>() / top.len() as f32;
            let rms = (top.iter().map(|y| (y - mean) * (y - mean)).sum::<f32>() / top.len() as f32)
                .sqrt();
            (rms, mean)
        };
        let (bumpy, _) = roughness(SurfaceField::Density);
        let (flat, top) = roughness(SurfaceField::MeanPosition);
        eprintln!("top roughness: density {bumpy} m, mean position {flat} m (at {top} m)");
        assert!(flat < 0.5 * bumpy, "{flat} vs {bumpy} m");
        // Where the block's top lies: within a quarter spacing of 12 cm.
        assert!((top - 0.12).abs() < 0.25 * s, "{top}");
    }

    #[test]
    fn a_lone_particle_is_a_sphere_of_the_mean_position_radius() {
        // One particle: x̄ is the particle wherever its kernel reaches, so
        // the surface is the sphere of radius r = 0.55 s about it; meshed
        // with nodes a tenth of a spacing apart, within 3% of its volume
        // (marching cubes' chords cut inside a sphere).
        let s = 0.01f32;
        let grid = SurfaceGrid::over([0.0; 3], [0.04; 3], 40);
        let centre = [0.0203, 0.0197, 0.021];
        let fixed = splat(&grid, &[centre], s);
        let mesh = marching_cubes(
            &grid,
            &level(&grid, &fixed, s, SurfaceField::MeanPosition, &Walls::default()),
            ISO_LEVEL,
        );
        assert_closed(&mesh);
        let r = (PARTICLE_RADIUS_SPACINGS * s) as f64;
        let sphere = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
        assert!((mesh.volume() / sphere - 1.0).abs() < 0.03, "{} vs {sphere}", mesh.volume());
        // The density of one particle peaks at 0.196 (its weight): under
        // the level, so that field has no drop at all.
        let blob = marching_cubes(
            &grid,
            &level(&grid, &fixed, s, SurfaceField::Density, &Walls::default()),
            ISO_LEVEL,
        );
        assert!(blob.indices.is_empty());
    }
}

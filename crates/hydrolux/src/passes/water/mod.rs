//! The water surface: a camera-centred clipmap of square rings on a
//! world-fixed grid, displaced by the surface model and shaded with Fresnel,
//! sky reflection, sun glint, the water body and foam (see `water.wgsl`).

use crate::gpu_util::*;
use crate::shaders::{self, compose};
use wgpu::util::DeviceExt;

/// Grid cells from a ring's centre to its edge.
pub const RING_HALF: i32 = 32;
/// Vertex spacing of the finest ring, metres.
pub const BASE_SPACING: f32 = 0.25;
/// Rings that carry displacement: the outermost reaches 8·2⁸ = 2 km, where
/// waves of a few metres are below a pixel at 1080p.
pub const DISPLACED_RINGS: u32 = 9;
/// Cells from the far field's centre to its edge (hole inside half of it).
pub const FAR_HALF: i32 = 4;
/// The far field's outer edge is this many times the last ring's (≈100 km).
pub const FAR_SCALE: f32 = 50.0;

pub fn ring_count() -> u32 {
    DISPLACED_RINGS
}

pub fn source() -> String {
    let consts = format!(
        "const RING_HALF: f32 = {RING_HALF}.0;\nconst FAR_HALF: f32 = {FAR_HALF}.0;\nconst FAR_SCALE: f32 = {FAR_SCALE:?};\n\
         const DISPLACED_RINGS: u32 = {DISPLACED_RINGS}u;\nconst SKY_CUBE_SIZE: f32 = {}.0;\n",
        super::sky::CUBE_SIZE
    );
    compose(&[
        &consts,
        shaders::CONSTANTS,
        shaders::FRAME,
        shaders::OPTICS,
        shaders::SKY_MODEL,
        shaders::SKY_BINDINGS,
        shaders::SURFACE,
        include_str!("water.wgsl"),
    ])
}

/// A square grid of cells (vertices at integer cell corners in [−h, h]²),
/// with index ranges for several variants (hole positions).
struct GridMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    variants: Vec<std::ops::Range<u32>>,
}

impl GridMesh {
    fn new(device: &wgpu::Device, label: &str, h: i32, holes: &[Option<(i32, i32)>]) -> Self {
        let cells: Vec<[i32; 2]> = (-h..=h).flat_map(|z| (-h..=h).map(move |x| [x, z])).collect();
        let mut idx = Vec::new();
        let mut variants = Vec::new();
        for hole in holes {
            let start = idx.len() as u32;
            idx.extend(grid_indices(h, *hole));
            variants.push(start..idx.len() as u32);
        }
        let init = |contents: &[u8], usage| device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage });
        GridMesh {
            vertices: init(bytemuck::cast_slice(&cells), wgpu::BufferUsages::VERTEX),
            indices: init(bytemuck::cast_slice(&idx), wgpu::BufferUsages::INDEX),
            variants,
        }
    }

    fn draw(&self, pass: &mut wgpu::RenderPass<'_>, variant: usize, instances: std::ops::Range<u32>) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(self.variants[variant].clone(), 0, instances);
    }
}

/// Centre of ring `level` for a camera at `xz`, exactly as `vs_main` computes
/// it (f32, round half to even).
pub fn ring_centre(xz: [f32; 2], level: u32) -> [f32; 2] {
    let spacing = BASE_SPACING * 2f32.powi(level as i32);
    xz.map(|c| (c / (2.0 * spacing)).round_ties_even() * 2.0 * spacing)
}

/// Which hole variant ring `level` ≥ 1 needs: the finer ring inside it is
/// centred up to one cell off this ring's centre, per axis.
pub fn hole_variant(xz: [f32; 2], level: u32) -> usize {
    let (outer, inner) = (ring_centre(xz, level), ring_centre(xz, level - 1));
    let spacing = BASE_SPACING * 2f32.powi(level as i32);
    let d = |i: usize| (((inner[i] - outer[i]) / spacing).round() as i32).clamp(-1, 1);
    ((d(0) + 1) * 3 + (d(1) + 1)) as usize
}

/// Hole offsets in the order [`hole_variant`] indexes them.
fn hole_offsets() -> Vec<Option<(i32, i32)>> {
    (-1..=1).flat_map(|dx| (-1..=1).map(move |dz| Some((dx, dz)))).collect()
}

pub struct WaterPass {
    full: GridMesh,
    ring: GridMesh,
    far: GridMesh,
    depth_rings: wgpu::RenderPipeline,
    shade_rings: wgpu::RenderPipeline,
    depth_far: wgpu::RenderPipeline,
    shade_far: wgpu::RenderPipeline,
}

/// Index list of the quads of a (2h)×(2h) cell grid, skipping the (h)×(h)
/// square centred at `hole` (in cells) when there is one.
fn grid_indices(h: i32, hole: Option<(i32, i32)>) -> Vec<u32> {
    let side = (2 * h + 1) as u32;
    let id = |x: i32, z: i32| ((z + h) as u32) * side + (x + h) as u32;
    let mut out = Vec::new();
    for z in -h..h {
        for x in -h..h {
            if let Some((hx, hz)) = hole {
                let inside = x >= hx - h / 2 && x < hx + h / 2 && z >= hz - h / 2 && z < hz + h / 2;
                if inside {
                    continue;
                }
            }
            // Counter-clockwise seen from above (+y).
            out.extend_from_slice(&[id(x, z), id(x, z + 1), id(x + 1, z), id(x + 1, z), id(x, z + 1), id(x + 1, z + 1)]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_ring_hole_is_exactly_the_finer_ring() {
        // For many camera positions, the finer ring's extent equals the hole.
        for i in 0..2000 {
            let xz = [i as f32 * 0.173 - 150.0, i as f32 * -0.311 + 40.0];
            for level in 1..DISPLACED_RINGS {
                let s = BASE_SPACING * 2f32.powi(level as i32);
                let (outer, inner) = (ring_centre(xz, level), ring_centre(xz, level - 1));
                let v = hole_variant(xz, level);
                let (dx, dz) = (v as i32 / 3 - 1, v as i32 % 3 - 1);
                let hole_centre = [outer[0] + dx as f32 * s, outer[1] + dz as f32 * s];
                assert!((hole_centre[0] - inner[0]).abs() < 1e-3 && (hole_centre[1] - inner[1]).abs() < 1e-3, "{xz:?} level {level}");
                // The finer ring stays near the camera.
                assert!((inner[0] - xz[0]).abs() <= s / 2.0 + 1e-3);
            }
        }
    }
}

impl WaterPass {
    pub fn new(device: &wgpu::Device, globals: &wgpu::BindGroupLayout, surface: &wgpu::BindGroupLayout) -> Self {
        let module = shader(device, "water", &source());
        let layout = pipeline_layout(device, "water", &[globals, surface]);
        let pipeline = |label: &str, vs: &str, shade: bool| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(vs),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: 8,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &wgpu::vertex_attr_array![0 => Sint32x2],
                    })],
                },
                primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: crate::targets::DEPTH_FORMAT,
                    depth_write_enabled: Some(!shade),
                    depth_compare: Some(if shade { wgpu::CompareFunction::GreaterEqual } else { wgpu::CompareFunction::Greater }),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(if shade { "fs_main" } else { "fs_depth" }),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: crate::targets::HDR_FORMAT,
                        blend: None,
                        write_mask: if shade { wgpu::ColorWrites::ALL } else { wgpu::ColorWrites::empty() },
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        WaterPass {
            full: GridMesh::new(device, "water full grid", RING_HALF, &[None]),
            ring: GridMesh::new(device, "water ring", RING_HALF, &hole_offsets()),
            far: GridMesh::new(device, "water far field", FAR_HALF, &[Some((0, 0))]),
            depth_rings: pipeline("water depth", "vs_main", false),
            shade_rings: pipeline("water shade", "vs_main", true),
            depth_far: pipeline("water far depth", "vs_far", false),
            shade_far: pipeline("water far shade", "vs_far", true),
        }
    }

    /// Depth pre-pass, then shading of what survived (depth Equal).
    /// `camera_xz` picks each ring's hole so it meets the finer ring exactly.
    pub fn record(&self, pass: &mut wgpu::RenderPass<'_>, globals: &wgpu::BindGroup, surface: &wgpu::BindGroup, camera_xz: [f32; 2]) {
        pass.set_bind_group(0, globals, &[]);
        pass.set_bind_group(1, surface, &[]);
        for (rings, far) in [(&self.depth_rings, &self.depth_far), (&self.shade_rings, &self.shade_far)] {
            pass.set_pipeline(rings);
            self.full.draw(pass, 0, 0..1);
            for level in 1..DISPLACED_RINGS {
                self.ring.draw(pass, hole_variant(camera_xz, level), level..level + 1);
            }
            pass.set_pipeline(far);
            self.far.draw(pass, 0, 0..1);
        }
    }
}

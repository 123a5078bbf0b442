//! The interactive water's readbacks and dumps, declared here by their owner.

use super::dynamics::Dynamics;
use crate::info::{DumpData, DumpKind, DumpShape};
use crate::renderer::Renderer;
use crate::technique::DumpContext;
use hydrolux_core::scene::Scene;

fn no_water(scene: &Scene) -> Option<&'static str> {
    (!scene.has_interactive_water()).then_some(
        "the scene has no interactive water (set water.dynamic = true, with water.model other than \"none\")",
    )
}

fn no_bodies(scene: &Scene) -> Option<&'static str> {
    let moving = scene.objects.iter().any(|o| o.moving());
    (!moving).then_some(
        "the scene has no moving object (an object with dynamic = true, a velocity or a path)",
    )
}

/// `ripples`: the heights over the domain; `bodies`: the moving bodies (JSON).
pub(crate) const DUMPS: &[DumpKind] = &[
    DumpKind { name: "ripples", shape: DumpShape::Grid, missing: no_water },
    DumpKind { name: "bodies", shape: DumpShape::Json, missing: no_bodies },
];

/// The moving bodies as JSON (the `bodies` dump, of every simulation's
/// bodies: `Simulations::dump`): time, then per body its object, position,
/// orientation (quaternion x, y, z, w), velocities and submerged volume.
pub(crate) fn bodies_json(
    states: &[hydrolux_core::bodies::BodyState],
    scene: &Scene,
    time: f64,
) -> String {
    let bodies: Vec<serde_json::Value> = states
        .iter()
        .map(|b| {
            serde_json::json!({
                "object": b.object,
                "name": scene.objects[b.object].name,
                "position": b.pose.position.to_array(),
                "orientation": b.pose.rotation.to_array(),
                "velocity": b.velocity.to_array(),
                "angular_velocity": b.angular_velocity.to_array(),
                "submerged_volume": b.submerged,
            })
        })
        .collect();
    let doc = serde_json::json!({ "time": time, "bodies": bodies });
    serde_json::to_string_pretty(&doc).expect("JSON of numbers and strings") + "\n"
}

impl Dynamics {
    fn field(&self, device: &wgpu::Device, queue: &wgpu::Queue, time: f64) -> Option<RippleField> {
        let r = self.ripples.as_ref()?;
        let g = r.settings.grid;
        Some(RippleField {
            cells: g.cells as u32,
            cell_size: g.cell_size as f32,
            origin: [0, 1].map(|a| r.window.low_edge(&g, a) as f32),
            heights: r.read_heights(device, queue),
            time,
        })
    }

    pub(crate) fn dump(&self, name: &str, ctx: &DumpContext) -> Option<Result<DumpData, String>> {
        match name {
            "ripples" => Some(match self.field(ctx.device, ctx.queue, ctx.time) {
                None => Err("the scene has no interactive water (water.dynamic = false)".into()),
                Some(f) => {
                    let note = format!(
                        "{n}×{n} cells of {c} m, cell (0, 0) centred at x = {x}, z = {z} m",
                        n = f.cells,
                        c = f.cell_size,
                        x = f.origin[0] + 0.5 * f.cell_size,
                        z = f.origin[1] + 0.5 * f.cell_size
                    );
                    let n = f.cells as usize;
                    Ok(DumpData::Floats {
                        columns: n,
                        rows: n,
                        channels: 1,
                        data: f.heights,
                        note: Some(note),
                    })
                }
            }),
            _ => None,
        }
    }
}

impl Renderer {
    /// The interactive water after the last frame or simulation step:
    /// heights (m) over its domain, row = z, col = x, and where the domain
    /// lies; `None` without `water.dynamic`.
    pub fn read_ripples(&self) -> Option<RippleField> {
        let time = self.simulation_time();
        self.simulations.ripples.as_ref()?.field(self.device(), self.queue(), time)
    }
}

/// The interactive water's heights over its square domain.
#[derive(Clone, Debug, PartialEq)]
pub struct RippleField {
    /// Cells per side.
    pub cells: u32,
    /// Side of a cell (m).
    pub cell_size: f32,
    /// World [x, z] (m) of the domain's corner: cell (i, j) is centred at
    /// origin + (i + ½, j + ½)·cell_size.
    pub origin: [f32; 2],
    /// Height above the mean level (m), row = z, col = x.
    pub heights: Vec<f32>,
    /// Simulated time (s) of the state.
    pub time: f64,
}

impl RippleField {
    /// Volume above the mean level (m³).
    pub fn volume(&self) -> f64 {
        self.heights.iter().map(|&h| h as f64).sum::<f64>() * (self.cell_size as f64).powi(2)
    }
}

//! What the simulations publish: named resources that other simulations
//! and the techniques read, remade by the layer after each batch of steps
//! (cheap: handles and a few numbers). A technique never reaches into a
//! simulation; it reads this.

/// Where the foam's window lies: the world point of its low corner (m),
/// its side (m), and whether it tiles the plane (open water).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoamWindow {
    pub origin: [f32; 2],
    pub side: f32,
    pub tiles: bool,
}

/// The water surface as every pass that reads it binds it.
#[derive(Clone)]
pub(crate) struct SurfaceState {
    /// Group 1 of the passes that read the surface (`Layouts::surface`):
    /// the model's textures and uniforms, the interactive water's heights
    /// and the foam's cover.
    pub group: wgpu::BindGroup,
    /// The same with no foam (the white water's own step writes the foam).
    pub group_without_foam: wgpu::BindGroup,
    /// Conservative reach (m) of the displacement, vertically and
    /// sideways, for culling; how far the surface rises in practice.
    pub bounds_margin: f32,
    pub vertical_reach: f32,
    /// It changes from frame to frame by itself.
    pub moving: bool,
    /// Slope variance per axis that the model does not resolve.
    pub unresolved_variance: [f32; 2],
    /// Its FFT's samples per side.
    pub ocean_resolution: u32,
}

/// The interactive water's heights and where they lie.
#[derive(Clone)]
pub(crate) struct RippleState {
    /// h, ∂h/∂x, ∂h/∂z per cell.
    pub heights: wgpu::TextureView,
    /// Where landing spray kicks the water (written by the white water).
    pub kicks: wgpu::Buffer,
    /// World (x, z) of the texture's origin (it tiles from there in open
    /// water), its side and cell (m), and the window it holds now
    /// (x0, z0, x1, z1).
    pub origin: [f32; 2],
    pub side: f32,
    pub cell: f32,
    pub window: [f32; 4],
}

/// The foam's cover over its window.
#[derive(Clone)]
pub(crate) struct FoamState {
    /// Cover per cell (mipmapped).
    pub cover: wgpu::TextureView,
    pub window: FoamWindow,
    /// The wind's direction and how streaky the foam is.
    pub wind: [f32; 2],
    pub streak: f32,
}

/// The alive bubbles and spray, for an indirect draw.
#[derive(Clone)]
pub(crate) struct ParticleState {
    pub particles: wgpu::Buffer,
    pub slots: wgpu::Buffer,
    /// Indirect draw arguments.
    pub args: wgpu::Buffer,
    /// Which alive list holds them now.
    pub list: u32,
    pub capacity: u32,
}

/// The volumetric liquid's particles (`LiquidParticle`s), for a draw.
#[derive(Clone)]
pub(crate) struct LiquidState {
    pub particles: wgpu::Buffer,
    pub count: u32,
    /// A particle's radius (m) as a sphere of its share of a cell.
    pub radius: f32,
    /// Where it lands in the interactive water: the buffer whose log the
    /// water takes (liquid/landing.wgsl; `None`: it lands in none).
    pub landings: Option<wgpu::Buffer>,
    /// Its surface as a mesh (`fluid.surface = "marching_cubes"`).
    pub mesh: Option<LiquidMesh>,
    /// While the error view compares surfaces: the liquid meshed by
    /// marching cubes on the finest grid, the reference drawing's
    /// (`FramePlan::liquid_reference`).
    pub reference_mesh: Option<LiquidMesh>,
    /// Its white water (`fluid.white_water`), drawn by `liquid_white_water`.
    pub white_water: Option<LiquidWhiteWater>,
}

/// The liquid's white water: a pool of `fluid::white_water::Diffuse`
/// records, the dead ones among them.
#[derive(Clone)]
pub(crate) struct LiquidWhiteWater {
    pub particles: wgpu::Buffer,
    pub slots: u32,
    /// How wide a particle is drawn (m).
    pub size: f32,
}

impl LiquidState {
    /// The mesh a drawing shows: the reference in the error view's
    /// reference drawing, the liquid's own otherwise.
    pub fn mesh_for(&self, plan: &crate::plan::FramePlan) -> Option<&LiquidMesh> {
        // (No reference of its own: the liquid's mesh already is one.)
        if plan.liquid_reference {
            self.reference_mesh.as_ref().or(self.mesh.as_ref())
        } else {
            self.mesh.as_ref()
        }
    }
}

/// The liquid's surface mesh, made on the GPU (liquid/surface.rs): drawn
/// indexed and indirect, with the meshes' vertex layout.
#[derive(Clone)]
pub(crate) struct LiquidMesh {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    /// The indexed indirect draw's arguments at offset 0.
    pub args: wgpu::Buffer,
    /// Its object bind group (identity, the water's index of refraction).
    pub group: wgpu::BindGroup,
}

#[derive(Clone, Default)]
pub(crate) struct Published {
    pub surface: Option<SurfaceState>,
    pub ripples: Option<RippleState>,
    pub foam: Option<FoamState>,
    pub particles: Option<ParticleState>,
    pub liquid: Option<LiquidState>,
    /// Each moving object's index and world transform now.
    pub bodies: Vec<(usize, glam::Mat4)>,
}

impl Published {
    /// The surface (every scene has one).
    pub fn surface(&self) -> &SurfaceState {
        self.surface.as_ref().expect("the surface simulation is always built")
    }
}

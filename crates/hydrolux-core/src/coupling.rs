//! What one simulation hands another, owned by neither (seed 003 §2.4,
//! two-way coupling): the hulls the bodies press into the interactive water
//! (their shapes, poses and vertical extent over a column), the drops that
//! disturb it, and the fixed-point kicks the white water's landing spray
//! gives it. The bodies (`bodies`), the interactive water (`waves::ripples`)
//! and the white water (`whitewater`) each import this leaf, never each
//! other. GPU twins: `body_column`, `held_depth`, `body_depth` and
//! `drop_height` in `simulation/ripples/ripples.wgsl`.

use glam::{DQuat, DVec3};

/// A body's shape in its own frame (centred on its origin).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    Sphere {
        radius: f64,
    },
    Box {
        half: DVec3,
    },
    /// Axis along the body's y.
    Cylinder {
        radius: f64,
        half_height: f64,
    },
}

impl Shape {
    pub fn volume(&self) -> f64 {
        use std::f64::consts::PI;
        match *self {
            Shape::Sphere { radius } => 4.0 / 3.0 * PI * radius.powi(3),
            Shape::Box { half } => 8.0 * half.x * half.y * half.z,
            Shape::Cylinder { radius, half_height } => PI * radius * radius * 2.0 * half_height,
        }
    }

    /// Half-sides [x, z] of the shape's footprint box at `pose` (the box
    /// around it, turned; a cylinder as its box).
    pub fn horizontal_half_extent(&self, pose: &Pose) -> [f64; 2] {
        let local = match *self {
            Shape::Sphere { radius } => return [radius, radius],
            Shape::Box { half } => half,
            Shape::Cylinder { radius, half_height } => DVec3::new(radius, half_height, radius),
        };
        let m = glam::DMat3::from_quat(pose.rotation);
        let reach = |row: usize| (0..3).map(|c| (m.col(c)[row] * local[c]).abs()).sum::<f64>();
        [reach(0), reach(2)]
    }

    /// Moment of inertia per unit mass (m²) about a horizontal axis through
    /// the centre, upright (the mean of the two for a box).
    pub fn tilt_inertia_per_mass(&self) -> f64 {
        match *self {
            Shape::Sphere { radius } => 0.4 * radius * radius,
            Shape::Box { half } => {
                let (x, y, z) = (2.0 * half.x, 2.0 * half.y, 2.0 * half.z);
                0.5 * ((y * y + z * z) + (x * x + y * y)) / 12.0
            }
            Shape::Cylinder { radius, half_height } => {
                (3.0 * radius * radius + 4.0 * half_height * half_height) / 12.0
            }
        }
    }

    /// Radius of a sphere around the shape.
    pub fn bounding_radius(&self) -> f64 {
        match *self {
            Shape::Sphere { radius } => radius,
            Shape::Box { half } => half.length(),
            Shape::Cylinder { radius, half_height } => radius.hypot(half_height),
        }
    }

    /// Signed distance (m) from the shape's surface to `p` in its own
    /// frame: negative inside (exact for the sphere and the box's and
    /// cylinder's outsides, the usual bound inside them).
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        match *self {
            Shape::Sphere { radius } => p.length() - radius,
            Shape::Box { half } => {
                let q = p.abs() - half;
                q.max(DVec3::ZERO).length() + q.max_element().min(0.0)
            }
            Shape::Cylinder { radius, half_height } => {
                let q = glam::DVec2::new(p.x.hypot(p.z) - radius, p.y.abs() - half_height);
                q.max(glam::DVec2::ZERO).length() + q.max_element().min(0.0)
            }
        }
    }

    /// The outward normal at `p` (own frame): the distance's gradient by
    /// central differences, a step of a thousandth of the shape's size.
    pub fn outward_normal(&self, p: DVec3) -> DVec3 {
        let e = 1e-3 * self.bounding_radius();
        let d = |o: DVec3| self.signed_distance(p + o) - self.signed_distance(p - o);
        DVec3::new(d(DVec3::X * e), d(DVec3::Y * e), d(DVec3::Z * e)).normalize_or_zero()
    }

    /// The code of the shape in the shaders (`PRIMITIVE_*`, generated into
    /// the renderer's WGSL from these constants) and its three size
    /// parameters.
    pub fn gpu(&self) -> (u32, [f32; 3]) {
        match *self {
            Shape::Sphere { radius } => (PRIMITIVE_SPHERE, [radius as f32, 0.0, 0.0]),
            Shape::Box { half } => (PRIMITIVE_BOX, half.as_vec3().to_array()),
            Shape::Cylinder { radius, half_height } => {
                (PRIMITIVE_CYLINDER, [radius as f32, half_height as f32, 0.0])
            }
        }
    }
}

/// Shape codes on the GPU (the renderer's ray tests and hulls): a sphere
/// (radius), a box (half-sizes), a cylinder along y (radius, half-height),
/// and for traced objects a unit plane at y = 0 and a mesh (its tree,
/// `raytrace::bvh`).
pub const PRIMITIVE_SPHERE: u32 = 0;
pub const PRIMITIVE_BOX: u32 = 1;
pub const PRIMITIVE_CYLINDER: u32 = 2;
pub const PRIMITIVE_PLANE: u32 = 3;
pub const PRIMITIVE_MESH: u32 = 4;

/// Where a body is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub position: DVec3,
    pub rotation: DQuat,
}

impl Pose {
    pub fn matrix(&self, scale: [f32; 3]) -> glam::Mat4 {
        glam::Mat4::from_scale_rotation_translation(
            scale.into(),
            self.rotation.as_quat(),
            self.position.as_vec3(),
        )
    }
}

/// The vertical extent [y0, y1] of `shape` at `pose` over the column at
/// world (x, z), or `None` if the column misses it.
pub fn body_column(shape: &Shape, pose: &Pose, x: f64, z: f64) -> Option<(f64, f64)> {
    // A downward ray from just above the body, in the body's frame.
    let top = pose.position.y + shape.bounding_radius() + 1.0;
    let inv = pose.rotation.inverse();
    let o = inv * (DVec3::new(x, top, z) - pose.position);
    let d = inv * DVec3::NEG_Y;
    let (t0, t1) = match *shape {
        Shape::Sphere { radius } => {
            let b = o.dot(d);
            let c = o.length_squared() - radius * radius;
            let disc = b * b - c;
            if disc < 0.0 {
                return None;
            }
            let s = disc.sqrt();
            (-b - s, -b + s)
        }
        Shape::Box { half } => slab(o, d, -half, half)?,
        Shape::Cylinder { radius, half_height } => {
            let (a, b, c) = (
                d.x * d.x + d.z * d.z,
                o.x * d.x + o.z * d.z,
                o.x * o.x + o.z * o.z - radius * radius,
            );
            let (mut t0, mut t1) = if a < 1e-12 {
                if c > 0.0 {
                    return None;
                }
                (f64::NEG_INFINITY, f64::INFINITY)
            } else {
                let disc = b * b - a * c;
                if disc < 0.0 {
                    return None;
                }
                let s = disc.sqrt();
                ((-b - s) / a, (-b + s) / a)
            };
            if d.y.abs() < 1e-12 {
                if o.y.abs() > half_height {
                    return None;
                }
            } else {
                let (ya, yb) = ((-half_height - o.y) / d.y, (half_height - o.y) / d.y);
                t0 = t0.max(ya.min(yb));
                t1 = t1.min(ya.max(yb));
            }
            if t0 > t1 {
                return None;
            }
            (t0, t1)
        }
    };
    Some((top - t1, top - t0))
}

fn slab(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    for a in 0..3 {
        if d[a].abs() < 1e-12 {
            if o[a] < lo[a] || o[a] > hi[a] {
                return None;
            }
        } else {
            let (ta, tb) = ((lo[a] - o[a]) / d[a], (hi[a] - o[a]) / d[a]);
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

/// A disturbance of the surface: a crater of depth `strength` (m) and
/// radius `radius` (m) with its rim, volume-neutral (a 2-D Ricker wavelet,
/// Δh = −s·(1 − r²/R²)·e^(−r²/R²), whose integral over the plane is zero).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drop {
    pub x: f64,
    pub z: f64,
    pub radius: f64,
    pub strength: f64,
}

impl Drop {
    /// Δh at horizontal distance² `r2` from the centre. Twin of `drop_height` in WGSL.
    pub fn height(&self, r2: f64) -> f64 {
        let u = r2 / (self.radius * self.radius);
        if u > 16.0 { 0.0 } else { -self.strength * (1.0 - u) * (-u).exp() }
    }
}

/// A body in the water during one step, pressing on it: the classic
/// moving pressure patch of ship-wave theory (Havelock; Tessendorf's iWave
/// sources). Where the body reaches a depth d below the mean level it holds
/// the surface down with the pressure ρ·g·d: a floating body rests in its
/// own hollow, the water it pushes away rises around it, a bobbing buoy
/// radiates rings and a moving hull leaves a bow wave and a Kelvin wake.
/// The volume of water never changes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyMove {
    pub shape: Shape,
    pub before: Pose,
    pub after: Pose,
    /// Where the body was put away from this step (the viewer's drop: it
    /// was lifted out, not moved through the water): the hollow it held
    /// there closes, as if it had never been there, instead of rebounding
    /// as a spout as high as the hollow was deep.
    pub released: Option<Pose>,
}

impl BodyMove {
    /// The pose whose hollow the body held the water down in before this
    /// step: where it was, or where it was lifted out of.
    pub fn held(&self) -> Pose {
        self.released.unwrap_or(self.before)
    }

    /// Depth (m) the body reached below the mean level at world (x, z)
    /// before the step (at [`BodyMove::held`]), where it pierced the
    /// surface. Twin of `held_depth` in WGSL.
    pub fn depth_before(&self, x: f64, z: f64) -> f64 {
        pressure_head(&self.shape, &self.held(), x, z)
    }

    /// Depth (m) the body reaches below the mean level at world (x, z),
    /// after the move, where it pierces the surface: its pressure head. A
    /// column of the body wholly under water holds nothing down (the water
    /// closes over it). Twin of `body_depth` in WGSL.
    pub fn depth(&self, x: f64, z: f64) -> f64 {
        pressure_head(&self.shape, &self.after, x, z)
    }
}

/// Depth (m) a body of `shape` at `pose` reaches below the mean level at
/// world (x, z) where it pierces the surface (0 elsewhere).
fn pressure_head(shape: &Shape, pose: &Pose, x: f64, z: f64) -> f64 {
    body_column(shape, pose, x, z)
        .map_or(0.0, |(y0, y1)| if y1 > 0.0 { (-y0).max(0.0) } else { 0.0 })
}

/// The water a spray particle carries by default (`whitewater.spray_water`):
/// a parcel drawn `spray_size` wide is a cloud of drops, about 1% water by
/// volume (dense spray near a splash's crown or a breaking crest; spume
/// blown off a crest is thinner).
pub const SPRAY_LIQUID_FRACTION: f64 = 0.01;

/// Water (m³) in one spray parcel drawn `spray_size` m wide, `water` of it
/// by volume.
pub fn spray_parcel_volume(spray_size: f32, water: f32) -> f64 {
    std::f64::consts::PI / 6.0 * (spray_size as f64).powi(3) * water as f64
}

/// Fixed point of the landing spray's kicks: units per m/s of downward
/// speed, summed per cell of the interactive water (u32 atomics on the
/// GPU: a thousand parcels at 60 m/s fit in one cell's step).
pub const KICK_SCALE: f32 = 65536.0;

/// The kick units of a parcel landing at `speed` m/s downwards (clamped to
/// 0..60 m/s, beyond any drop's terminal velocity).
pub fn kick_units(speed: f32) -> u32 {
    let s = if speed.is_finite() { speed.clamp(0.0, 60.0) } else { 0.0 };
    (s * KICK_SCALE).round() as u32
}

/// Δφ (m²/s) one kick unit gives a cell `cell` m wide: a parcel of volume V
/// landing at speed v hands the water its momentum ρ·V·v, an impulsive
/// pressure P = ρ·V·v / A over the cell (the drops are far smaller than
/// it), and the linearised Bernoulli equation ∂φ/∂t = −p/ρ − g·h turns an
/// impulse into a jump of the surface potential, Δφ = −V·v / A.
pub fn kick_per_unit(spray_size: f32, water: f32, cell: f64) -> f64 {
    kick_per_unit_of_volume(spray_parcel_volume(spray_size, water), cell)
}

/// Depth (m) the plume under a plunging liquid reaches per m/s of its
/// impact speed: about 0.2 m for a jet plunging at 4 m/s. The liquid's
/// momentum goes down into that plume (a submerged jet spreading as it
/// goes), so the surface feels it over the plume's width, not the cell it
/// crossed the level in; the white water's bubbles fill the same plume.
pub const PLUME_DEPTH_PER_SPEED: f32 = 0.05;
/// Most cells a plunge's impulse reaches on each side of its own.
pub const PLUNGE_SPREAD_CELLS: i64 = 8;

/// The share of a plunge's impulse that a cell of the interactive water
/// takes before normalising (as `plunge_weight` in ripples.wgsl): its
/// centre `r2` m² (squared) from where the liquid landed, in a plume
/// `radius` m wide, (1 − r²/R²)², nothing beyond.
pub fn plunge_weight(r2: f64, radius: f64) -> f64 {
    let u = 1.0 - r2 / (radius * radius);
    if u > 0.0 { u * u } else { 0.0 }
}

/// Δφ (m²/s) one kick unit gives a cell `cell` m wide when a unit stands
/// for a parcel of `volume` m³ at 1/[`KICK_SCALE`] m/s (the liquid's
/// particles, where no spray sets the unit).
pub fn kick_per_unit_of_volume(volume: f64, cell: f64) -> f64 {
    volume / (cell * cell) / KICK_SCALE as f64
}

//! What can go wrong building or feeding the renderer: one error type for
//! the library's callers, each variant a one-line message naming the value.

use hydrolux_core::geometry::load::AssetError;

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(transparent)]
    OceanTooLarge(#[from] OceanTooLarge),
    #[error(transparent)]
    Asset(#[from] AssetError),
    #[error("cannot update the heightfield: {0}")]
    Heightfield(String),
}

#[derive(Debug, thiserror::Error)]
#[error(
    "ocean.resolution = {n} with {cascades} cascades needs a {need_mib} MiB GPU buffer, but this device allows {max_mib} MiB: \
     lower ocean.resolution or ocean.cascades"
)]
pub struct OceanTooLarge {
    pub n: u32,
    pub cascades: u32,
    pub need_mib: u64,
    pub max_mib: u64,
}

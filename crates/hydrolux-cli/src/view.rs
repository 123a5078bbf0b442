//! `hydrolux view`: interactive viewer (to be filled in).
use crate::SceneArgs;
use anyhow::Result;
use clap::Args;

#[derive(Args)]
pub struct ViewArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
}

pub fn run(_a: ViewArgs) -> Result<()> {
    anyhow::bail!("the viewer is not built yet")
}

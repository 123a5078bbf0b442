//! Write the fuzz targets' seed inputs (valid scenes, arrays, meshes and
//! images) into DIR/<target>/, the corpus cargo-fuzz starts from:
//! `cargo run -p hydrolux-core --example fuzz_corpus fuzz/corpus`.

fn main() -> std::io::Result<()> {
    let dir = std::env::args().nth(1).unwrap_or_else(|| "fuzz/corpus".into());
    for (name, _) in hydrolux_core::fuzz::TARGETS {
        let sub = std::path::Path::new(&dir).join(name);
        std::fs::create_dir_all(&sub)?;
        for (i, seed) in hydrolux_core::fuzz::seeds(name).iter().enumerate() {
            std::fs::write(sub.join(format!("seed{i}")), seed)?;
        }
    }
    println!("wrote the seeds into {dir}/<target>/");
    Ok(())
}

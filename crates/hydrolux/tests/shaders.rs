//! Every WGSL shader the renderer builds parses and validates with naga, and
//! every uniform struct has the same size in Rust and WGSL. Needs no GPU.

fn parse(name: &str, source: &str) -> naga::Module {
    naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)))
}

#[test]
fn all_shaders_validate() {
    let shaders = hydrolux::shaders::all_for_validation();
    assert!(shaders.len() >= 10);
    for (name, source) in shaders {
        let module = parse(&name, &source);
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
    }
}

#[test]
fn uniform_layouts_match_wgsl() {
    for (struct_name, source, rust_size) in hydrolux::uniforms::layouts() {
        let module = parse(struct_name, &source);
        let ty = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(struct_name))
            .unwrap_or_else(|| panic!("struct {struct_name} not found"))
            .1;
        let wgsl_size = ty.inner.size(module.to_ctx()) as usize;
        assert_eq!(wgsl_size, rust_size, "{struct_name}: WGSL {wgsl_size} bytes, Rust {rust_size}");
    }
}

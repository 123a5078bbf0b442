// The output the liquid's two meshers share (surface.wgsl, marching cubes;
// screen_mesh.wgsl, screen-space meshes; Rust: `LiquidMesh`): the indexed
// indirect draw's arguments with the vertices taken, and eight floats a
// vertex (position, normal, uv: the meshes' layout). The importer binds
// `counters: MeshCounters` and `vertices: array<f32>`.

struct MeshCounters {
    index_count: atomic<u32>,
    instance_count: u32,
    first_index: u32,
    base_vertex: u32,
    first_instance: u32,
    vertex_count: atomic<u32>,
}

// An empty mesh, drawn once.
fn reset_mesh_counters() {
    atomicStore(&counters.index_count, 0u);
    counters.instance_count = 1u;
    counters.first_index = 0u;
    counters.base_vertex = 0u;
    counters.first_instance = 0u;
    atomicStore(&counters.vertex_count, 0u);
}

// The draw covers the indices written (allocations past the buffer's end
// were not).
fn keep_indices_within(capacity: u32) {
    let n = atomicLoad(&counters.index_count);
    atomicStore(&counters.index_count, min(n, capacity));
}

fn set_mesh_position(slot: u32, p: vec3<f32>) {
    let at = slot * 8u;
    vertices[at] = p.x;
    vertices[at + 1u] = p.y;
    vertices[at + 2u] = p.z;
    vertices[at + 6u] = 0.0;
    vertices[at + 7u] = 0.0;
}

fn set_mesh_normal(slot: u32, n: vec3<f32>) {
    let at = slot * 8u;
    vertices[at + 3u] = n.x;
    vertices[at + 4u] = n.y;
    vertices[at + 5u] = n.z;
}

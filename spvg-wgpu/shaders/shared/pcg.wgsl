// pcg3d16 (Jarzynski & Olano 2020, docs/algorithms.md §6): 16 random bits per lane.
// Rust twin: `spvg_wgpu::twin::pcg3d16`.
fn pcg3d16(p: vec3<u32>) -> vec3<u32> {
    var v = p * 12829u + vec3<u32>(47989u);
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    return v >> vec3<u32>(16u);
}

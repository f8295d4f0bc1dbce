//! The library as a naga_oil composable module (`spvg_shaders::composable_module`, the
//! `naga_oil` feature): composed with a host shader that imports it by its path `spvg`,
//! the result validates with naga's validator. Needs no GPU.
#![cfg(feature = "naga_oil")]

use naga::valid::{Capabilities, ValidationFlags, Validator};
use naga_oil::compose::{Composer, NagaModuleDescriptor, ShaderLanguage, ShaderType};

/// A Route 2 estimate as a renderer would write it: imported names (the whole decision,
/// the texel estimate, the entering count and the dilation mark), and a qualified one.
const HOST: &str = r#"
#import spvg::{spvg_Params, spvg_Reprojection, spvg_PreviousTexel, spvg_SOURCE_PENDING,
    spvg_SOURCE_BORDER_PRIOR, spvg_SOURCE_DISOCCLUDED, spvg_REPROJECT_DEFAULT_FLAGS,
    spvg_reproject_locate_start, spvg_reproject_locate, spvg_reproject_entering_count,
    spvg_history_written, spvg_estimate_texel, spvg_DILATION_KEEP}

@group(0) @binding(0) var<uniform> params: spvg_Params;
@group(0) @binding(1) var history: texture_2d<f32>;
@group(0) @binding(2) var motion: texture_2d<f32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var previous_depth: texture_2d<f32>;
@group(0) @binding(5) var<storage, read_write> counts: array<u32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(history);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let v = textureLoad(motion, id.xy, 0).xy;
    let d = textureLoad(depth, id.xy, 0).x;
    let rule = spvg_Reprojection(0.02, spvg_REPROJECT_DEFAULT_FLAGS);
    var l = spvg_reproject_locate_start(rule, id.xy, v, size, size);
    while (l.source == spvg_SOURCE_PENDING) {
        let h = textureLoad(history, l.texel, 0);
        let prev = spvg_PreviousTexel(true, textureLoad(previous_depth, l.texel, 0).x, spvg_history_written(h));
        l = spvg_reproject_locate(rule, id.xy, v, size, d, l, prev);
    }
    var h = vec4<f32>(0.0);
    if (l.source != spvg_SOURCE_DISOCCLUDED) {
        h = textureLoad(history, l.texel, 0);
    }
    var n = spvg_estimate_texel(params, h, 1.0);
    if (l.source == spvg_SOURCE_BORDER_PRIOR) {
        n = spvg_reproject_entering_count(rule, n, params.max_samples);
    }
    if (l.source == spvg_SOURCE_DISOCCLUDED) {
        n = n | spvg_DILATION_KEEP;
    }
    // A qualified name works as well as an imported one.
    n = min(n, spvg::spvg_round_count(params, 1e9) | spvg_DILATION_KEEP);
    counts[id.y * size.x + id.x] = n;
}
"#;

#[test]
fn naga_oil_composes_the_library() {
    let mut composer = Composer::default();
    let descriptor = spvg_shaders::composable_module();
    assert!(matches!(descriptor.language, ShaderLanguage::Wgsl));
    let added = composer
        .add_composable_module(descriptor)
        .map(|m| m.name.clone());
    let defined = added.unwrap_or_else(|e| panic!("{}", e.emit_to_string(&composer)));
    assert_eq!(defined, spvg_shaders::IMPORT_PATH, "the import path");
    let module = composer
        .make_naga_module(NagaModuleDescriptor {
            source: HOST,
            file_path: "host.wgsl",
            shader_type: ShaderType::Wgsl,
            ..Default::default()
        })
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&composer)));
    Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(&module)
        .unwrap_or_else(|e| panic!("the composed module does not validate: {e:?}"));
    // The host's entry point, and the library's functions it reaches, under naga_oil's
    // decorated names.
    assert_eq!(module.entry_points.len(), 1);
    assert_eq!(module.entry_points[0].name, "main");
    let names: Vec<&str> = module
        .functions
        .iter()
        .filter_map(|(_, f)| f.name.as_deref())
        .collect();
    for called in [
        "spvg_reproject_locate_start",
        "spvg_reproject_locate",
        "spvg_estimate_texel",
        "spvg_round_count",
    ] {
        // naga_oil 0.23 decorates an imported item as `{name}X_naga_oil_mod_X{module}X`.
        assert!(
            names.iter().any(|n| n
                .strip_prefix(called)
                .is_some_and(|rest| rest.starts_with("X_naga_oil_mod_X"))),
            "{called} is not in the composed module: {names:?}"
        );
    }
}

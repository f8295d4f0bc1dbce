//! The library without a GPU: naga parses and validates it (alone, module by module with
//! the documented dependencies, and joined to a host shader), every public name carries
//! the `spvg_` prefix, `Params` has the layout naga computes for `spvg_Params`, and
//! `ReprojectionRule` the layout and flag values of `spvg_Reprojection`.

use naga::valid::{Capabilities, ValidationFlags, Validator};
use spvg_shaders::{
    MODULES, Params, REPROJECT_BORDER_MAXIMUM, REPROJECT_BORDER_PRIOR, REPROJECT_FOOTPRINT,
    ReprojectionRule, WGSL,
};

fn validate(label: &str, src: &str) -> (naga::Module, naga::valid::ModuleInfo) {
    let module = naga::front::wgsl::parse_str(src)
        .unwrap_or_else(|e| panic!("{label}: WGSL parse error\n{}", e.emit_to_string(src)));
    let info = Validator::new(ValidationFlags::all(), Capabilities::empty())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{label}: validation error\n{}", e.emit_to_string(src)));
    (module, info)
}

#[test]
fn library_validates_alone_with_no_globals_or_entry_points() {
    let (module, _) = validate("spvg_shaders::WGSL", WGSL);
    assert_eq!(
        module.global_variables.len(),
        0,
        "the library declares no globals"
    );
    assert!(
        module.entry_points.is_empty(),
        "the library declares no entry points"
    );
    assert!(
        module.functions.len() >= 50,
        "only {} functions parsed",
        module.functions.len()
    );
}

#[test]
fn every_public_name_is_prefixed() {
    let (module, _) = validate("spvg_shaders::WGSL", WGSL);
    let mut names: Vec<String> = Vec::new();
    names.extend(module.functions.iter().filter_map(|(_, f)| f.name.clone()));
    names.extend(module.constants.iter().filter_map(|(_, c)| c.name.clone()));
    names.extend(module.types.iter().filter_map(|(_, t)| t.name.clone()));
    for n in &names {
        assert!(
            n.starts_with("spvg_"),
            "public WGSL name `{n}` lacks the spvg_ prefix"
        );
    }
    for required in [
        "spvg_estimate_count",
        "spvg_update_history",
        "spvg_cv_coefficient",
        "spvg_update_cv",
        "spvg_Params",
        "spvg_History",
        "spvg_CvHistory",
    ] {
        assert!(names.iter().any(|n| n == required), "{required} missing");
    }
}

#[test]
fn each_module_validates_with_its_documented_dependencies() {
    for m in MODULES {
        let mut src = String::new();
        let mut stack: Vec<&str> = vec![m.name];
        let mut seen: Vec<&str> = Vec::new();
        while let Some(n) = stack.pop() {
            if seen.contains(&n) {
                continue;
            }
            seen.push(n);
            let dep = MODULES
                .iter()
                .find(|d| d.name == n)
                .unwrap_or_else(|| panic!("{}: unknown dependency {n}", m.name));
            src.push_str(dep.source);
            stack.extend(dep.depends_on.iter().copied());
        }
        validate(m.name, &src);
    }
    let joined: String = MODULES.iter().map(|m| m.source).collect();
    assert_eq!(joined, WGSL, "WGSL is the concatenation of MODULES");
}

/// A host shader of the kind a renderer writes: its own uniform (with `spvg_Params`
/// inside), textures, storage buffer and entry point, calling the library.
const HOST: &str = r"
struct Frame {
    spvg: spvg_Params,
    size: vec2<u32>,
    frame: u32,
    pad: u32,
}
@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var history_in: texture_2d<f32>;
@group(0) @binding(2) var history_out: texture_storage_2d<rgba16float, write>;
@group(0) @binding(3) var<storage, read_write> counts: array<u32>;

@compute @workgroup_size(8, 8)
fn adaptive(@builtin(global_invocation_id) id: vec3<u32>) {
    if (any(id.xy >= frame.size)) {
        return;
    }
    let p = frame.spvg;
    let h = spvg_decode_history(p, textureLoad(history_in, id.xy, 0));
    let n = spvg_estimate_count(p, h, 1.0, true);
    let seed = spvg_r2_offset_from_seed(spvg_pixel_seed(id.x, id.y, frame.frame));
    var s = 0.0;
    for (var m = 0u; m < n; m++) {
        s += spvg_to_unit_f32(spvg_r2_point(seed, m).x);
    }
    let u = spvg_update_history(p, h, s / f32(max(n, 1u)), n, true);
    textureStore(history_out, id.xy, spvg_encode_history(p, u.history, seed.x));
    counts[id.y * frame.size.x + id.x] = n;
}
";

#[test]
fn library_joins_a_host_shader() {
    let src = format!("{WGSL}{HOST}");
    let (module, _) = validate("library + host", &src);
    assert_eq!(module.entry_points.len(), 1, "the host's entry point");
    assert_eq!(module.global_variables.len(), 4, "the host's bindings");
}

/// `(name, byte offset, is f32)` of every field of `Params`, from the Rust struct itself:
/// `offset_of!` gives the offset and the `let` checks the declared type.
macro_rules! rust_fields {
    ($($f:ident: $t:ty),* $(,)?) => {{
        let p = Params::zeroed();
        let mut v: Vec<(&str, usize, bool)> = Vec::new();
        $(
            let _: $t = p.$f;
            v.push((stringify!($f), core::mem::offset_of!(Params, $f), stringify!($t) == "f32"));
        )*
        v
    }};
}

use bytemuck::Zeroable;

#[test]
fn params_layout_matches_naga_reflection() {
    let (module, _) = validate("spvg_shaders::WGSL", WGSL);
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).expect("layout");
    let (handle, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some("spvg_Params"))
        .expect("struct spvg_Params");
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        panic!("spvg_Params is not a struct");
    };
    assert_eq!(*span as usize, size_of::<Params>(), "size");
    assert_eq!(
        layouter[handle].size as usize,
        size_of::<Params>(),
        "layouter size"
    );
    assert_eq!(
        layouter[handle].alignment,
        naga::proc::Alignment::FOUR,
        "alignment"
    );
    let rust = rust_fields!(
        eta: f32, retain: f32, eta_retain: f32, target_variance: f32, inv_target: f32,
        kappa: f32, k_minus_1: f32, eps_u: f32, min_samples_f: f32, max_samples_f: f32,
        min_samples: u32, max_samples: u32, policy: u32, fixed_count: u32, damped: u32,
        cap_down: f32, cap_up: f32, model: u32,
        f16_inputs: u32, eta_cv: f32, retain_cv: f32, eta_retain_cv: f32, eps_a: f32,
        a0: f32, texel_layout: u32, rounding: u32, var_scale: f32, inv_var_scale: f32,
        cv_scale: f32, inv_cv_scale: f32, firefly_k: f32, young: u32, fractional: u32,
        floor_f: f32, resolve_weight: f32, spare_b: u32,
    );
    assert_eq!(
        rust.len() * 4,
        size_of::<Params>(),
        "every Rust field listed"
    );
    assert_eq!(members.len(), rust.len(), "member count");
    // The WGSL names that differ from the Rust fields (params.wgsl says why: no member
    // name ends in a digit).
    let wgsl_name = |rust: &'static str| match rust {
        "k_minus_1" => "k_minus_one",
        "a0" => "a_zero",
        other => other,
    };
    for (m, (name, offset, is_f32)) in members.iter().zip(&rust) {
        assert_eq!(m.name.as_deref(), Some(wgsl_name(name)), "member order");
        assert!(
            !wgsl_name(name).ends_with(|c: char| c.is_ascii_digit()),
            "{name}: a member name ending in a digit is renamed by naga and refused by naga_oil"
        );
        assert_eq!(m.offset as usize, *offset, "offset of {name}");
        let want = naga::Scalar {
            kind: if *is_f32 {
                naga::ScalarKind::Float
            } else {
                naga::ScalarKind::Uint
            },
            width: 4,
        };
        assert_eq!(
            module.types[m.ty].inner,
            naga::TypeInner::Scalar(want),
            "type of {name}"
        );
    }
}

/// The value of the WGSL `const` named `name` of `module` (a `u32` literal).
fn u32_constant(module: &naga::Module, name: &str) -> u32 {
    let (_, c) = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("const {name}"));
    match module.global_expressions[c.init] {
        naga::Expression::Literal(naga::Literal::U32(v)) => v,
        ref other => panic!("{name} is not a u32 literal: {other:?}"),
    }
}

/// `ReprojectionRule` is `spvg_Reprojection` byte for byte (naga's layout: the tolerance
/// an f32 at 0, the flags a u32 at 4, 8 bytes), and the Rust flag bits are the WGSL
/// `spvg_REPROJECT_*` constants the library tests, so a rule built with
/// `ReprojectionRule::new` switches in the shader what it switches in `spvg::reproject`.
#[test]
fn reprojection_rule_matches_the_wgsl_struct_and_flags() {
    let (module, _) = validate("spvg_shaders::WGSL", WGSL);
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).expect("layout");
    let (handle, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some("spvg_Reprojection"))
        .expect("struct spvg_Reprojection");
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        panic!("spvg_Reprojection is not a struct");
    };
    assert_eq!(*span as usize, size_of::<ReprojectionRule>(), "size");
    assert_eq!(
        layouter[handle].size as usize,
        size_of::<ReprojectionRule>(),
        "layouter size"
    );
    let scalar = |kind| naga::TypeInner::Scalar(naga::Scalar { kind, width: 4 });
    let rust = [
        (
            "depth_tolerance",
            core::mem::offset_of!(ReprojectionRule, depth_tolerance),
            scalar(naga::ScalarKind::Float),
        ),
        (
            "flags",
            core::mem::offset_of!(ReprojectionRule, flags),
            scalar(naga::ScalarKind::Uint),
        ),
    ];
    assert_eq!(members.len(), rust.len(), "member count");
    for (m, (name, offset, inner)) in members.iter().zip(&rust) {
        assert_eq!(m.name.as_deref(), Some(*name), "member order");
        assert_eq!(m.offset as usize, *offset, "offset of {name}");
        assert_eq!(module.types[m.ty].inner, *inner, "type of {name}");
    }
    for (rust, wgsl) in [
        (REPROJECT_BORDER_PRIOR, "spvg_REPROJECT_BORDER_PRIOR"),
        (REPROJECT_FOOTPRINT, "spvg_REPROJECT_FOOTPRINT"),
        (REPROJECT_BORDER_MAXIMUM, "spvg_REPROJECT_BORDER_MAXIMUM"),
    ] {
        assert_eq!(rust, u32_constant(&module, wgsl), "{wgsl}");
    }
    let default = ReprojectionRule::default();
    assert_eq!(
        default.flags,
        u32_constant(&module, "spvg_REPROJECT_DEFAULT_FLAGS"),
        "Reprojection::default() is spvg_REPROJECT_DEFAULT_FLAGS"
    );
}

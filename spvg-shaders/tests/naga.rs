//! The library without a GPU: naga parses and validates it (alone, module by module with
//! the documented dependencies, and joined to a host shader), every public name carries
//! the `spvg_` prefix, and `Params` has the layout naga computes for `spvg_Params`.

use naga::valid::{Capabilities, ValidationFlags, Validator};
use spvg_shaders::{MODULES, Params, WGSL};

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
        floor_f: f32, spare_a: u32, spare_b: u32,
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

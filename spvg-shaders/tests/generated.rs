//! The committed HLSL and MSL (`generated/`) are what naga makes of the library today:
//! regenerated here and compared byte for byte. `SPVG_BLESS=1 cargo test -p spvg-shaders
//! --test generated` rewrites them after a change to the WGSL.

use naga::valid::{Capabilities, ValidationFlags, Validator};

fn module() -> (naga::Module, naga::valid::ModuleInfo) {
    let src = spvg_shaders::WGSL;
    let module =
        naga::front::wgsl::parse_str(src).unwrap_or_else(|e| panic!("{}", e.emit_to_string(src)));
    let info = Validator::new(ValidationFlags::all(), Capabilities::empty())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(src)));
    (module, info)
}

fn hlsl() -> String {
    let (module, info) = module();
    let options = naga::back::hlsl::Options {
        shader_model: naga::back::hlsl::ShaderModel::V5_1,
        ..Default::default()
    };
    let pipeline = naga::back::hlsl::PipelineOptions::default();
    let mut out = String::new();
    naga::back::hlsl::Writer::new(&mut out, &options, &pipeline)
        .write(&module, &info, None)
        .expect("HLSL");
    out
}

fn msl() -> String {
    let (module, info) = module();
    let options = naga::back::msl::Options {
        lang_version: (2, 0),
        ..Default::default()
    };
    let pipeline = naga::back::msl::PipelineOptions::default();
    naga::back::msl::write_string(&module, &info, &options, &pipeline)
        .expect("MSL")
        .0
}

fn check(path: &str, committed: &str, fresh: &str) {
    let file = format!("{}/generated/{path}", env!("CARGO_MANIFEST_DIR"));
    if std::env::var_os("SPVG_BLESS").is_some_and(|v| v == "1") {
        std::fs::write(&file, fresh).expect("write generated file");
        return;
    }
    if committed != fresh {
        let line = committed
            .lines()
            .zip(fresh.lines())
            .position(|(a, b)| a != b)
            .map_or(committed.lines().count().min(fresh.lines().count()), |i| i);
        panic!(
            "{file} differs from naga's output from line {} on (committed {} bytes, fresh {}); \
             rerun with SPVG_BLESS=1 to regenerate",
            line + 1,
            committed.len(),
            fresh.len()
        );
    }
}

#[test]
fn hlsl_is_regenerated_byte_for_byte() {
    check("spvg.hlsl", spvg_shaders::HLSL, &hlsl());
}

#[test]
fn msl_is_regenerated_byte_for_byte() {
    check("spvg.metal", spvg_shaders::MSL, &msl());
}

/// Every library function appears in both translations although the library has no entry
/// point (naga 30's backends write every function; if a later naga wrote only what entry
/// points reach, this test fails and the generation needs a wrapper entry point).
///
/// Names are matched as whole identifiers (`spvg_estimate` is not found inside
/// `spvg_estimate_count`), so a function that a backend dropped or renamed otherwise than
/// documented is missed. The one documented rename (README, HLSL and MSL): naga appends
/// `_` to a name that ends in a digit (`spvg_pcg3d16` is `spvg_pcg3d16_`).
#[test]
fn every_function_is_translated() {
    let (module, _) = module();
    let (hlsl, msl) = (hlsl(), msl());
    let (h, m) = (identifiers(&hlsl), identifiers(&msl));
    assert!(!module.functions.is_empty(), "the library has functions");
    for (_, f) in module.functions.iter() {
        let name = f.name.as_deref().expect("every library function is named");
        let translated = if name.ends_with(|c: char| c.is_ascii_digit()) {
            format!("{name}_")
        } else {
            name.to_owned()
        };
        assert!(
            h.contains(translated.as_str()),
            "{translated} missing from the HLSL"
        );
        assert!(
            m.contains(translated.as_str()),
            "{translated} missing from the MSL"
        );
    }
}

/// The identifiers of a C-like source: maximal runs of ASCII letters, digits and `_`.
fn identifiers(source: &str) -> std::collections::HashSet<&str> {
    source
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| w.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_'))
        .collect()
}

#[test]
fn identifiers_are_whole_words() {
    let ids = identifiers("uint spvg_estimate_count(float x) { return spvg_u32_to_f32(1u); }");
    assert!(ids.contains("spvg_estimate_count"));
    assert!(ids.contains("spvg_u32_to_f32"));
    assert!(
        !ids.contains("spvg_estimate"),
        "a prefix is not an identifier"
    );
    assert!(!ids.contains("1u"), "a literal is not an identifier");
}

//! WGSL sources: the pass (`shaders/sss.wgsl`) is prefixed by the controller library
//! ([`spvg_shaders::WGSL`]: every controller, control-variate, texel, sequence and Burley
//! rule) and by the pass's own shared files (`shaders/shared/`: the uniform block, the
//! sample direction and the estimator glue), a plain textual concatenation at load time.

/// The pass's own shared WGSL files in dependency order (name, source); they call the
/// library's `spvg_` functions.
pub const SHARED: [(&str, &str); 3] = [
    ("params.wgsl", include_str!("../shaders/shared/params.wgsl")),
    (
        "direction.wgsl",
        include_str!("../shaders/shared/direction.wgsl"),
    ),
    (
        "estimator.wgsl",
        include_str!("../shaders/shared/estimator.wgsl"),
    ),
];

/// The subsurface pass (`shaders/sss.wgsl`): entry points `sss_fixed`, `sss_gamma` and
/// `sss_sample` (the adaptive models' count control is [`crate::adaptive::AdaptivePass`]).
pub const SSS: &str = include_str!("../shaders/sss.wgsl");

/// Concatenates the library, the shared files and `pass` into one WGSL module source.
#[must_use]
pub fn assemble(pass: &str) -> String {
    let mut s = String::from("// ---- spvg_shaders::WGSL\n");
    s.push_str(spvg_shaders::WGSL);
    for (name, src) in SHARED {
        s.push_str("// ---- shared/");
        s.push_str(name);
        s.push('\n');
        s.push_str(src);
    }
    s.push_str("// ---- pass\n");
    s.push_str(pass);
    s
}

/// The assembled subsurface pass.
#[must_use]
pub fn sss_source() -> String {
    assemble(SSS)
}

/// The budget reduction (`shaders/reduce.wgsl`): entry point `reduce_demand`.
pub const REDUCE: &str = include_str!("../shaders/reduce.wgsl");

/// The assembled budget reduction.
#[must_use]
pub fn reduce_source() -> String {
    assemble(REDUCE)
}

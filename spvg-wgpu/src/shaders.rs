//! WGSL sources: each pass file is prefixed by the `shaders/shared/` files it uses, a plain
//! textual concatenation at load time.

/// The shared WGSL files in dependency order (name, source).
pub const SHARED: [(&str, &str); 8] = [
    ("params.wgsl", include_str!("../shaders/shared/params.wgsl")),
    ("texel.wgsl", include_str!("../shaders/shared/texel.wgsl")),
    ("pcg.wgsl", include_str!("../shaders/shared/pcg.wgsl")),
    ("r2.wgsl", include_str!("../shaders/shared/r2.wgsl")),
    ("burley.wgsl", include_str!("../shaders/shared/burley.wgsl")),
    (
        "controller.wgsl",
        include_str!("../shaders/shared/controller.wgsl"),
    ),
    ("cv.wgsl", include_str!("../shaders/shared/cv.wgsl")),
    (
        "estimator.wgsl",
        include_str!("../shaders/shared/estimator.wgsl"),
    ),
];

/// The subsurface pass (`shaders/sss.wgsl`): entry points `sss_fixed`, `sss_adaptive`,
/// `sss_ocv`.
pub const SSS: &str = include_str!("../shaders/sss.wgsl");

/// Concatenates the shared files and `pass` into one WGSL module source.
#[must_use]
pub fn assemble(pass: &str) -> String {
    let mut s = String::new();
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

//! Which frame-loop variant this build runs on this CPU, and the CPU's x86-64
//! micro-architecture level: what `benches/native_vs_portable.sh` prints above its
//! tables.
//!
//! ```sh
//! cargo run --release --example loop_variant
//! ```
//!
//! Prints two lines, for example on an AVX2 machine in the portable build:
//!
//! ```text
//! cpu level: x86-64-v3 (no avx512f/bw/vl)
//! loop variant: avx2; available: as-compiled avx2
//! ```

use spvg::texel::{LoopVariant, selected_loop_variant};

fn main() {
    println!("cpu level: {}", cpu_level());
    let available: Vec<&str> = LoopVariant::ALL
        .into_iter()
        .filter(|v| v.is_available())
        .map(LoopVariant::name)
        .collect();
    println!(
        "loop variant: {}; available: {}",
        selected_loop_variant(),
        available.join(" ")
    );
}

/// The highest x86-64 micro-architecture level whose features this CPU has (detected at
/// run time), and whether it has the AVX-512 subsets the AVX-512 variant needs.
#[cfg(target_arch = "x86_64")]
fn cpu_level() -> String {
    use std::arch::is_x86_feature_detected as has;
    let v2 = has!("sse4.2") && has!("popcnt") && has!("ssse3") && has!("sse4.1");
    let v3 = v2
        && has!("avx2")
        && has!("bmi1")
        && has!("bmi2")
        && has!("f16c")
        && has!("fma")
        && has!("lzcnt")
        && has!("movbe");
    let v4 = v3
        && has!("avx512f")
        && has!("avx512bw")
        && has!("avx512cd")
        && has!("avx512dq")
        && has!("avx512vl");
    let level = match (v2, v3, v4) {
        (_, _, true) => "x86-64-v4",
        (_, true, _) => "x86-64-v3",
        (true, _, _) => "x86-64-v2",
        _ => "x86-64-v1",
    };
    let avx512 = has!("avx512f") && has!("avx512bw") && has!("avx512vl");
    let fp16 = has!("avx512fp16");
    match (avx512, fp16) {
        (false, _) => format!("{level} (no avx512f/bw/vl)"),
        (true, false) => format!("{level} (avx512f/bw/vl; no avx512fp16)"),
        (true, true) => format!("{level} (avx512f/bw/vl, avx512fp16)"),
    }
}

/// Not an x86-64 CPU: the architecture.
#[cfg(not(target_arch = "x86_64"))]
fn cpu_level() -> String {
    std::env::consts::ARCH.to_owned()
}

//! A `#![no_std]` `#![no_main]` binary linking `spvg` with default features off (only
//! `libm`), for the host. It is the test that no crate in the dependency graph pulls in
//! `std`: `std` brings its own `#[panic_handler]`, so if anything enabled std, this crate's
//! handler below would collide with std's and the build would fail with
//! `error[E0152]: found duplicate lang item 'panic_impl'`. (Checked by hand: adding
//! `"std"` to spvg's features in Cargo.toml gives exactly that error.)
//!
//! `main` is the C `main` called by the host C runtime's start files, so no Rust runtime
//! is needed. Build: `cd nostd-probe && cargo build --release` (CI does; running it is
//! optional, it exits 0 when the estimators give the expected numbers).
#![no_std]
#![no_main]

use core::hint::black_box;

use half::f16;
use spvg::stats::{Ema, Emcm, Emv, Weight};

// rustc links no_std binaries with `-nodefaultlibs`; the host C runtime's start files
// (`_start` -> `__libc_start_main` -> `main`) need libc itself.
#[cfg(unix)]
#[link(name = "c")]
unsafe extern "C" {}

// rustc links no_std binaries with `-nodefaultlibs`; the host C runtime's start files
// (`_start` -> `__libc_start_main` -> `main`) need libc itself.
#[cfg(unix)]
#[link(name = "c")]
unsafe extern "C" {}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    loop {}
}

/// `libm`'s `expf`/`logf` (the governor's `exp` and `ln`) keep a bounds check whose panic
/// path links the precompiled `core::panicking` object, and that object names the
/// unwinding personality. With `panic = "abort"` it is never called; a `no_std` binary
/// that uses the crate's `exp`/`ln` paths (the budget governor, the Burley profile)
/// defines it like this, or builds `core` with `-Z build-std`.
#[unsafe(no_mangle)]
extern "C" fn rust_eh_personality() {}

/// Runs the estimators in `f32` and `f16` through `black_box` so nothing is folded away;
/// returns 0 when the results are the exact values of the two-sample stream `{2, 4}` with
/// `eta = 1/2` (mean 3, variance 1).
fn exercise() -> i32 {
    let mut failures = 0;
    let Ok(w32) = Weight::new(black_box(0.5_f32)) else {
        return 10;
    };
    let Ok(w16) = Weight::new(black_box(f16::from_f32(0.5))) else {
        return 11;
    };

    let mut ema = Ema::seeded(black_box(2.0_f32));
    ema.update(&w32, black_box(4.0));
    failures += i32::from(black_box(ema.mean()) != 3.0);

    let mut emv = Emv::seeded(black_box(2.0_f32));
    emv.update(&w32, black_box(4.0));
    failures += i32::from(black_box(emv.variance()) != 1.0);

    let mut emv16 = Emv::seeded(black_box(f16::from_f32(2.0)));
    emv16.update(&w16, black_box(f16::from_f32(4.0)));
    failures += i32::from(black_box(emv16.variance()) != f16::from_f32(1.0));

    let mut emcm = Emcm::<f32, 2>::seeded(black_box([2.0, 0.0]));
    emcm.update(&w32, black_box([4.0, -2.0]));
    failures += i32::from(black_box(emcm.covariance(0, 1)) != -1.0);

    let mut emcm16 = Emcm::<f16, 3>::default();
    let z = [f16::from_f32(1.0), f16::from_f32(-1.0), f16::from_f32(0.5)];
    emcm16.update(&w16, black_box(z));
    failures += i32::from(black_box(emcm16.coefficients())[0][0] != f16::from_f32(1.0));

    // The frame budget governor (`ln` and `exp` through libm): a total of twice the
    // budget at gain 1/2 raises the target by sqrt(2).
    let Ok(budget) = spvg::budget::BudgetConfig::builder(black_box(100.0_f32))
        .gain(0.5)
        .build()
    else {
        return 12;
    };
    let Ok(mut governor) = spvg::budget::Governor::new(budget, black_box(1e-3)) else {
        return 13;
    };
    governor.observe(black_box(200.0));
    let ratio = black_box(governor.target()) / 1e-3;
    failures += i32::from((ratio - core::f32::consts::SQRT_2).abs() > 1e-5);

    // The libm path: sqrt of the variance.
    failures += i32::from(num_sqrt(black_box(emv.variance())) != 1.0);
    failures
}

/// `sqrt` through `num_traits::Float`, which routes to `libm` without std.
fn num_sqrt(v: f32) -> f32 {
    num_traits::Float::sqrt(v)
}

/// The C entry point, called by the host C runtime.
#[unsafe(no_mangle)]
pub extern "C" fn main(_argc: i32, _argv: *const *const u8) -> i32 {
    exercise()
}

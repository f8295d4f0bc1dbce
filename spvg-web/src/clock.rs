//! Wall time in milliseconds: `performance.now()` in a browser (where
//! `std::time::Instant` does not exist), `Instant` on native targets.

/// Milliseconds since an arbitrary origin fixed for the process (the page's load in a
/// browser).
#[cfg(target_arch = "wasm32")]
#[must_use]
pub fn now_ms() -> f64 {
    web_sys::window()
        .and_then(|w| w.performance())
        .map_or(0.0, |p| p.now())
}

/// Milliseconds since an arbitrary origin fixed for the process (its first call).
#[cfg(not(target_arch = "wasm32"))]
#[must_use]
pub fn now_ms() -> f64 {
    static ORIGIN: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
    ORIGIN
        .get_or_init(std::time::Instant::now)
        .elapsed()
        .as_secs_f64()
        * 1e3
}

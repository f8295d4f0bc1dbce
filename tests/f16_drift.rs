//! f16_drift

//! Exact identities between the estimators (docs/algorithms.md §1).

use proptest::prelude::*;
use spvg::arbitrary::{finite_f32, finite_f64, stream_f32, stream_f64, weight_f32, weight_f64};
use spvg::stats::{Emc, Emcm, Emv, Ewma, Weight};

fn weight<T: num_traits::Float>(eta: T) -> Result<Weight<T>, TestCaseError> {
    Weight::new(eta).map_err(|e| TestCaseError::fail(format!("{e}")))
}

macro_rules! exact_identities {
    ($name:ident, $t:ty, $stream:ident, $weight:ident, $finite:ident) => {
        proptest! {
            #![proptest_config(ProptestConfig::with_cases(256))]

            /// `Emc(x, x)` is bit-for-bit `Emv(x)`, and every `Emcm` entry is bit-for-bit the
            /// `Emc` of its pair (diagonal: the `Emv`), on hard-case streams including
            /// saturation, from both seeds.
            #[test]
            fn $name(
                xs in $stream(0..64),
                eta in $weight(),
                seed in prop::array::uniform3($finite()),
                zero_state in any::<bool>(),
            ) {
                let w = weight(eta)?;
                let seed = if zero_state { [0.0; 3] } else { seed };
                let mut emv = [0, 1, 2].map(|i| Emv::seeded(seed[i]));
                let mut emc = [[Emc::<$t>::default(); 3]; 3];
                for i in 0..3 {
                    for j in 0..3 {
                        emc[i][j] = Emc::seeded(seed[i], seed[j]);
                    }
                }
                let mut m = Emcm::<$t, 3>::seeded(seed);
                for k in 0..xs.len() {
                    // Three streams read from the one generated stream at offsets.
                    let z = [0, 1, 2].map(|o| xs[(k + o) % xs.len()]);
                    m.update(&w, z);
                    for i in 0..3 {
                        emv[i].update(&w, z[i]);
                        for j in 0..3 {
                            emc[i][j].update(&w, z[i], z[j]);
                        }
                    }
                }
                for i in 0..3 {
                    prop_assert_eq!(emc[i][i].covariance().to_bits(), emv[i].variance().to_bits(),
                        "Emc(x,x) {} != Emv {}", emc[i][i].covariance(), emv[i].variance());
                    prop_assert_eq!(emc[i][i].mean_x().to_bits(), emv[i].mean().to_bits(),
                        "Emc mean {} != Emv mean {}", emc[i][i].mean_x(), emv[i].mean());
                    prop_assert_eq!(m.mean()[i].to_bits(), emv[i].mean().to_bits(),
                        "Emcm mean {} != Emv mean {}", m.mean()[i], emv[i].mean());
                    for j in 0..3 {
                        prop_assert_eq!(m.covariance(i, j).to_bits(), emc[i][j].covariance().to_bits(),
                            "Emcm ({},{}) {} != Emc {}", i, j, m.covariance(i, j), emc[i][j].covariance());
                    }
                }
            }
        }
    };
}

exact_identities!(
    pairwise_identities_f64,
    f64,
    stream_f64,
    weight_f64,
    finite_f64
);
exact_identities!(
    pairwise_identities_f32,
    f32,
    stream_f32,
    weight_f32,
    finite_f32
);

fn seeds() -> impl Strategy<Value = Option<[f64; 2]>> {
    prop::option::of(prop::array::uniform2(-100.0..100.0_f64))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// docs/algorithms.md §1 correction: from equal starting states, `S_t = Sigma_t / (1 - eta)` for every
    /// t (eta < 1), up to rounding; so the coefficients of the two estimators agree.
    #[test]
    fn ewma_is_emcm_over_retain(
        z in proptest::collection::vec(prop::array::uniform2(-100.0..100.0_f64), 1..200),
        eta in prop_oneof![Just(1e-7), 1e-4..0.999_f64],
        seed in seeds(),
    ) {
        let w = weight(eta)?;
        let (mut sigma, mut s) = match seed {
            Some(z0) => (Emcm::<f64, 2>::seeded(z0), Ewma::<f64, 2>::seeded(z0)),
            None => (Emcm::default(), Ewma::default()),
        };
        for v in &z {
            sigma.update(&w, *v);
            s.update(&w, *v);
            let scale = s.covariance(0, 0) + s.covariance(1, 1);
            for i in 0..2 {
                for j in 0..2 {
                    let (got, want) = (s.covariance(i, j), sigma.covariance(i, j) / w.retain());
                    let tol = 1e-13 * scale;
                    prop_assert!((got - want).abs() <= tol, "S({i},{j}) {got} != {want} (tol {tol})");
                }
            }
            prop_assert_eq!(s.mean(), sigma.mean(), "means are the same recurrence");
        }
        let (a, b) = (s.coefficients(), sigma.coefficients());
        for i in 0..2 {
            for j in 0..2 {
                // Coefficient error is relative to sqrt(S_jj / S_ii), its Cauchy-Schwarz bound.
                let bound = (s.covariance(j, j) / s.covariance(i, i)).sqrt();
                let tol = 1e-12 * bound.max(1.0);
                prop_assert!((a[i][j] - b[i][j]).abs() <= tol,
                    "A({i},{j}) {} != {} (tol {tol})", a[i][j], b[i][j]);
            }
        }
    }
}

/// With eta = 1 the identity has no finite factor: Sigma is zero and S the outer product
/// of the last deviation, `(z - zeta_old)(z - zeta_old)^T`.
#[test]
fn weight_one_resets() {
    let w = Weight::<f64>::one();
    let mut sigma = Emcm::<f64, 2>::seeded([1.0, 2.0]);
    let mut s = Ewma::<f64, 2>::seeded([1.0, 2.0]);
    sigma.update(&w, [4.0, -2.0]);
    s.update(&w, [4.0, -2.0]);
    assert_eq!(sigma.matrix(), [[0.0; 2]; 2], "Sigma reset by eta = 1");
    let d = [3.0, -4.0];
    assert_eq!(
        s.matrix(),
        [[d[0] * d[0], d[0] * d[1]], [d[1] * d[0], d[1] * d[1]]],
        "S = d d^T"
    );
    assert_eq!(s.mean(), [4.0, -2.0], "mean is the sample");
}

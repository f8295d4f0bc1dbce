//! The frame functions compute the same bits as the per-pixel loop
//! (decode, `PixelController`, encode), on hard inputs.

use half::f16;
use proptest::prelude::*;
use spvg::cv::{As, Ccv, ControlModel, Ocv, PixelController, PixelFrame};
use spvg::texel::{
    ConstantCoefficient, CvTexel16, CvTexel32, FrameInputs, FrameInputsBuf, Rounding, SpvgTexel16,
    SpvgTexel32, Texel, TexelEncoding, channel_bits, estimate_frame, update_frame,
    update_frame_ocv,
};
use spvg::{CvHistory, SpvgConfig, SpvgHistory, controller::CountPolicy};

/// Hard per-pixel inputs: ordinary luminances, extremes, zero, NaN, infinities.
fn value() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => 0.0_f32..4.0,
        1 => -1.0_f32..1.0,
        1 => prop_oneof![Just(0.0_f32), Just(1e-4), Just(1e4), Just(7e4), Just(3e38),
            Just(f32::NAN), Just(f32::INFINITY), Just(-f32::INFINITY), Just(1e-30)],
        1 => any::<u32>().prop_map(f32::from_bits),
    ]
}

fn gamma() -> impl Strategy<Value = f32> {
    prop_oneof![4 => 0.0_f32..=1.0, 1 => Just(0.005_f32), 1 => Just(f32::NAN), 1 => Just(0.0)]
}

#[derive(Clone, Debug)]
struct Pixel {
    l: f32,
    b: f32,
    gamma: f32,
    count: u32,
    valid: u8,
    h: [u32; 4],
    j: [u32; 4],
}

fn pixel() -> impl Strategy<Value = Pixel> {
    let texel = prop_oneof![
        // Random f16 pairs or f32 patterns (NaN, infinities, negatives included) ...
        3 => any::<[u32; 4]>(),
        // ... and plausible stored states.
        3 => (0.0_f32..4.0, 0.0_f32..100.0, 8.0_f32..64.0, -50.0_f32..50.0)
            .prop_map(|(a, b, c, d)| [a.to_bits(), b.to_bits(), c.to_bits(), d.to_bits()]),
    ];
    (
        value(),
        value(),
        gamma(),
        prop_oneof![Just(0_u32), 1_u32..80],
        0_u8..3,
        texel.clone(),
        texel,
    )
        .prop_map(|(l, b, gamma, count, valid, h, j)| Pixel {
            l,
            b,
            gamma,
            count,
            valid: valid.min(1),
            h,
            j,
        })
}

fn t16<T: Texel>(w: [u32; 4]) -> T {
    let bits: [u16; 4] = w.map(|x| (x >> 7) as u16);
    bytemuck::cast_slice::<u16, T>(&bits)[0]
}

fn t32<T: Texel>(w: [u32; 4]) -> T {
    bytemuck::cast_slice::<u32, T>(&w)[0]
}

fn word(rounding: Rounding, i: usize) -> Rounding {
    match rounding {
        Rounding::Nearest => Rounding::Nearest,
        Rounding::Stochastic(s) => Rounding::Stochastic(channel_bits(s, i as u32)),
    }
}

impl Pixel {
    fn frame(&self) -> PixelFrame<f32> {
        PixelFrame {
            radiance: self.l,
            preintegrated: self.b,
            gamma: self.gamma,
        }
    }
}

/// The pixels' inputs as a frame (structure of arrays).
fn frame(p: &[Pixel]) -> FrameInputsBuf {
    let mut f = FrameInputsBuf::with_capacity(p.len());
    for x in p {
        f.push(x.frame(), x.count, x.valid != 0);
    }
    f
}

fn bits_eq<T: Texel>(a: &[T], b: &[T]) -> bool {
    bytemuck::cast_slice::<T, u8>(a) == bytemuck::cast_slice::<T, u8>(b)
}

fn check_constant<M: ConstantCoefficient, H: Texel<History = SpvgHistory<f32>>>(
    pixel: &PixelController<f32, M>,
    enc: &TexelEncoding,
    rounding: Rounding,
    px: &[Pixel],
    mk: fn([u32; 4]) -> H,
) -> Result<(), TestCaseError> {
    let frame = frame(px);
    let inputs = frame.inputs();
    let mut batch: Vec<H> = px.iter().map(|p| mk(p.h)).collect();
    let mut reference = batch.clone();
    update_frame(pixel, enc, rounding, &inputs, &mut batch).unwrap();
    for (i, (t, p)) in reference.iter_mut().zip(px).enumerate() {
        let mut h = enc.decode(*t);
        pixel.update(&mut h, &mut (), p.frame(), p.count, p.valid != 0);
        *t = enc.encode(&h, word(rounding, i));
    }
    prop_assert!(
        bits_eq(&batch, &reference),
        "batch {:?} != per-pixel {:?}",
        batch,
        reference
    );
    Ok(())
}

fn check_ocv<H, C>(
    pixel: &PixelController<f32, Ocv<f32>>,
    enc: &TexelEncoding,
    rounding: Rounding,
    px: &[Pixel],
    mk: fn([u32; 4]) -> H,
    mkc: fn([u32; 4]) -> C,
) -> Result<(), TestCaseError>
where
    H: Texel<History = SpvgHistory<f32>>,
    C: Texel<History = CvHistory<f32>>,
{
    let frame = frame(px);
    let inputs = frame.inputs();
    let mut hb: Vec<H> = px.iter().map(|p| mk(p.h)).collect();
    let mut jb: Vec<C> = px.iter().map(|p| mkc(p.j)).collect();
    let (mut hr, mut jr) = (hb.clone(), jb.clone());
    update_frame_ocv(pixel, enc, rounding, &inputs, &mut hb, &mut jb).unwrap();
    let cv_rounding = match rounding {
        Rounding::Stochastic(s) => Rounding::Stochastic(!s),
        r => r,
    };
    for (i, ((t, c), p)) in hr.iter_mut().zip(jr.iter_mut()).zip(px).enumerate() {
        let mut h = enc.decode(*t);
        let mut j = enc.decode(*c);
        pixel.update(&mut h, &mut j, p.frame(), p.count, p.valid != 0);
        *t = enc.encode(&h, word(rounding, i));
        *c = enc.encode(&j, word(cv_rounding, i));
    }
    prop_assert!(bits_eq(&hb, &hr), "H batch {:?} != per-pixel {:?}", hb, hr);
    prop_assert!(bits_eq(&jb, &jr), "J batch {:?} != per-pixel {:?}", jb, jr);
    Ok(())
}

fn config(policy: CountPolicy, eta: f32, firefly: Option<f32>) -> SpvgConfig<f32> {
    SpvgConfig::builder()
        .eta(eta)
        .policy(policy)
        .firefly_clamp(firefly)
        .build()
        .unwrap()
}

fn policy() -> impl Strategy<Value = CountPolicy> {
    prop_oneof![
        3 => Just(CountPolicy::Spvg),
        1 => Just(CountPolicy::TwoPhase),
        1 => Just(CountPolicy::UnrealClamp),
        1 => Just(CountPolicy::Fixed(16)),
    ]
}

fn rounding() -> impl Strategy<Value = Rounding> {
    prop_oneof![
        Just(Rounding::Nearest),
        any::<u32>().prop_map(Rounding::Stochastic)
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn update_frame_matches_per_pixel(
        px in prop::collection::vec(pixel(), 0..150),
        pol in policy(),
        eta in prop_oneof![Just(0.2_f32), Just(1e-3), Just(1.0)],
        r in rounding(),
        cv_scale in prop_oneof![Just(None), Just(Some(4.096e-3_f32))],
        // The firefly clamp off, usual and tight (it engages on most pixels).
        firefly in prop_oneof![Just(None), Just(Some(8.0_f32)), Just(Some(0.5))],
    ) {
        let c = config(pol, eta, firefly);
        let mut enc = TexelEncoding::new(c.target_variance()).unwrap();
        if let Some(s) = cv_scale {
            enc = enc.with_cv_scale(s).unwrap();
        }
        check_constant(&PixelController::new(c, As), &enc, r, &px, t16::<SpvgTexel16>)?;
        check_constant(&PixelController::new(c, Ccv), &enc, r, &px, t16::<SpvgTexel16>)?;
        check_constant(&PixelController::new(c, As), &enc, r, &px, t32::<SpvgTexel32>)?;
        check_constant(&PixelController::new(c, Ccv), &enc, r, &px, t32::<SpvgTexel32>)?;
        let ocv = PixelController::new(c, Ocv::with_weight(0.05).unwrap());
        check_ocv(&ocv, &enc, r, &px, t16::<SpvgTexel16>, t16::<CvTexel16>)?;
        check_ocv(&ocv, &enc, r, &px, t32::<SpvgTexel32>, t32::<CvTexel32>)?;
        // The model for f16 CV texels: fbar and G enter the update at f16 precision.
        let ocv16 = PixelController::new(c, Ocv::with_weight(0.05).unwrap().with_f16_inputs(true));
        check_ocv(&ocv16, &enc, r, &px, t16::<SpvgTexel16>, t16::<CvTexel16>)?;
        let ocv = PixelController::new(c, Ocv::new(1e-6, 0.0, 2.0).unwrap());
        check_ocv(&ocv, &enc, r, &px, t16::<SpvgTexel16>, t32::<CvTexel32>)?;
    }

    #[test]
    fn estimate_frame_matches_per_pixel(
        px in prop::collection::vec(pixel(), 0..150),
        pol in policy(),
        kappa in prop_oneof![Just(0.2_f32), Just(0.0), Just(1.0)],
        damped in prop_oneof![Just(None), Just(Some(0.35_f32)), Just(Some(0.05))],
    ) {
        let c = SpvgConfig::builder().kappa(kappa).policy(pol).max_change(damped).build().unwrap();
        let enc = TexelEncoding::new(c.target_variance()).unwrap();
        let g: Vec<f32> = px.iter().map(|p| p.gamma).collect();
        let v: Vec<u8> = px.iter().map(|p| p.valid).collect();
        let h16: Vec<SpvgTexel16> = px.iter().map(|p| t16(p.h)).collect();
        let h32: Vec<SpvgTexel32> = px.iter().map(|p| t32(p.h)).collect();
        let mut n16 = vec![0; px.len()];
        let mut n32 = vec![0; px.len()];
        estimate_frame(&c, &enc, &h16, &g, &v, &mut n16).unwrap();
        estimate_frame(&c, &enc, &h32, &g, &v, &mut n32).unwrap();
        for i in 0..px.len() {
            let want16 = c.estimate_with_validity(&enc.decode(h16[i]), g[i], v[i] != 0);
            let want32 = c.estimate_with_validity(&enc.decode(h32[i]), g[i], v[i] != 0);
            prop_assert_eq!(n16[i], want16, "f16 pixel {}", i);
            prop_assert_eq!(n32[i], want32, "f32 pixel {}", i);
        }
    }
}

#[test]
fn length_mismatch_is_an_error_and_writes_nothing() {
    let c = SpvgConfig::<f32>::published();
    let enc = TexelEncoding::new(c.target_variance()).unwrap();
    let one = [1.0_f32];
    let two = [1.0_f32, 1.0];
    let inputs = FrameInputs {
        radiance: &two,
        preintegrated: &one,
        gamma: &two,
        count: &[8, 8],
        valid: &[1, 1],
    };
    let mut h = [SpvgTexel16([f16::ONE; 4]); 2];
    let before = h;
    assert!(
        update_frame(
            &PixelController::new(c, As),
            &enc,
            Rounding::Nearest,
            &inputs,
            &mut h
        )
        .is_err(),
        "short preintegrated"
    );
    assert_eq!(h, before, "nothing written on error");
    let inputs = FrameInputs {
        preintegrated: &two,
        ..inputs
    };
    let mut j = [CvTexel16::default(); 1];
    let ocv = PixelController::new(c, Ocv::with_weight(0.1).unwrap());
    assert!(
        update_frame_ocv(&ocv, &enc, Rounding::Nearest, &inputs, &mut h, &mut j).is_err(),
        "short cv"
    );
    let mut counts = [0_u32; 1];
    assert!(
        estimate_frame(&c, &enc, &h, &two, &[1, 1], &mut counts).is_err(),
        "short counts"
    );
    let _ = <Ccv as ControlModel<f32>>::coefficient(&Ccv, &(), 0.0, 0.0);
}

#!/usr/bin/env python3
"""Writes the seed corpus of every fuzz target (fuzz/corpus/<target>/).

Float decoding (spvg::arbitrary, shared by every target): 8-byte little-endian chunks.
The low 4 bits of a chunk's first byte select the hard-case class (0 zero, 1 max, 2 min
normal, 3 min subnormal, 4-5 subnormal, 6 tiny, 7 huge, 8-9 near +-1, 10-11 moderate,
12-13 raw bits, 14 NaN, 15 inf); bit 4 is the sign. For weights the low 3 bits select:
0-1 exactly 1, 2-3 1e-7, 4 tiny, 5 just below 1, 6-7 uniform (bits >> 3 over 2^24).
`unit` values (fuzz/src/input.rs): low 3 bits 0 -> 0, 1 -> 1, 2 -> the special value,
else (bits >> 8) & 0xffffff over 2^24.

Per-target layouts are documented on the check functions in fuzz/src/<target>.rs; the
estimators layout: 8 bytes of weight bits, then the stream (8-byte chunks as f64, 4-byte
chunks as f32).

Run from anywhere: `python3 fuzz/seeds.py`. Deterministic. It (re)writes only the files
it names: the `regress_*` files in the corpora are fuzzer finds kept by hand (each named
in the commit that added it), and stay.

Fuzz a target: `cargo +nightly fuzz run <target> -- -max_total_time=30`; the stable
replay of every corpus is `cargo test -p spvg-fuzz`.
"""
import os
import random
import struct

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")
OUT = os.path.join(ROOT, "estimators")

def chunk(cls, sign=0, rnd=None):
    rnd = rnd or random.Random(cls * 31 + sign)
    first = (cls & 0xF) | (0x10 if sign else 0) | (rnd.randrange(8) << 5)
    return bytes([first]) + bytes(rnd.randrange(256) for _ in range(7))


def weight(cls, rnd):
    return bytes([cls | (rnd.randrange(32) << 3)]) + bytes(rnd.randrange(256) for _ in range(7))


def u64(v):
    return struct.pack("<Q", v & 0xFFFF_FFFF_FFFF_FFFF)


def uniform24(u, low):
    """A chunk whose uniform-in-(0,1] decoding is u (on the 2^-24 grid); `low` the class
    bits and the shift of the payload (3 for weights, 8 for unit values)."""
    cls, shift = low
    return u64((round(u * (1 << 24)) << shift) | cls)


def weight_exact(u):
    return uniform24(u, (6, 3))


def unit(u):
    return uniform24(u, (3, 8))


UNIT0, UNIT1, UNIT_SPECIAL = u64(0), u64(1), u64(2)
NAN, INF, NEG_INF, MAX, NEG_MAX, ZERO = (
    chunk(14), chunk(15, 0), chunk(15, 1), chunk(1, 0), chunk(1, 1), chunk(0, 0))


def budget(lo, hi):
    """Valid-range budget bits: min = 1 + (b & 63), max = min + ((b >> 8) & 127)."""
    return u64((lo - 1) | ((hi - lo) << 8))


def config(wild=0, eta=None, target=None, kappa=None, eps=UNIT_SPECIAL, bud=None, policy=0):
    rnd = random.Random(7)
    return (bytes([wild]) + (eta or weight_exact(0.2)) + (target or chunk(10, 0, rnd))
            + (kappa or unit(0.2)) + eps + (bud or budget(8, 64)) + u64(policy))


def controller_frame(sample, valid=True, gamma=UNIT1, override=None, corrupt=None, wild_gamma=False):
    flags = int(valid) | (2 if override is not None else 0) | (4 if corrupt else 0) | (8 if wild_gamma else 0)
    out = bytes([flags]) + sample + gamma
    if override is not None:
        out += bytes([override])
    if corrupt:
        out += b"".join(corrupt)
    return out


def controller_seeds(rnd):
    moderate = lambda: chunk(10 + rnd.randrange(2), rnd.randrange(2), rnd)
    steady = b"".join(controller_frame(moderate(), valid=k > 0, gamma=unit(rnd.random())) for k in range(32))
    return {
        "published_moderate": config() + steady,
        "nan_inf_samples_and_zero_counts": config()
        + b"".join(controller_frame(s, valid=v, override=o) for s, v, o in [
            (moderate(), False, None), (NAN, True, None), (INF, True, 0), (NEG_INF, False, None),
            (moderate(), True, 0), (moderate(), False, 0), (MAX, True, None), (NEG_MAX, True, 255)] * 2),
        "tiny_weight_huge_samples": config(eta=u64(2), target=chunk(6, 0, rnd), kappa=UNIT1)
        + b"".join(controller_frame(chunk(c, s, rnd)) for c, s in [(7, 0), (1, 1), (7, 1), (1, 0), (0, 0)] * 4),
        "weight_one_subnormal_samples": config(eta=u64(0), kappa=UNIT0, eps=UNIT0)
        + b"".join(controller_frame(chunk(c, s, rnd), gamma=g) for c, s, g in [
            (3, 0, UNIT1), (4, 1, UNIT0), (5, 0, UNIT_SPECIAL), (2, 1, unit(0.5)), (0, 1, UNIT1)] * 3),
        "wild_invalid_parameters": config(wild=0xFF, eta=NAN, target=NEG_INF, kappa=chunk(7, 0),
                                          eps=chunk(9, 1), bud=u64(1 << 63 | 5), policy=3)
        + steady[:40],
        "wild_valid_edge_parameters": config(wild=0x0F, eta=chunk(8, 1, random.Random(0)), target=chunk(2, 0),
                                             kappa=ZERO, eps=ZERO) + steady,
        "corrupt_history": config()
        + b"".join(controller_frame(moderate(), valid=True, corrupt=c) for c in [
            [NAN, NAN, NAN], [ZERO, INF, ZERO], [ZERO, ZERO, INF], [MAX, NEG_MAX, NEG_MAX], None, [chunk(3), chunk(4, 1), NAN]]),
        "two_phase": config(policy=1) + steady,
        "unreal_clamp_huge_budget": config(wild=0x10, bud=u64(1 << 63 | (0xFFFF_FFFF << 32) | 1), policy=2)
        + b"".join(controller_frame(chunk(c, 0, rnd)) for c in [7, 1, 10, 0, 7, 1]),
        "fixed_policy": config(policy=3 | (5 << 8)) + steady[:80],
        "wild_gamma": config()
        + b"".join(controller_frame(moderate(), gamma=g, wild_gamma=True) for g in [NAN, NEG_INF, INF, chunk(3), chunk(8, 0), chunk(0, 1)]),
        "raw_random": bytes(rnd.randrange(256) for _ in range(512)),
    }


def ocv(wild=0, eta=None, eps=None, a0=None):
    # eps_a: a finite chunk then a byte (bit 0 clear: the default 1e-6).
    eps = eps if eps is not None else chunk(10, 0) + b"\x00"
    return bytes([wild]) + (eta or weight_exact(0.05)) + eps + (a0 or unit(0.25))


def cv_frame(radiance, pre, gamma=UNIT1, valid=True, override=None, wild_gamma=False):
    flags = int(valid) | (2 if override is not None else 0) | (4 if wild_gamma else 0)
    out = bytes([flags]) + radiance + pre + gamma
    if override is not None:
        out += bytes([override])
    return out


def f64(v):
    """A chunk that decodes (as f64) to exactly v, through the moderate class 10:
    exponent 2^-20..2^20 from (r >> 52) % 41, mantissa from the low 52 bits of r = bits >> 5
    (the f32 decoding of the same bytes is another moderate value)."""
    if v == 0.0:
        return ZERO
    bits = struct.unpack("<Q", struct.pack("<d", abs(v)))[0]
    exp = (bits >> 52) - 1023
    assert -20 <= exp <= 20, v
    r = ((exp + 20) << 52) | (bits & ((1 << 52) - 1))
    return u64((r << 5) | (0x10 if v < 0 else 0) | 10)


def cv_seeds(rnd):
    flash = b"".join(
        cv_frame(f64(1.2 * (1.0 + 0.9 * ((t % 12) / 6.0 - 1.0)) + 0.01 * rnd.random()),
                 f64(1.0 + 0.9 * ((t % 12) / 6.0 - 1.0)), gamma=unit(0.5), valid=t > 0)
        for t in range(48))
    return {
        "flashing_light": config() + ocv() + flash,
        "hard_shadow": config() + ocv() + b"".join(cv_frame(ZERO, ZERO, valid=t > 0) for t in range(16)),
        "nan_inf_frames": config() + ocv()
        + b"".join(cv_frame(r, p, g, valid=v) for r, p, g, v in [
            (f64(1.0), f64(1.0), UNIT1, False), (NAN, f64(1.0), UNIT1, True), (f64(1.0), INF, UNIT1, True),
            (f64(1.0), f64(1.0), NAN, True), (INF, NEG_INF, UNIT1, False), (f64(2.0), f64(1.0), unit(0.5), True)]),
        "huge_and_max_luminance": config() + ocv()
        + b"".join(cv_frame(a, b, valid=t > 0) for t, (a, b) in enumerate([(MAX, MAX), (NEG_MAX, MAX), (chunk(7, 0), chunk(6, 0)), (MAX, chunk(3, 0))] * 3)),
        "negative_control_tiny_weight": config() + ocv(eta=u64(2), eps=ZERO + b"\x01", a0=UNIT0)
        + b"".join(cv_frame(f64(rnd.uniform(-3, 3)), f64(-rnd.uniform(0, 2)), unit(rnd.random())) for _ in range(24)),
        "weight_one_subnormal": config(eta=u64(0)) + ocv(eta=u64(0))
        + b"".join(cv_frame(chunk(4 + k % 2, k % 3 == 0, rnd), chunk(3, 0), gamma=UNIT_SPECIAL, override=k % 3) for k in range(12)),
        "invalid_ocv_parameters": config() + ocv(wild=7, eta=chunk(7, 0), eps=NEG_INF, a0=NAN) + flash[:200],
        "raw_random": bytes(rnd.randrange(256) for _ in range(512)),
    }


def burley_sample(xi, r0=ZERO, dz=ZERO, lighting=None, sub=True, wild_xi=False, wild_r0=False):
    flags = int(sub) | (2 if wild_xi else 0) | (4 if wild_r0 else 0)
    return bytes([flags]) + xi + r0 + dz + (lighting or f64(1.0))


def burley_head(sel, albedo, l):
    return bytes([sel]) + albedo + l


def burley_seeds(rnd):
    xis = [f64(v) for v in (1e-6, 0.25, 0.5, 0.5000000001, 0.9, 1 - 2**-20, 0.75)]
    xis += [chunk(6, 0, rnd), chunk(3, 0), chunk(8, 1, rnd), chunk(9, 1, rnd), chunk(2, 0)]
    sweep = b"".join(burley_sample(x, r0=f64(rnd.choice([0.0, 0.1, 2.0, 40.0])), dz=f64(rnd.uniform(0, 3)),
                                   lighting=f64(rnd.uniform(0, 4))) for x in xis)
    return {
        "skin_default_fit": burley_head(8, unit(0.44), f64(3.75)) + sweep,
        "searchlight_albedo_one": burley_head(0, UNIT1, f64(1.0)) + sweep,
        "transmission_albedo_zero": burley_head(4, UNIT0, f64(0.56)) + sweep,
        "huge_mean_free_path": burley_head(8, unit(0.8), MAX) + sweep,
        "min_normal_shape": burley_head(16, unit(0.5), chunk(2, 0)) + sweep,
        "subnormal_shape_rejected": burley_head(16 | 2, unit(0.5), chunk(3, 0)) + sweep,
        "invalid_albedo": burley_head(1, NAN, f64(1.0)) + sweep,
        "wild_xi_and_r0": burley_head(8, unit(0.6), f64(2.0))
        + b"".join(burley_sample(x, r0=r, wild_xi=True, wild_r0=True) for x, r in [
            (NAN, ZERO), (INF, f64(1.0)), (chunk(9, 0), INF), (ZERO, NAN), (chunk(8, 1), NEG_MAX), (chunk(3), MAX), (f64(0.5), chunk(7, 0))]),
        "edge_samples": burley_head(8, unit(0.3), f64(1.0))
        + b"".join(burley_sample(f64(0.5), r0=r, dz=dz, lighting=l, sub=s) for r, dz, l, s in [
            (ZERO, INF, NAN, True), (f64(1e3), ZERO, MAX, True), (ZERO, MAX, f64(1.0), True), (ZERO, ZERO, f64(1.0), False), (chunk(3), chunk(3), NEG_MAX, True)]),
        "raw_random": bytes(rnd.randrange(256) for _ in range(512)),
    }


def f32c(v):
    """A chunk that decodes (as f32) to exactly v through the moderate class 10 (exponent
    2^-20..2^20 from (r >> 23) % 41, mantissa from the low 23 bits of r = bits >> 5)."""
    if v == 0.0:
        return ZERO
    bits = struct.unpack("<I", struct.pack("<f", abs(v)))[0]
    exp = (bits >> 23) - 127
    assert -20 <= exp <= 20, v
    r = ((exp + 20) << 23) | (bits & ((1 << 23) - 1))
    return u64((r << 5) | (0x10 if v < 0 else 0) | 10)


def texel_head(sel=0, target=None, cv=None, seed=0x1234_5678, deviation=None, hists=None, corrupt=None):
    hists = hists or [[f32c(0.75), f32c(3e-4), f32c(24.0)] + [f32c(2e-6), f32c(1e-6), f32c(1.5), f32c(0.5)]] * 4
    corrupt = corrupt or (u64(0x7C00_FC00_7E00_3C00) + u64(0x7F80_0000_FF80_0000) + u64(0x7FC0_0000_BF80_0000))
    return (bytes([sel]) + (target or f32c(1e-4)) + (cv or f32c(1e-6 * 4096)) + u64(seed)
            + (deviation or f32c(0.1)) + b"".join(b"".join(h) for h in hists) + corrupt)


def texel_pixel(radiance, pre, gamma=UNIT1, count=8, valid=True, wild_gamma=False, hist=None, cv=None):
    flags = int(valid) | (2 if wild_gamma else 0)
    hist = hist or [f32c(1.0), f32c(1e-4), f32c(16.0)]
    cv = cv or [f32c(1e-6), f32c(2e-6), f32c(1.0), f32c(1.0)]
    return bytes([flags, count]) + radiance + pre + gamma + b"".join(hist) + b"".join(cv)


def texel_seeds(rnd):
    tail = config() + ocv()
    moderate = lambda: f32c(rnd.uniform(0.1, 4.0))
    frame = lambda n: b"".join(
        texel_pixel(moderate(), moderate(), unit(rnd.random()), count=rnd.choice([0, 8, 17, 64]),
                    valid=rnd.random() < 0.8,
                    hist=[moderate(), f32c(rnd.uniform(1e-5, 1e-2)), f32c(rnd.uniform(8, 64))])
        for _ in range(n))
    bad = [NAN, INF, NEG_INF, MAX, NEG_MAX, chunk(7, 0), chunk(7, 1), chunk(3, 0), chunk(4, 1), ZERO, chunk(0, 1)]
    nasty = [[bad[(k + i) % len(bad)] for i in range(7)] for k in range(4)]
    small = [[f32c(v) for v in (2**-20, 2**-19, 3.0, 2**-18, 2**-20, 6e-5, -6e-5)],
             [f32c(v) for v in (65504.0, 65520.0, 65536.0, 1e5, 7e4, -65519.0, 1e6)],
             [chunk(3), chunk(4), chunk(5), chunk(2), chunk(6, 1), chunk(3, 1), chunk(2, 1)],
             [f32c(v) for v in (1.0 + 2**-12, 1.0 - 2**-13, 1.5 + 2**-12, 0.1, 0.2, 0.3, 3e-5)]]
    return {
        "published_nearest_as": texel_head() + tail + frame(12),
        "stochastic_ccv": texel_head(sel=4 | 8) + tail + frame(12),
        "ocv_stochastic_two_chunks": texel_head(sel=4 | 16) + tail + frame(70),
        "nan_inf_histories_ocv": texel_head(sel=16, hists=nasty) + tail
        + b"".join(texel_pixel(r, p, g, count=c, valid=v, wild_gamma=w, hist=nasty[k % 4][:3], cv=nasty[k % 4][3:])
                   for k, (r, p, g, c, v, w) in enumerate([
                       (NAN, f32c(1.0), UNIT1, 8, True, False), (INF, NEG_INF, UNIT1, 8, True, False),
                       (MAX, MAX, UNIT1, 64, True, False), (f32c(1.0), f32c(1.0), NAN, 8, True, True),
                       (f32c(2.0), chunk(3), UNIT0, 0, False, False), (NEG_MAX, f32c(1.0), unit(0.5), 255, False, False)])),
        "subnormal_and_saturating_stochastic": texel_head(sel=4, hists=small, target=f32c(2**-20)) + tail + frame(4),
        "rounding_ties_nearest": texel_head(hists=small[::-1], seed=0xFFFF_FFFF) + tail + frame(3),
        "rejected_scales": texel_head(sel=3, target=NAN, cv=chunk(7, 0), deviation=NEG_INF) + tail + frame(2),
        "huge_target_tiny_cv_scale": texel_head(sel=3, target=chunk(7, 0), cv=chunk(6, 0)) + tail + frame(2),
        "wild_config_zero_deviation": texel_head(deviation=ZERO) + config(wild=0x0F, eta=u64(2)) + ocv(eta=u64(2)) + frame(8),
        # eps_a = 0 with var_g = 0 and cov_fg > 0: the OCV ratio overflows at moderate
        # luminance (Ocv saturates it; the frame functions of branch texel took 1).
        "ocv_eps_a_zero_moderate": texel_head(sel=16) + config() + ocv(eps=ZERO + b"\x01")
        + b"".join(texel_pixel(f32c(1.5 + 0.1 * k), f32c(1.0), unit(0.5), count=16,
                               cv=[f32c(1e-3), ZERO, f32c(1.0), f32c(0.5)]) for k in range(4)),
        "raw_random": bytes(rnd.randrange(256) for _ in range(1024)),
    }


def estimators_seeds(rnd):
    return {
        "empty": b"",
        "nan_inf_small_weight": weight(2, rnd)
        + b"".join(chunk(c, s, rnd) for c, s in [(10, 0), (14, 0), (15, 0), (15, 1), (7, 0), (1, 1), (10, 1)]),
        "subnormal_tiny_weight": weight(4, rnd)
        + b"".join(chunk(c, s, rnd) for c, s in [(3, 0), (4, 1), (5, 0), (0, 1), (2, 0), (6, 1)] * 3),
        "huge_weight_one": weight(0, rnd)
        + b"".join(chunk(c, s, rnd) for c, s in [(1, 0), (1, 1), (7, 0), (7, 1), (1, 0)] * 2),
        "near_one_weight_below_one": weight(5, rnd)
        + b"".join(chunk(c, s, rnd) for c, s in [(8, 0), (9, 0), (8, 1), (9, 1)] * 4),
        "alternating_extremes": weight(6, rnd)
        + b"".join(chunk(c, s, rnd) for c, s in [(1, 0), (3, 1), (1, 1), (0, 0), (7, 0), (6, 0)] * 4),
        "moderate_long": weight(7, rnd) + b"".join(chunk(10 + rnd.randrange(2), rnd.randrange(2), rnd) for _ in range(64)),
        "raw_random": bytes(rnd.randrange(256) for _ in range(256)),
    }


TARGETS = {
    # The estimators seeds come first from one generator, as before this file covered
    # more targets, so their bytes do not change.
    "estimators": estimators_seeds,
    "controller": controller_seeds,
    "control_variates": cv_seeds,
    "burley": burley_seeds,
    "texel": texel_seeds,
}


def main():
    rnd = random.Random(20261122)
    for target, make in TARGETS.items():
        out = os.path.join(ROOT, target)
        os.makedirs(out, exist_ok=True)
        for name, data in make(rnd).items():
            with open(os.path.join(out, name), "wb") as f:
                f.write(data)


if __name__ == "__main__":
    main()

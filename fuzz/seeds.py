#!/usr/bin/env python3
"""Writes the seed corpus of the `estimators` fuzz target (fuzz/corpus/estimators/).

Input layout (see spvg_fuzz::check_estimators): 8 bytes of weight bits, then the stream,
decoded by spvg::arbitrary in 8-byte chunks (f64) and 4-byte chunks (f32). The low 4 bits
of a chunk's first byte select the hard-case class (0 zero, 1 max, 2 min normal,
3 min subnormal, 4-5 subnormal, 6 tiny, 7 huge, 8-9 near +-1, 10-11 moderate, 12-13 raw
bits, 14 NaN, 15 inf); bit 4 is the sign. For weights the low 3 bits select: 0-1 exactly
1, 2-3 1e-7, 4 tiny, 5 just below 1, 6-7 uniform.
"""
import os
import random

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "estimators")


def chunk(cls, sign=0, rnd=None):
    rnd = rnd or random.Random(cls * 31 + sign)
    first = (cls & 0xF) | (0x10 if sign else 0) | (rnd.randrange(8) << 5)
    return bytes([first]) + bytes(rnd.randrange(256) for _ in range(7))


def weight(cls, rnd):
    return bytes([cls | (rnd.randrange(32) << 3)]) + bytes(rnd.randrange(256) for _ in range(7))


def main():
    rnd = random.Random(20261122)
    os.makedirs(OUT, exist_ok=True)
    seeds = {
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
    for name, data in seeds.items():
        with open(os.path.join(OUT, name), "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main()

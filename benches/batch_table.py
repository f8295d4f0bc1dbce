#!/usr/bin/env python3
"""Turns criterion's estimates of `cargo bench --bench batch` into markdown tables.

Usage: python3 benches/batch_table.py [CRITERION_DIR]   (default: target/criterion)
       python3 benches/batch_table.py PORTABLE_DIR NATIVE_DIR

With two directories (the portable and the `-C target-cpu=native` build's criterion
output of one run, see benches/native_vs_portable.sh), it prints each build's table and
then one table of native / portable time ratios per benchmark both measured. A directory
may hold several runs of a benchmark (the rounds of native_vs_portable.sh): their median
is used.

For each resolution: ns per pixel (criterion's median over the frame / pixels), GB/s of
history and input traffic (bytes read + written per pixel / ns per pixel), the fraction
of the copy bandwidth (copy time of the same bytes / update time: 1.0 = as fast as the
copy), for the threaded variants the same against the copy split over as many threads
(`copy/parallel`, what the memory system gives them), and the speed-up over the scalar
loop of the same layout. Every ratio is between figures of the same run.
"""

import json
import os
import statistics
import sys

PIXELS = {"1080p": 1920 * 1080, "2160p": 3840 * 2160}
INPUTS = 4 * 4 + 1  # radiance, preintegrated, gamma, count (f32/u32) and valid (u8)

# History bytes per pixel, read once and written once, and the copy that moves as much.
HISTORY = {
    ("as", "f16"): (8, "h16"),
    ("as", "f16-sr"): (8, "h16"),
    ("as", "f32"): (16, "h16+j16"),
    ("ccv", "f16"): (8, "h16"),
    ("ccv", "f32"): (16, "h16+j16"),
    ("ocv", "f16"): (16, "h16+j16"),
    ("ocv", "f16-sr"): (16, "h16+j16"),
    ("ocv", "f32"): (32, "h32+j32"),
}
COPY = {"h16": 8, "h16+j16": 16, "h32+j32": 32}


def traffic(model, kind, layout):
    if model == "copy":
        return 2 * COPY[layout] + INPUTS
    if model == "estimate":
        # History, gamma and valid read; a u32 count written.
        return (8 if layout == "f16" else 16) + 4 + 1 + 4
    return 2 * HISTORY[(model, layout)][0] + INPUTS


def load(root):
    """Criterion's median time of every benchmark under `root`; where `root` holds several
    runs of a benchmark (the rounds of benches/native_vs_portable.sh), their median."""
    runs = {}
    for dirpath, _, files in os.walk(root):
        if "benchmark.json" not in files or not dirpath.endswith("new"):
            continue
        with open(os.path.join(dirpath, "benchmark.json")) as f:
            bench = json.load(f)
        with open(os.path.join(dirpath, "estimates.json")) as f:
            est = json.load(f)
        key = (bench["group_id"], bench["function_id"], bench["value_str"])
        runs.setdefault(key, []).append(est["median"]["point_estimate"])
    return {key: statistics.median(times) for key, times in runs.items()}


def main():
    roots = sys.argv[1:] or ["target/criterion"]
    for root in roots:
        if len(roots) > 1:
            print(f"\n## {root}")
        table(load(root))
    if len(roots) == 2:
        compare(load(roots[0]), load(roots[1]))


def compare(portable, native):
    """Portable time over native time for every benchmark of both runs."""
    print("\n## portable / native (1.00 = as fast; above 1 the portable build is slower)\n")
    print("| benchmark | portable ms | native ms | portable / native |")
    print("|---|---|---|---|")
    for key in sorted(k for k in portable if k in native):
        group, name, layout = key
        p, q = portable[key] / 1e6, native[key] / 1e6
        print(f"| {group.removeprefix('frame_update_')} {name} {layout} | {p:.2f} | {q:.2f} | {p / q:.2f} |")


def table(times):
    for res, n in PIXELS.items():
        group = f"frame_update_{res}"
        rows = sorted(k for k in times if k[0] == group)
        if not rows:
            continue
        print(f"\n{res} ({n} pixels)\n")
        print("| benchmark | ns/px | bytes/px | GB/s | of copy bandwidth | of threaded copy | vs scalar |")
        print("|---|---|---|---|---|---|---|")
        for key in rows:
            _, name, layout = key
            model, kind = (name, "") if name == "copy" else name.split("/", 1)
            ns = times[key] / n
            b = traffic(model, kind, layout)
            copy = threaded = ""
            if model not in ("copy", "estimate") and kind != "scalar":
                ck = (group, "copy", HISTORY[(model, layout)][1])
                if ck in times:
                    copy = f"{times[ck] / times[key]:.2f}"
                tk = (group, "copy/parallel", HISTORY[(model, layout)][1])
                if kind == "parallel" and tk in times:
                    threaded = f"{times[tk] / times[key]:.2f}"
            speed = ""
            sk = (group, f"{model}/scalar", layout.removesuffix("-sr"))
            if kind in ("batch", "parallel") and sk in times:
                speed = f"{times[sk] / times[key]:.1f}x"
            print(f"| {name} {layout} | {ns:.2f} | {b} | {b / ns:.2f} | {copy} | {threaded} | {speed} |")


if __name__ == "__main__":
    main()

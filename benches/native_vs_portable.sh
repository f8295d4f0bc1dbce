#!/usr/bin/env bash
# One side-by-side run of the frame-update benchmarks at 1080p: the portable build
# (run-time CPU dispatch) and a `-C target-cpu=native` build, interleaved benchmark by
# benchmark so that both see the same machine load, then the tables and the ratios.
#
# Usage: [ROUNDS=N] bash benches/native_vs_portable.sh [FILTER]
#   FILTER: a criterion regex (default: the 1080p AS/OCV f16 updates, scalar loops and
#   copies that the acceptance figures need, and the copies split over the threads of the
#   parallel variants).
#   ROUNDS: how many times the interleaved pass runs (default 1); the tables take each
#   benchmark's median over the rounds (of criterion's medians), which damps what other
#   processes on a shared machine do to single benchmarks.
#   PORTABLE_RUSTFLAGS: RUSTFLAGS for the "portable" build (built in target/portable-flags
#   then); for the AVX-512 width question, "-C target-feature=+prefer-256-bit" keeps the
#   AVX-512 variant's loops in 256-bit registers (see BENCHMARKS.md, "AVX-512").
#   SPVG_MAX_LOOP_VARIANT (as-compiled, avx2, avx512): passed on to both binaries, it caps
#   the variant the portable build's dispatch takes (the native build has none).
# First it prints the CPU model, its x86-64 level and the loop variant each build runs
# (examples/loop_variant.rs).
set -euo pipefail
cd "$(dirname "$0")/.."
filter=${1:-'frame_update_1080p/(copy/(parallel/)?(h16|h16\+j16)|(as|ocv)/(batch|parallel|scalar)/f16)$'}

bench_exe() { # prints the path of the batch bench binary of a build
    "$@" cargo bench --bench batch --no-run --message-format=json 2>/dev/null |
        python3 -c 'import json,sys
for l in sys.stdin:
    m = json.loads(l)
    if m.get("reason") == "compiler-artifact" and m["target"]["name"] == "batch" and m.get("executable"):
        print(m["executable"])'
}
variant_exe() { # builds examples/loop_variant for a build and prints its path
    "$@" cargo build --release --example loop_variant --message-format=json 2>/dev/null |
        python3 -c 'import json,sys
for l in sys.stdin:
    m = json.loads(l)
    if m.get("reason") == "compiler-artifact" and m["target"]["name"] == "loop_variant" and m.get("executable"):
        print(m["executable"])'
}
if [ -n "${PORTABLE_RUSTFLAGS:-}" ]; then
    portable_env=(env RUSTFLAGS="$PORTABLE_RUSTFLAGS" CARGO_TARGET_DIR=target/portable-flags)
else
    portable_env=(env)
fi
native_env=(env RUSTFLAGS="-C target-cpu=native" CARGO_TARGET_DIR=target/native)
portable=$(bench_exe "${portable_env[@]}")
native=$(bench_exe "${native_env[@]}")
model=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -n 1)
echo "CPU: ${model:-unknown} ($(nproc) logical cores)"
echo "portable build${PORTABLE_RUSTFLAGS:+ (RUSTFLAGS=$PORTABLE_RUSTFLAGS)}:"
"$(variant_exe "${portable_env[@]}")" | sed 's/^/  /'
echo "native build (-C target-cpu=native):"
"$(variant_exe "${native_env[@]}")" | sed 's/^/  /'
echo "SPVG_MAX_LOOP_VARIANT=${SPVG_MAX_LOOP_VARIANT:-(unset)}"
echo
out=target/native-vs-portable
rm -rf "$out"
# Interleave: in each round, each benchmark id is run by the portable, then the native
# binary.
ids=$("$portable" --bench --list "$filter" 2>/dev/null | sed -n 's/: benchmark$//p')
for round in $(seq "${ROUNDS:-1}"); do
    for id in $ids; do
        exact="^${id//+/\\+}\$"
        CRITERION_HOME="$out/portable/$round" "$portable" --bench "$exact" >/dev/null
        CRITERION_HOME="$out/native/$round" "$native" --bench "$exact" >/dev/null
    done
done
python3 benches/batch_table.py "$out/portable" "$out/native"

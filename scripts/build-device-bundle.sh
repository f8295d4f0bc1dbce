#!/usr/bin/env bash
# Builds what scripts/device-check.sh runs on a machine without a Rust toolchain: stripped
# release binaries, the GPU test binaries, and the Vulkan loader as a Debian package, in
# device-bundle/ (ignored by git; carry it with the working tree). Prints the bundle's size,
# which must stay well under the 64 MiB a carried working tree may hold.
#
# Usage: bash scripts/build-device-bundle.sh
#   BUNDLE: output folder (default device-bundle)
#   SPVG_BUNDLE_TESTS: space-separated "crate:test" GPU test targets to carry (default: the
#     component's and the effects' tests against their twins and the classified dispatch)
#   SPVG_BUNDLE_SKIP_CPU=1: leave out the three frame-update benchmark builds.
# Needs cargo, strip and xz here; apt-get (or a cached .deb) for the Vulkan loader.
set -euo pipefail
cd "$(dirname "$0")/.."
bundle=${BUNDLE:-device-bundle}
tests=${SPVG_BUNDLE_TESTS:-"spvg-wgpu:adaptive spvg-wgpu:classified spvg-wgpu:guide spvg-wgpu:reprojected_depth spvg-wgpu:adaptive_tiles spvg-effects:classified spvg-effects:ao spvg-effects:determinism spvg-effects:sss_consumer"}
rm -rf "$bundle"
mkdir -p "$bundle/bin" "$bundle/tests" "$bundle/debs"

# The executables a cargo command built (its JSON messages), one per line.
executables() {
    python3 -c 'import json,sys
for l in sys.stdin:
    try:
        m = json.loads(l)
    except ValueError:
        continue
    if m.get("reason") == "compiler-artifact" and m.get("executable"):
        print(m["target"]["name"], m["executable"])'
}
carry() { # carry NAME PATH DIR: a stripped copy
    cp "$2" "$3/$1"
    strip "$3/$1"
}

echo "== report binaries (whatever spvg-report builds: spvg-gpu-readiness, spvg-report, ...)"
cargo build --locked --release -p spvg-report --bins --message-format=json 2>/dev/null |
    executables | while read -r name path; do carry "$name" "$path" "$bundle/bin"; done
echo "== spvg-effects examples"
cargo build --locked --release -p spvg-effects --examples --message-format=json 2>/dev/null |
    executables | while read -r name path; do
        case $name in time_follows_samples | step_costs) carry "$name" "$path" "$bundle/bin" ;; esac
    done

echo "== GPU tests (release, --no-run)"
for t in $tests; do
    crate=${t%%:*}
    test=${t#*:}
    cargo test --locked --release -p "$crate" --test "$test" --no-run --message-format=json 2>/dev/null |
        executables | while read -r name path; do
            if [ "$name" = "$test" ]; then carry "$crate--$test" "$path" "$bundle/tests"; fi
        done
done

if [ "${SPVG_BUNDLE_SKIP_CPU:-0}" != 1 ]; then
    # The core's frame-update benchmark: the portable build (run-time dispatch over the
    # as-compiled, AVX2 and AVX-512 loops), and two fixed-target builds standing in for
    # `-C target-cpu=native` on a machine where nothing can be compiled: x86-64-v3 (AVX2)
    # and x86-64-v4 (AVX-512; run only where the CPU has it).
    for flavour in portable v3 v4; do
        echo "== frame-update benchmark: $flavour"
        case $flavour in
            portable) env=(env) ;;
            # --target: the flags apply to the benchmark, not to the build scripts and
            # proc macros that run here (an x86-64-v4 build script dies on a CPU without
            # AVX-512).
            *) env=(env RUSTFLAGS="-C target-cpu=x86-64-$flavour" CARGO_TARGET_DIR="target/device-$flavour") ;;
        esac
        target=()
        [ "$flavour" != portable ] && target=(--target "$(rustc -vV | sed -n 's/^host: //p')")
        "${env[@]}" cargo bench --locked "${target[@]}" --bench batch --no-run --message-format=json 2>/dev/null |
            executables | while read -r name path; do
                if [ "$name" = batch ]; then carry "batch-$flavour" "$path" "$bundle/bin"; fi
            done
        "${env[@]}" cargo build --locked "${target[@]}" --release --example loop_variant --message-format=json 2>/dev/null |
            executables | while read -r name path; do
                if [ "$name" = loop_variant ]; then carry "loop_variant-$flavour" "$path" "$bundle/bin"; fi
            done
    done
fi

echo "== Vulkan loader (Debian package, unpacked on the device if it has none)"
deb=$(ls /var/cache/apt/archives/libvulkan1_*_amd64.deb 2>/dev/null | head -n 1 || true)
if [ -n "$deb" ]; then
    cp "$deb" "$bundle/debs/"
else
    (cd "$bundle/debs" && apt-get download libvulkan1 >/dev/null 2>&1) ||
        echo "warning: libvulkan1 not downloaded: the device must have a Vulkan loader"
fi

# Compress the binaries: the bundle travels with the working tree.
tar -C "$bundle" -cf - bin tests | xz -T0 -6 >"$bundle/binaries.tar.xz"
rm -rf "$bundle/bin" "$bundle/tests"
{
    echo "commit: $(git rev-parse HEAD)$(git diff --quiet HEAD || echo ' (with uncommitted changes)')"
    echo "built: $(date -u +%Y-%m-%dT%H:%M:%SZ) on $(uname -m)"
    echo "rustc: $(rustc --version)"
    echo "tests: $tests"
} >"$bundle/MANIFEST"
ls -l "$bundle" "$bundle/debs"
echo "bundle size: $(du -sh "$bundle" | cut -f1)"

#!/usr/bin/env bash
# The checks a machine with a hardware GPU runs in one go, from the prebuilt binaries of
# scripts/build-device-bundle.sh (no Rust toolchain needed): the GPU tests, the
# GPU-readiness table (estimate and update against a copy kernel), the time-follows-samples
# lines (subsurface and AO, classified dispatch off and on) at 1080p and 2160p, the hybrid
# pass's per-pass times, and on the CPU the core's frame-update benchmark, portable against
# fixed-target builds, with the CPU's AVX-512 flags recorded. Each result is a file in the
# output folder; summary.md lists what ran, how long it took and how it ended.
#
# Usage: bash scripts/device-check.sh [OUT_DIR]      (default out-device)
#   BUNDLE: the bundle folder (default device-bundle)
#   SPVG_DEVICE_QUICK=1: small sizes and few frames (a check of the script itself on a
#     software adapter, where the full sizes take far longer than a GPU needs)
#   SPVG_DEVICE_BUDGET_S: seconds the whole run may take (default 450, under 8 minutes);
#     each step gets a share and is stopped at it
set -uo pipefail
cd "$(dirname "$0")/.."
bundle=${BUNDLE:-device-bundle}
out=${1:-out-device}
quick=${SPVG_DEVICE_QUICK:-0}
budget=${SPVG_DEVICE_BUDGET_S:-450}
start=$(date +%s)
mkdir -p "$out"
summary="$out/summary.md"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

if [ ! -f "$bundle/binaries.tar.xz" ]; then
    echo "device-check: $bundle/binaries.tar.xz is missing: run scripts/build-device-bundle.sh" >&2
    exit 2
fi
xz -dc "$bundle/binaries.tar.xz" | tar -C "$work" -xf -
bin=$work/bin

# The Vulkan loader: the system's, else the carried Debian package unpacked here.
if ! ldconfig -p 2>/dev/null | grep -q 'libvulkan\.so\.1'; then
    for deb in "$bundle"/debs/libvulkan1_*.deb; do
        [ -f "$deb" ] || continue
        mkdir -p "$work/root"
        if command -v dpkg-deb >/dev/null; then
            dpkg-deb -x "$deb" "$work/root"
        else # a .deb is an ar archive holding data.tar.*
            (cd "$work/root" && ar x "$deb" && tar -xf data.tar.* && rm -f data.tar.* control.tar.* debian-binary)
        fi
        export LD_LIBRARY_PATH="$work/root/usr/lib/x86_64-linux-gnu${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
        echo "Vulkan loader: unpacked from $(basename "$deb")" >>"$out/environment.txt"
    done
fi
# The NVIDIA driver's Vulkan ICD: containers often carry the driver's libraries without
# its ICD file; point the loader at libGLX_nvidia.so.0 then.
icd_dirs="/usr/share/vulkan/icd.d /etc/vulkan/icd.d /usr/local/share/vulkan/icd.d"
if ! ls $icd_dirs 2>/dev/null | grep -q -i nvidia && ldconfig -p 2>/dev/null | grep -q 'libGLX_nvidia\.so\.0'; then
    mkdir -p "$work/icd"
    printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "libGLX_nvidia.so.0", "api_version": "1.3"}}\n' >"$work/icd/nvidia_icd.json"
    export VK_ICD_FILENAMES="$work/icd/nvidia_icd.json"
    echo "Vulkan ICD: written for libGLX_nvidia.so.0 (none installed)" >>"$out/environment.txt"
fi
# Mesa's device-select layer probes Wayland and prints errors without a session.
export NODEVICE_SELECT=1

{
    echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
    echo "bundle: $(tr '\n' ';' <"$bundle/MANIFEST" 2>/dev/null)"
    echo "kernel: $(uname -sr)"
    echo "cpu: $(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -n 1) ($(nproc) logical cores)"
    avx512=$(grep -o -w 'avx512[a-z0-9_]*' /proc/cpuinfo | sort -u | tr '\n' ' ')
    echo "avx512 flags: ${avx512:-none}"
    command -v nvidia-smi >/dev/null &&
        nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader
    command -v vulkaninfo >/dev/null && vulkaninfo --summary 2>/dev/null | grep -E 'deviceName|driverName|apiVersion'
} >>"$out/environment.txt" 2>&1
lscpu >"$out/lscpu.txt" 2>&1 || true
has_avx512=0
grep -q -w avx512f /proc/cpuinfo && has_avx512=1

printf '# Device check\n\n' >"$summary"
printf '| step | seconds | exit | output |\n| --- | --- | --- | --- |\n' >>"$summary"

# step NAME SHARE_S FILE COMMAND...: runs COMMAND with its output in FILE, stopped after
# SHARE_S seconds or what is left of the budget, and adds a row to the summary.
step() {
    local name=$1 share=$2 file=$3
    shift 3
    local left=$((budget - ($(date +%s) - start)))
    [ "$share" -gt "$left" ] && share=$left
    if [ "$share" -le 5 ]; then
        printf '| %s | 0 | skipped: out of time | |\n' "$name" >>"$summary"
        return
    fi
    local t0
    t0=$(date +%s)
    echo "== $name (up to ${share}s)"
    timeout --kill-after=10 "$share" "$@" >"$out/$file" 2>&1
    local rc=$?
    [ "$rc" = 124 ] && rc="124 (stopped at ${share}s)"
    printf '| %s | %s | %s | %s |\n' "$name" "$(($(date +%s) - t0))" "$rc" "$file" >>"$summary"
}

if [ "$quick" = 1 ]; then
    sizes=("480 270")
    frames=6 warmup=2 readiness_frames=2
    sss_ms=${SSS_MS:-100} ao_ms=${AO_MS:-400} low_ms=5 governor_frames=40
else
    sizes=("1920 1080" "3840 2160")
    frames=12 warmup=4 readiness_frames=10
    sss_ms=${SSS_MS:-1.5} ao_ms=${AO_MS:-3} low_ms=0.01 governor_frames=60
fi

# 1. The GPU tests that need an adapter: a missing one fails them.
for t in "$work"/tests/*; do
    [ -x "$t" ] || continue
    # 90 s each; the effects' determinism test also runs the AO twin on the CPU: 150 s.
    share=90
    case $t in *determinism) share=150 ;; esac
    step "test $(basename "$t")" "$share" "test-$(basename "$t").txt" env SPVG_REQUIRE_GPU=1 "$t" --test-threads=1
done

# 2. GPU readiness: the binary, or the report's subcommand if the report took it over.
if [ -x "$bin/spvg-gpu-readiness" ]; then
    step "gpu readiness" 120 gpu-readiness.txt "$bin/spvg-gpu-readiness" --frames "$readiness_frames" --out "$out/gpu-readiness"
elif [ -x "$bin/spvg-report" ] && "$bin/spvg-report" --help 2>/dev/null | grep -q 'gpu-readiness'; then
    step "gpu readiness" 120 gpu-readiness.txt "$bin/spvg-report" gpu-readiness --frames "$readiness_frames" --out "$out/gpu-readiness"
else
    printf '| gpu readiness | 0 | skipped: no binary in the bundle | |\n' >>"$summary"
fi

# 2b. Where the component's time goes: its steps under one rule switched at a time.
if [ -x "$bin/step_costs" ]; then
    for s in "${sizes[@]}"; do
        set -- $s
        step "step costs ${1}x${2}" 60 "step-costs-${1}x${2}.txt" "$bin/step_costs" --width "$1" --height "$2" --frames "$readiness_frames"
    done
fi

# 3. Time follows samples, classified dispatch off and on.
for s in "${sizes[@]}"; do
    set -- $s
    step "time follows samples ${1}x${2}" 150 "time-follows-samples-${1}x${2}.txt" \
        "$bin/time_follows_samples" --width "$1" --height "$2" --frames "$frames" --warmup "$warmup" \
        --fixed 1 --csv "$out/time-follows-samples-${1}x${2}.csv"
done

# 4. CPU: the frame-update benchmark, portable (run-time dispatch) against the fixed-target
#    builds; on an AVX-512 CPU also the portable build capped at AVX2.
filter='frame_update_1080p/(copy/(h16|h16\+j16)|(as|ocv)/(batch|parallel|scalar)/f16)$'
crit=(--warm-up-time 0.5 --measurement-time 1 --noplot)
[ "$quick" = 1 ] && crit=(--warm-up-time 0.2 --measurement-time 0.5 --noplot)
for v in portable v3 v4; do
    [ -x "$bin/loop_variant-$v" ] || continue
    [ "$v" = v4 ] && [ "$has_avx512" = 0 ] && continue
    "$bin/loop_variant-$v" >"$out/loop-variant-$v.txt" 2>&1
    step "frame update $v" 60 "frame-update-$v.txt" env CRITERION_HOME="$work/criterion-$v" \
        "$bin/batch-$v" --bench "$filter" "${crit[@]}"
done
if [ "$has_avx512" = 1 ] && [ -x "$bin/batch-portable" ]; then
    step "frame update portable capped at avx2" 60 frame-update-portable-avx2.txt \
        env SPVG_MAX_LOOP_VARIANT=avx2 CRITERION_HOME="$work/criterion-cap" \
        "$bin/batch-portable" --bench "$filter" "${crit[@]}"
fi

# 5. The frame-time governor: the subsurface sampling pass on flash and switch, the AO
#    frame on a pan, each steered to a target in ms (SSS_MS, AO_MS), and one target below
#    the least count's time (the unreachable case): the report's `governor` subcommand,
#    whose device run these flags set (its judged lines run on the CPU twin's cost model,
#    the same on every machine: exit status 2 when one fails is not this step's failure).
if [ -x "$bin/spvg-report" ] && "$bin/spvg-report" --help 2>/dev/null | grep -q 'governor'; then
    for s in "${sizes[@]}"; do
        set -- $s
        for run in "sss flash $sss_ms" "sss switch $sss_ms" "ao pan $ao_ms" "sss static $low_ms"; do
            set -- $s $run
            step "frame-time governor $3 $4 ${1}x${2} ${5} ms" 45 "governor-$3-$4-${1}x${2}-${5}ms.txt" \
                sh -c '"$@"; rc=$?; [ "$rc" = 2 ] && rc=0; exit "$rc"' governor \
                "$bin/spvg-report" governor --effect "$3" --scene "$4" --target-ms "$5" --width "$1" --height "$2" \
                --frames "$governor_frames" --out "$out/governor-$3-$4-${1}x${2}-${5}ms"
        done
    done
else
    printf '| frame-time governor | 0 | skipped: not in the bundle | |\n' >>"$summary"
fi

# 6. The subsurface pass's steps timed apart at 1920x1080, and the separable section with
#    its timing rows (the hybrid pass's work in ms): the report's subcommands, or the older
#    spvg-separable binary.
if [ "$quick" != 1 ]; then
    if [ -x "$bin/spvg-report" ] && "$bin/spvg-report" --help 2>/dev/null | grep -q 'pass-breakdown'; then
        step "pass breakdown 1920x1080" 60 pass-breakdown.txt "$bin/spvg-report" pass-breakdown --out "$out/pass-breakdown"
        step "separable / hybrid (--full)" 60 separable.txt "$bin/spvg-report" separable --full --out "$out/separable"
    elif [ -x "$bin/spvg-separable" ]; then
        step "separable / hybrid (--full)" 60 separable.txt "$bin/spvg-separable" --full --out "$out/separable"
    fi
fi

total=$(($(date +%s) - start))
printf '\nTotal: %s s (budget %s s).\n' "$total" "$budget" >>"$summary"
cat "$summary"
# Exit 1 when a step failed (a test, a stopped step), so a caller sees it.
! grep -q -E '^\| [^|]+ \| [0-9]+ \| [1-9]' "$summary"

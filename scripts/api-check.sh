#!/usr/bin/env bash
# The public API of the published crates (spvg, spvg-shaders, spvg-wgpu) against its
# recorded listing, api/<crate>.txt: one sorted line per public item (path, kind, and the
# signature of functions, the types of fields and constants, the traits each type
# implements), made by scripts/api-listing.py from rustdoc's JSON output.
#
#   scripts/api-check.sh               check: exit 1, naming the lines added and removed,
#                                      when a listing differs from the recorded one
#   scripts/api-check.sh --bless       rewrite api/*.txt from the sources
#   scripts/api-check.sh --since REV   also fail when api/ changed since REV (its merge
#                                      base with HEAD) and CHANGELOG.md did not
#
# A change of the public API goes with a CHANGELOG.md entry ([Unreleased]; a **Migration**
# line where it breaks callers) and the re-blessed listing, in the same change; CI
# (.ci/run) runs the check. The listing is no semver judgement: any difference needs a
# look, and an entry where a caller can notice it.
#
# rustdoc's JSON output is unstable (`-Z unstable-options`). It is made with the pinned
# toolchain (rust-toolchain.toml), so its format moves only with the pin (api-listing.py
# checks the format version), through a rustdoc wrapper that sets RUSTC_BOOTSTRAP=1 for
# the documented crate alone: the dependencies are the same builds as `cargo doc`'s (a
# build script that probes for nightly features sees nothing different), so after the
# rustdoc step this costs only the three crates' documentation passes.
set -euo pipefail
cd "$(dirname "$0")/.."

crates=(spvg spvg-shaders spvg-wgpu)
mode=check
since=
while [ $# -gt 0 ]; do
  case "$1" in
    --bless) mode=bless ;;
    --since) since="${2:?--since needs a revision}"; shift ;;
    *) echo "usage: scripts/api-check.sh [--bless] [--since REV]" >&2; exit 2 ;;
  esac
  shift
done

target="${CARGO_TARGET_DIR:-target}"
work="$target/api-check"
mkdir -p "$work" api
work="$(cd "$work" && pwd)"
# The wrapper runs the pinned toolchain's rustdoc (resolved here, not by the rustup proxy
# from the directory cargo runs it in).
rustdoc_bin="$(rustup which rustdoc)"
cat >"$work/rustdoc" <<WRAP
#!/bin/sh
RUSTC_BOOTSTRAP=1 exec "$rustdoc_bin" "\$@"
WRAP
chmod +x "$work/rustdoc"

status=0
for crate in "${crates[@]}"; do
  json="$target/doc/${crate//-/_}.json"
  # Never a listing of an earlier run's output: cargo writes it again or this fails.
  rm -f "$json"
  RUSTDOC="$work/rustdoc" cargo rustdoc --locked -q -p "$crate" --all-features \
    -- -Z unstable-options --output-format json
  python3 scripts/api-listing.py "$json" >"$work/$crate.txt"
  recorded="api/$crate.txt"
  if [ "$mode" = bless ]; then
    cp "$work/$crate.txt" "$recorded"
    echo "api-check: wrote $recorded ($(wc -l <"$recorded") items)"
  elif ! cmp -s "$recorded" "$work/$crate.txt"; then
    status=1
    echo "api-check: the public API of $crate differs from $recorded:"
    if [ -f "$recorded" ]; then
      # Lines only in the sources (+), only in the recorded listing (-).
      diff --old-line-format='  - %L' --new-line-format='  + %L' --unchanged-line-format='' \
        "$recorded" "$work/$crate.txt" || true
    else
      echo "  (no recorded listing)"
    fi
  else
    echo "api-check: $crate matches $recorded ($(wc -l <"$recorded") items)"
  fi
done
if [ "$status" -ne 0 ]; then
  cat <<'MSG'
api-check: FAILED. If the change is meant, describe it in CHANGELOG.md under [Unreleased]
(with a **Migration** line when existing callers break), then run
`scripts/api-check.sh --bless` and commit api/ together with the entry.
MSG
  exit 1
fi

if [ -n "$since" ]; then
  base="$(git merge-base "$since" HEAD)"
  changed="$(git diff --name-only "$base" -- api/ CHANGELOG.md)"
  if grep -q '^api/' <<<"$changed" && ! grep -qx 'CHANGELOG.md' <<<"$changed"; then
    echo "api-check: api/ changed since $since ($base) but CHANGELOG.md did not:" \
      "a public API change needs its CHANGELOG entry."
    exit 1
  fi
fi

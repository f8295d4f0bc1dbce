#!/usr/bin/env bash
# The demo page (spvg-web) in a real browser: builds it for wasm32 (release) with its
# wasm-bindgen glue into <target>/web-site/ (<target>: cargo's target directory, from
# `cargo metadata`, so CARGO_TARGET_DIR is honoured), serves that on 127.0.0.1 with
# `python3 -m http.server`, and runs Debian's Chromium headless with WebGPU on SwiftShader
# on `index.html?check=N`: the page renders N frames of a scripted camera path with the
# adaptive controller, compares every frame's counts and history texels with the
# component's twin compiled into the same wasm, and logs one line, `SPVG-WEB PASS ...` or
# `SPVG-WEB FAIL ...`. Exits 0 only on PASS. Before the check it opens the interactive
# page and prints its first-run time: from page load to the first frame shown.
#
#   scripts/web-check.sh [--frames N] [--eq K] [--screenshot FILE] [--timeout S]
#   scripts/web-check.sh --serve [PORT]     # build, then serve the page to open yourself
#
# --frames N        frames of the scripted path (default 48)
# --eq K            also measure the equal-quality figure on the last view, K frames per
#                   run (fixed 8, 16, 32, 64 and adaptive); 0 skips it (default 0)
# --screenshot FILE the page as a PNG once the check has logged its line
# --timeout S       give up after S seconds in the browser (default 900)
#
# Needs: rustup (adds the wasm32-unknown-unknown target if missing), python3, and for the
# check `chromium` (Debian: `apt-get install -y chromium`). The JS glue comes from
# spvg-web/bindgen, a small tool of its own workspace on wasm-bindgen's library at the
# version spvg-web pins (no `cargo install wasm-bindgen-cli`, which builds the whole CLI);
# the first run builds it into <target>, later runs reuse it. "total" counts every build.
set -euo pipefail
cd "$(dirname "$0")/.."

frames=48
eq=0
screenshot=""
timeout=900
serve=""
while [ $# -gt 0 ]; do
  case "$1" in
    --frames) frames="$2"; shift 2 ;;
    --eq) eq="$2"; shift 2 ;;
    --screenshot) screenshot="$2"; shift 2 ;;
    --timeout) timeout="$2"; shift 2 ;;
    --serve)
      serve=8000
      if [ $# -gt 1 ] && [[ "$2" =~ ^[0-9]+$ ]]; then serve="$2"; shift; fi
      shift ;;
    -h|--help) sed -n '2,25p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "web-check: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done

started=$SECONDS
# The wasm-bindgen version the crate pins exactly; the glue tool must pin the same.
bindgen_version="$(sed -n 's/^wasm-bindgen = "=\(.*\)"/\1/p' spvg-web/Cargo.toml)"
tool_version="$(sed -n 's/^wasm-bindgen-cli-support = "=\(.*\)"/\1/p' spvg-web/bindgen/Cargo.toml)"
if [ -z "$bindgen_version" ] || [ "$bindgen_version" != "$tool_version" ]; then
  echo "web-check: spvg-web pins wasm-bindgen '$bindgen_version', spvg-web/bindgen pins '$tool_version': they must be one exact version" >&2
  exit 1
fi
if ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
  rustup target add wasm32-unknown-unknown
fi
target="$(cargo metadata --locked --format-version 1 --no-deps |
  python3 -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')"
# The glue tool: its own workspace and lockfile, built once into the target directory.
cargo build --locked --release --manifest-path spvg-web/bindgen/Cargo.toml \
  --target-dir "$target/spvg-web-bindgen"
bindgen="$target/spvg-web-bindgen/release/spvg-web-bindgen"
cargo build --locked --release --target wasm32-unknown-unknown -p spvg-web
site="$target/web-site"
rm -rf "$site"
mkdir -p "$site"
cp spvg-web/web/index.html "$site/"
"$bindgen" "$target/wasm32-unknown-unknown/release/spvg_web.wasm" "$site/pkg"
wasm="$site/pkg/spvg_web_bg.wasm"
echo "web-check: built in $((SECONDS - started)) s; $wasm: $(stat -c %s "$wasm") bytes, $(gzip -9 -c "$wasm" | wc -c) gzipped"

if [ -n "$serve" ]; then
  echo "web-check: serving the page: open http://127.0.0.1:$serve/ in a browser with WebGPU"
  exec python3 -m http.server "$serve" --bind 127.0.0.1 --directory "$site"
fi

if ! command -v chromium >/dev/null; then
  echo "web-check: chromium not found (Debian: apt-get install -y chromium)" >&2
  exit 1
fi
port="$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
python3 -m http.server "$port" --bind 127.0.0.1 --directory "$site" >/dev/null 2>&1 &
server=$!
trap 'kill "$server" 2>/dev/null || true' EXIT
# Wait for the server to answer.
for _ in $(seq 50); do
  if python3 -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:$port/index.html')" 2>/dev/null; then
    break
  fi
  sleep 0.1
done
query="check=$frames"
if [ "$eq" != 0 ]; then query="$query&eq=$eq"; fi
# The interactive page first, timed from page load to its first frame (the first-run
# time), then the check.
args=(--log "$target/web-check-chromium.log" --timeout "$timeout"
  --first-run "http://127.0.0.1:$port/index.html")
if [ -n "$screenshot" ]; then args+=(--screenshot "$screenshot"); fi
status=0
python3 scripts/web-check.py "${args[@]}" "http://127.0.0.1:$port/index.html?$query" || status=$?
echo "web-check: Chromium's log: $target/web-check-chromium.log; total $((SECONDS - started)) s"
exit "$status"

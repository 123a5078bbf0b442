#!/usr/bin/env bash
# Build the Hydrolux web page into target/web (and serve it with --serve [PORT]).
#   web/build.sh            build
#   web/build.sh --serve    build, then serve on http://127.0.0.1:8000
# Needs the wasm32 target (installed here with rustup) and wasm-bindgen-cli of
# the version Cargo.lock pins (installed from crates.io into target/tools).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
out=$root/target/web
# Its own target folder: a build from inside `cargo test` must not wait on
# the test's lock of target/.
export CARGO_TARGET_DIR=$root/target/wasm

if ! rustup target list --installed 2>/dev/null | grep -qx wasm32-unknown-unknown; then
  echo "installing the wasm32-unknown-unknown target" >&2
  rustup target add wasm32-unknown-unknown
fi
version=$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/version = |"/, ""); print; exit }' Cargo.lock)
bindgen=$root/target/tools/bin/wasm-bindgen
if [ ! -x "$bindgen" ] || [ "$("$bindgen" --version | awk '{print $2}')" != "$version" ]; then
  echo "installing wasm-bindgen-cli $version (once)" >&2
  # A debug build: installs in about a third of the time, and binds the page in seconds.
  cargo install --quiet --debug wasm-bindgen-cli --version "$version" --root "$root/target/tools"
fi

cargo build --quiet --profile web -p hydrolux-web --target wasm32-unknown-unknown
rm -rf "$out"
mkdir -p "$out"
"$bindgen" --target web --no-typescript --out-dir "$out" --out-name hydrolux \
  "$CARGO_TARGET_DIR/wasm32-unknown-unknown/web/hydrolux_web.wasm"
cp web/index.html "$out/"
echo "built $out ($(du -sh "$out/hydrolux_bg.wasm" | cut -f1) of wasm)" >&2

if [ "${1:-}" = "--serve" ]; then
  port=${2:-8000}
  echo "serving http://127.0.0.1:$port/ (Ctrl-C stops)" >&2
  exec python3 -m http.server --bind 127.0.0.1 --directory "$out" "$port"
fi

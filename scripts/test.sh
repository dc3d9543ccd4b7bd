#!/usr/bin/env bash
# Every test tier: the native core, the bindings as wasm under Node, and the
# widgets in a real browser.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh
bash scripts/setup.sh --browser

# Any warning fails the run: clippy on every target, natively and for the
# wasm build with the benchmark entry points, and rustdoc's links.
echo "== lints: cargo fmt, cargo clippy, cargo doc"
cargo fmt --all --check
cargo clippy --quiet --all-targets -- -D warnings
cargo clippy --quiet --target wasm32-unknown-unknown --all-targets --features bench -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --quiet --no-deps

echo "== native: cargo test"
cargo test --quiet
# The benchmark runner is no test target: make sure it still compiles.
cargo check --quiet --benches
# SLAM's loop tests map hundreds of scans: seconds optimised, minutes
# without (they are ignored in the debug run above). Whole-program
# optimisation is for the shipped wasm, not for a test run.
CARGO_PROFILE_RELEASE_LTO=false CARGO_PROFILE_RELEASE_CODEGEN_UNITS=16 \
  cargo test --release --quiet --test slam_loops

echo "== wasm: wasm-pack test --node"
wasm-pack --log-level warn test --node -- --features bench

bash scripts/build.sh
echo "== node: wasm soak and JS-side garbage"
node --test --test-concurrency=1 --test-timeout=600000 --test-force-exit tests/node/

echo "== browser: Chromium"
node --test --test-concurrency=1 --test-timeout=600000 --test-force-exit tests/browser/

#!/usr/bin/env bash
# Builds the wasm package the page and the Node scripts load (pkg/), or with
# `--bench` the same core with the benchmark workloads' entry points
# (pkg-bench/, for npm run bench; the page never loads it).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh
out=pkg
cargo_args=()
if [ "${1:-}" = "--bench" ]; then
  out=pkg-bench
  cargo_args=(-- --features bench)
fi
wasm-pack --log-level warn build --target web --release --out-dir "$out" --no-pack "${cargo_args[@]}"
node scripts/lib/strip-wasm-names.mjs "$out/occgrid_bg.wasm"

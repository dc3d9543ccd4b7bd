#!/usr/bin/env bash
# Builds the wasm the page and the Node scripts load, as two modules of the
# one crate (Cargo.toml's `chapter` and `logs` features) side by side in pkg/:
# occgrid.js + occgrid_bg.wasm, the chapter's widgets, and occgrid_logs.js +
# occgrid_logs_bg.wasm, real laser logs, which the page loads only when a
# reader opens a log. With `--bench`, one module with both and the benchmark
# workloads' entry points (pkg-bench/, for npm run bench; the page never
# loads it).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh

build() { # OUT_DIR OUT_NAME CARGO_ARGS...
  local out=$1 name=$2
  shift 2
  wasm-pack --log-level warn build --target web --release --out-dir "$out" --out-name "$name" --no-pack -- "$@"
  # Finds the stack pointer by name, so before the names are stripped.
  node scripts/lib/guard-stack-pointer.mjs "$out/${name}_bg.wasm" "$out/${name}.js"
  node scripts/lib/strip-wasm-names.mjs "$out/${name}_bg.wasm"
}

if [ "${1:-}" = "--bench" ]; then
  build pkg-bench occgrid --features bench
else
  build pkg occgrid --no-default-features --features chapter
  build pkg occgrid_logs --no-default-features --features logs
fi

#!/usr/bin/env bash
# Builds the wasm package the page and the Node scripts load (pkg/).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh
wasm-pack --log-level warn build --target web --release --out-dir pkg --no-pack
node scripts/lib/strip-wasm-names.mjs pkg/occgrid_bg.wasm

# Sourced by the other scripts: where the tools live, and the pinned versions.
export PATH="$HOME/.cargo/bin:$PWD/node_modules/.bin:$PATH"
# The wasm-bindgen CLI must match the crate exactly (Cargo.toml pins it).
WASM_BINDGEN_VERSION="$(sed -n 's/^wasm-bindgen = "=\(.*\)"$/\1/p' Cargo.toml)"
WASM_PACK_VERSION="0.15.1"

//! Rendering: what cells believe, to pixels. The one gray ramp, and the
//! incremental view a widget reads its map pixels from (in wasm memory,
//! without a copy).

pub mod evidence;
pub mod gray;
pub mod map_view;
pub mod overlay;
pub mod viewport;

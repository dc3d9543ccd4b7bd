//! The chapter's scenes as data (serde, seeded): the apartment Map Weaver
//! drives through, the doorway of the doorway trap, the table of the fusion
//! widget, the paths robots and people follow, and the random floor plans the
//! learned inverse model is trained on. Each scene builds a [`crate::world::World`]
//! (its ground truth) and the stream of readings its sensors take.

use crate::error::{self, Result};
use crate::geometry::GridGeometry;

pub mod apartment;
pub mod doorway;
pub mod floor_plans;
pub mod paths;
pub mod table;

/// The most cells a scene stepped cell by cell in a widget may have (the
/// doorway's sweep and MAP climb, the table's two sonar sweeps per step):
/// about 100 and 20 times the chapter's scenes, still a fraction of a
/// second per step natively.
pub const MAX_WIDGET_SCENE_CELLS: usize = 250_000;

/// Refuses a scene grid larger than [`MAX_WIDGET_SCENE_CELLS`], naming its
/// size and resolution.
pub(crate) fn check_scene_cells(g: &GridGeometry) -> Result<()> {
    if g.len() > MAX_WIDGET_SCENE_CELLS {
        return Err(error::invalid(
            "width x height",
            format!(
                "{} x {} cells at resolution {}",
                g.width(),
                g.height(),
                error::show(g.resolution())
            ),
            "at most 250000 cells: a coarser resolution or a smaller room",
        ));
    }
    Ok(())
}

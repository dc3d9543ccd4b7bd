//! Random floor plans: the map prior the learned inverse model (§9.3) is
//! trained on. Rooms by recursive division, doorways, and furniture that is
//! mostly legs and small pieces, all seeded by the caller's generator.

use crate::error::{self, Result};
use crate::geometry::GridGeometry;
use crate::world::World;
use rand::Rng;

/// Draws one floor plan from the map prior, a square of `side` metres at
/// `res` metres per cell,
/// standing in empty space: a ray that leaves the square returns nothing,
/// as in [`World::cast`], and a target cell outside it is free.
///
/// The prior is a building as a LiDAR at shin height sees it: thin walls
/// with open rooms on both sides, doorways, and furniture that is mostly
/// legs and small pieces. What lies behind a surface is what the model
/// learns about the cells past a reading, so the prior's obstacles must be
/// as thin as real ones: a prior of deep solid blocks teaches an occupied
/// band that runs far past every wall (and paints one behind every wall of
/// a real flat). In the order it is drawn:
///
/// * **The outer wall**, [`OUTER_WALL`] thick (two cells at 0.1 m), around
///   the whole square, with an entrance in one side out of two.
/// * **Rooms**, by recursive division of the floor inside it: a part whose
///   longer side exceeds a limit drawn for it from 2.5 to 5 m is cut
///   across that side at a random place (each new part at least
///   [`MIN_ROOM`] wide) by a wall one cell thick (0.1 m; one wall in four
///   is 0.2 m) with a doorway, and one wall in three with a second one.
///   One cut in eight gets no wall: open-plan rooms. Doorways are 0.8 to
///   1.2 m wide.
/// * **Furniture** in every room: 2 to 4 tries per square metre, each a
///   piece that is kept only if it stays a cell clear of everything drawn
///   so far (walls included), so that no two obstacles merge into a
///   deeper one. Seven pieces in ten are small (0.1 to 0.25 m a side:
///   chair legs, bins, plants, pillars), a quarter are tables (a leg of
///   one cell at each corner of 0.6 to 1.6 m by 0.6 to 1.0 m), one in
///   twenty is a solid piece 0.3 to 0.5 m deep and 0.6 to 1.6 m long
///   (cabinets, sofas).
///
/// Every obstacle is at least one cell thick, whatever the resolution. On
/// the default 12 m square the maps come out about 17% occupied (see
/// `TrainingSet::map_occupancy` of [`crate::inverse::training`]). Rooms are smaller than the sensor's
/// range, so nearly every max-range reading in them is a dropout from a
/// real wall, which is what makes a no-return doubtful.
pub fn sample_floor_plan<R: Rng + ?Sized>(side: f64, res: f64, rng: &mut R) -> Result<World> {
    error::positive("resolution", res)?;
    error::positive("side", side)?;
    let n = (side / res).ceil() as usize;
    let geometry = GridGeometry::new(n, n, res, 0.0, 0.0)?;
    let mut world = World::empty(geometry);
    // No obstacle thinner than a cell: a span narrower than one may hold
    // no cell centre at all.
    let thick = |t: f64| t.max(res);

    // The outer wall: south, north, west and east strips.
    let t = thick(OUTER_WALL);
    let outer = [
        Span::new(0.0, 0.0, side, t),
        Span::new(0.0, side - t, side, side),
        Span::new(0.0, 0.0, t, side),
        Span::new(side - t, 0.0, side, side),
    ];
    for s in &outer {
        fill(&mut world, s, true);
    }
    if rng.random::<f64>() < 0.5 {
        let s = outer[rng.random_range(0..4)];
        door(&mut world, &s, rng);
    }

    // Rooms: recursive division, depth first with an explicit stack. Every
    // cut leaves parts at least MIN_ROOM wide, so the loop ends.
    let mut parts = vec![Span::new(t, t, side - t, side - t)];
    let mut rooms = Vec::new();
    while let Some(p) = parts.pop() {
        let (w, h) = (p.x1 - p.x0, p.y1 - p.y0);
        let limit = rng.random_range(2.5..5.0);
        let across_x = w >= h;
        let long = if across_x { w } else { h };
        let wall_t = thick(if rng.random::<f64>() < 0.25 {
            2.0 * WALL
        } else {
            WALL
        });
        if !(long > limit && long - wall_t >= 2.0 * MIN_ROOM) {
            rooms.push(p);
            continue;
        }
        // (The test above leaves room on both sides; `max` only guards
        // against rounding.)
        let at = rng.random_range(MIN_ROOM..=(long - wall_t - MIN_ROOM).max(MIN_ROOM));
        let (wall, a, b) = if across_x {
            let x = p.x0 + at;
            (
                Span::new(x, p.y0, x + wall_t, p.y1),
                Span::new(p.x0, p.y0, x, p.y1),
                Span::new(x + wall_t, p.y0, p.x1, p.y1),
            )
        } else {
            let y = p.y0 + at;
            (
                Span::new(p.x0, y, p.x1, y + wall_t),
                Span::new(p.x0, p.y0, p.x1, y),
                Span::new(p.x0, y + wall_t, p.x1, p.y1),
            )
        };
        if rng.random::<f64>() >= 1.0 / 8.0 {
            fill(&mut world, &wall, true);
            door(&mut world, &wall, rng);
            if rng.random::<f64>() < 1.0 / 3.0 {
                door(&mut world, &wall, rng);
            }
        }
        parts.push(a);
        parts.push(b);
    }

    // Furniture, room by room.
    for room in &rooms {
        let (w, h) = (room.x1 - room.x0, room.y1 - room.y0);
        let tries = (w * h * rng.random_range(2.0..4.0)).round() as usize;
        for _ in 0..tries {
            let kind = rng.random::<f64>();
            let table = (0.7..0.95).contains(&kind);
            let (bw, bh) = if kind < 0.7 {
                let s = rng.random_range(0.1..0.25);
                (s, s)
            } else if table {
                (rng.random_range(0.6..1.6), rng.random_range(0.6..1.0))
            } else {
                let (deep, long) = (rng.random_range(0.3..0.5), rng.random_range(0.6..1.6));
                if rng.random::<f64>() < 0.5 {
                    (deep, long)
                } else {
                    (long, deep)
                }
            };
            let (bw, bh) = (thick(bw).min(w), thick(bh).min(h));
            let x = room.x0 + rng.random::<f64>() * (w - bw);
            let y = room.y0 + rng.random::<f64>() * (h - bh);
            let clear = Span::new(x - res, y - res, x + bw + res, y + bh + res);
            if any_occupied(&world, &clear) {
                continue;
            }
            if table {
                for (lx, ly) in [
                    (x, y),
                    (x + bw - res, y),
                    (x, y + bh - res),
                    (x + bw - res, y + bh - res),
                ] {
                    fill(&mut world, &Span::new(lx, ly, lx + res, ly + res), true);
                }
            } else {
                fill(&mut world, &Span::new(x, y, x + bw, y + bh), true);
            }
        }
    }
    Ok(world)
}

/// The densest map prior [`add_clutter`] draws: three cells in five
/// occupied. Past that a robot's footprint hardly ever fits.
pub const MAX_DENSITY: f64 = 0.6;

/// Fills a sampled plan with solid boxes (0.2 to 0.8 m a side, placed
/// anywhere, walls and each other included) until `density` of its cells
/// are occupied: the dense map prior of random boxes, against the plan's
/// own thin walls. A `density` at or below the plan's own occupancy adds
/// nothing and draws no random numbers, so the buildings prior stays bit
/// for bit what it was. What a model trained on these maps learns about
/// the cells past a reading is mostly this density: its `l0` follows it.
pub fn add_clutter<R: Rng + ?Sized>(world: &mut World, density: f64, rng: &mut R) -> Result<()> {
    if !(0.0..=MAX_DENSITY).contains(&density) {
        return Err(crate::error::invalid(
            "density",
            density,
            "an occupied fraction between 0 and 0.6",
        ));
    }
    let g = *world.geometry();
    let res = g.resolution();
    let (w, h) = (g.width() as f64 * res, g.height() as f64 * res);
    let total = world.occupied().len();
    let target = (density * total as f64).ceil() as usize;
    let mut occupied = world.occupied().iter().filter(|&&o| o).count();
    // Every box covers at least one free cell or is redrawn; the bound
    // only guards a loop in the core (a box of 0.2 m covers 4 cells, so
    // `total` boxes would fill the map many times over).
    let mut tries = 0;
    while occupied < target && tries < total {
        tries += 1;
        let (bw, bh) = (rng.random_range(0.2..0.8), rng.random_range(0.2..0.8));
        let x = rng.random::<f64>() * (w - bw).max(0.0);
        let y = rng.random::<f64>() * (h - bh).max(0.0);
        let span = Span::new(x, y, x + bw, y + bh);
        let (xs, ys) = span.cells(&g);
        let cells = world.occupied_mut();
        for iy in ys {
            for ix in xs.clone() {
                let c = &mut cells[iy * g.width() + ix];
                occupied += !*c as usize;
                *c = true;
            }
        }
    }
    Ok(())
}

/// Thickness of a sampled map's outer wall, metres.
pub const OUTER_WALL: f64 = 0.2;
/// Thickness of most interior walls, metres (one cell at 0.1 m).
pub const WALL: f64 = 0.1;
/// Narrowest room the division leaves, metres.
pub const MIN_ROOM: f64 = 1.5;
/// Half the side of the square that must be clear around a pose, metres:
/// a robot stands where its footprint fits, not in a crack between two
/// chair legs. (Without it a no-return would often come from a pose
/// pressed against an obstacle, and the model would learn that the cells
/// next to the sensor of a no-return are occupied.)
pub const POSE_CLEARANCE: f64 = 0.25;

/// An axis-aligned span of a sampled map, `[x0, x1) x [y0, y1)` metres.
#[derive(Debug, Clone, Copy)]
struct Span {
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
}

impl Span {
    fn new(x0: f64, y0: f64, x1: f64, y1: f64) -> Self {
        Self { x0, y0, x1, y1 }
    }

    /// The cell columns and rows whose centres lie in the span, clipped to
    /// the map.
    fn cells(&self, g: &GridGeometry) -> (std::ops::Range<usize>, std::ops::Range<usize>) {
        let res = g.resolution();
        let range = |lo: f64, hi: f64, n: usize| {
            let first = (lo / res - 0.5).ceil().clamp(0.0, n as f64) as usize;
            let end = (hi / res - 0.5).ceil().clamp(0.0, n as f64) as usize;
            first..end.max(first)
        };
        (
            range(self.x0, self.x1, g.width()),
            range(self.y0, self.y1, g.height()),
        )
    }
}

/// Opens a doorway 0.8 to 1.2 m wide at a random place along `wall` (all
/// of it, if it is shorter).
fn door<R: Rng + ?Sized>(world: &mut World, wall: &Span, rng: &mut R) {
    let width = rng.random_range(0.8..1.2);
    let (w, h) = (wall.x1 - wall.x0, wall.y1 - wall.y0);
    let gap = if w >= h {
        let x = wall.x0 + rng.random::<f64>() * (w - width).max(0.0);
        Span::new(x, wall.y0, x + width, wall.y1)
    } else {
        let y = wall.y0 + rng.random::<f64>() * (h - width).max(0.0);
        Span::new(wall.x0, y, wall.x1, y + width)
    };
    fill(world, &gap, false);
}

/// Whether the square of half side `half` (metres) around `(x, y)` is free
/// of obstacles: where a robot's footprint fits.
pub fn is_clear_around(world: &World, x: f64, y: f64, half: f64) -> bool {
    !any_occupied(world, &Span::new(x - half, y - half, x + half, y + half))
}

/// Whether any cell whose centre lies in `span` is occupied.
fn any_occupied(world: &World, span: &Span) -> bool {
    let g = *world.geometry();
    let (xs, ys) = span.cells(&g);
    let cells = world.occupied();
    ys.into_iter().any(|iy| {
        cells
            .get(iy * g.width() + xs.start..iy * g.width() + xs.end)
            .is_some_and(|row| row.contains(&true))
    })
}

/// Sets the cells whose centres lie in `span`, visiting only those cells.
fn fill(world: &mut World, span: &Span, occupied: bool) {
    let g = *world.geometry();
    let (xs, ys) = span.cells(&g);
    let cells = world.occupied_mut();
    for iy in ys {
        if let Some(row) = cells.get_mut(iy * g.width() + xs.start..iy * g.width() + xs.end) {
            row.fill(occupied);
        }
    }
}

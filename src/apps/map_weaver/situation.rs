//! What the robot and the person do while Map Weaver maps: the chapter's
//! lap, or the ghost watch of exercise 5.
//!
//! On the lap the robot drives on after the person has passed, so how long
//! a ghost lasts says when the robot came back, not how the filter forgets.
//! The ghost watch keeps the robot parked in the corridor, scanning it
//! twelve times a second, while the person stands by the kitchen door long
//! enough for every clamp to saturate the cells they stand on, then walks
//! out of sight into the kitchen. From then on every scan contradicts the
//! ghost: a cell at the clamp `l_max` needs `l_max / |l_free|` free
//! readings to fall back below p = 0.5 (Table 9.1 adds `l_free` once per
//! scan), so the fade time is linear in the clamp and inversely
//! proportional to the free evidence.

use crate::scenes::apartment::{ApartmentScene, TrackedPoint};
use crate::scenes::paths::{LapPath, WalkerParams};

/// Where the robot drives and where the person walks.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Situation {
    /// The scene's own lap and walk (the chapter's run).
    #[default]
    Lap,
    /// The robot parked in the corridor; the person stands by the kitchen
    /// door, then leaves into the kitchen and comes back, again and again.
    GhostWatch,
}

/// Where the robot is parked in the ghost watch, metres: in the corridor,
/// about a metre west of where the person stands, so that four or five of
/// its 60 beams end on the person.
pub const WATCH_POST: [f64; 2] = [9.5, 5.05];
/// Seconds the person stands at each end of the watch's walk: at 12 scans
/// a second and a quarter of Table 9.2's laser evidence (0.21 a scan), 8 s
/// take a cell the person stands on past the largest clamp (16).
pub const WATCH_PAUSE: f64 = 8.0;
/// Where the person stands in the corridor (their centre, metres), and
/// where they stand in the kitchen, out of the robot's sight behind the
/// corridor's south wall. The straight walk between the two passes
/// through the kitchen door (x 10.3 to 11.3).
const WATCH_STAND: [f64; 2] = [10.83, 4.63];
const WATCH_HIDE: [f64; 2] = [10.83, 2.45];
/// A cell of the ghost the chart follows (metres): on the person's west
/// outline, where the robot's beam at -18 degrees ends, and clear of the
/// beams that end on the person while they walk away south.
pub const WATCH_GHOST_CELL: [f64; 2] = [10.55, 4.65];
/// How far the robot's two waypoints lie apart, metres: the least a lap
/// allows is 1 mm; 2 mm keeps clear of it after rounding.
const PARKED_STEP: f64 = 0.002;
/// Turning rate of the parked robot, rad/s: its half turn at each end of
/// its 2 mm takes 3 ms, less than the gap between two scans, so no scan
/// sees it mid-turn; turned by pi, a 60-beam LiDAR reads along the same
/// lines, so the parked robot scans the same cells scan after scan.
const PARKED_TURN_RATE: f64 = 1000.0;

impl Situation {
    /// `scene` with this situation's robot path and person (the lap: the
    /// scene unchanged). Applying it twice gives the same scene.
    pub fn apply(self, scene: &ApartmentScene) -> ApartmentScene {
        let mut scene = scene.clone();
        if self == Self::GhostWatch {
            let person = WalkerParams {
                size: 0.5,
                from: WATCH_STAND,
                to: WATCH_HIDE,
                speed: 0.5,
                pause: WATCH_PAUSE,
                phase: 0.0,
            };
            // Start the cycle (walk out, stand, walk back, stand) at its
            // last part, standing in the corridor: the first ghost builds
            // from the first scan.
            let [x, y] = WATCH_POST;
            let walk = (WATCH_HIDE[1] - WATCH_STAND[1]).abs() / person.speed;
            let cycle = 2.0 * (walk + WATCH_PAUSE);
            scene.person = WalkerParams {
                phase: (2.0 * walk + WATCH_PAUSE) / cycle,
                ..person
            };
            // One "lap" of the parked robot lasts two of the person's
            // cycles, plus half a scan so that its turns fall between scans.
            let half = cycle + 0.5 / scene.scan_rate;
            // The chart follows a wall cell the robot sees and a cell of
            // the ghost (the closet stays, never seen).
            scene.tracked[0] = TrackedPoint {
                name: "corridor wall".into(),
                at: [x, 5.55],
            };
            scene.tracked[1] = TrackedPoint {
                name: "ghost cell".into(),
                at: WATCH_GHOST_CELL,
            };
            scene.path = LapPath {
                waypoints: vec![[x, y], [x + PARKED_STEP, y]],
                speed: PARKED_STEP / half,
                turn_rate: PARKED_TURN_RATE,
            };
        }
        scene
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_watch_parks_the_robot_and_starts_with_the_person_standing() {
        let scene = Situation::GhostWatch.apply(&ApartmentScene::default());
        scene.validate().unwrap();
        assert_eq!(Situation::GhostWatch.apply(&scene), scene, "idempotent");
        assert_eq!(Situation::Lap.apply(&scene), scene);
        // Sampled over a whole "lap", the robot never leaves its post by
        // more than 2 mm, and faces east or west.
        let lap = scene.path.lap_seconds();
        for i in 0..=1000 {
            let p = scene.path.pose_at(lap * i as f64 / 1000.0);
            assert!((p.x - WATCH_POST[0]).abs() <= 0.002 + 1e-9 && p.y == WATCH_POST[1]);
        }
        for k in 0..(lap * scene.scan_rate) as usize {
            let p = scene.path.pose_at(k as f64 / scene.scan_rate);
            assert!(p.theta.sin().abs() < 1e-9, "scan {k} mid-turn: {}", p.theta);
        }
        // Standing in the corridor for the first 8 s, then gone south.
        assert_eq!(scene.person.center_at(0.0), WATCH_STAND);
        assert_eq!(scene.person.center_at(WATCH_PAUSE - 0.01), WATCH_STAND);
        assert!(scene.person.center_at(WATCH_PAUSE + 2.0)[1] < WATCH_STAND[1] - 0.9);
    }
}

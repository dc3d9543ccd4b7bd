//! Every cell model's export, on a synthetic corridor walked by a robot:
//! the robot's own path lies on free cells (a model whose updates are too
//! weak for the export's thresholds draws at its own cut, and the YAML
//! says so), the counts shown beside the map are the image's, and the
//! YAML names the log, the pose source and the cell model.

use occgrid::apps::real_log::{LogCellModel, LogMapSettings, LogPane};
use occgrid::io::carmen::read_scans;
use occgrid::io::map_server::{read_pgm, PGM_FREE, PGM_OCCUPIED};

#[path = "log_support/mod.rs"]
mod log_support;
use log_support::flaser_log;

/// The range from `(x, y)` along `angle` to the walls of the box
/// `[-1, 7] x [-1.5, 1.5]` (the robot inside it).
fn to_box(x: f64, y: f64, angle: f64) -> f64 {
    let (s, c) = angle.sin_cos();
    let mut t = f64::INFINITY;
    if c > 1e-9 {
        t = t.min((7.0 - x) / c);
    }
    if c < -1e-9 {
        t = t.min((-1.0 - x) / c);
    }
    if s > 1e-9 {
        t = t.min((1.5 - y) / s);
    }
    if s < -1e-9 {
        t = t.min((-1.5 - y) / s);
    }
    t
}

/// A robot driving down the corridor and back, sixteen scans of 180
/// beams over the half plane ahead (as FLASER lays them out).
fn corridor_log() -> Vec<u8> {
    use std::f64::consts::{FRAC_PI_2, PI};
    let scans: Vec<_> = (0..16)
        .map(|k| {
            let step = if k < 8 { k } else { 15 - k };
            let (x, y) = (step as f64 * 0.5, 0.1 * (k % 2) as f64);
            let theta = if k < 8 { 0.0 } else { PI };
            let ranges = (0..180)
                .map(|i| to_box(x, y, theta - FRAC_PI_2 + i as f64 * PI / 179.0))
                .collect();
            (x, y, theta, ranges)
        })
        .collect();
    flaser_log(&scans)
}

#[test]
fn every_cell_model_exports_the_robot_s_path_on_free_cells_and_says_how() {
    let bytes = corridor_log();
    for model in LogCellModel::ALL {
        let settings = LogMapSettings {
            model,
            ..LogMapSettings::default()
        };
        let mut pane = LogPane::new(read_scans(&bytes[..]).unwrap(), settings).unwrap();
        pane.advance(usize::MAX);
        let pair = pane.export_map_of(Some("corridor"), Some("corridor.log"));
        let pgm = read_pgm(&pair.pgm).unwrap();
        // The counts beside the map are the image's.
        let counts = pane.counts();
        let count = |gray: u8| pgm.pixels.iter().filter(|&&p| p == gray).count();
        assert_eq!(
            (counts.free, counts.occupied),
            (count(PGM_FREE), count(PGM_OCCUPIED)),
            "{model:?}"
        );
        // The robot's own path: every pose on a free cell.
        let g = pane.grid().geometry();
        for pose in pane.poses() {
            let (ix, iy) = g.world_to_cell(pose.x, pose.y).unwrap();
            let gray = pgm.at(ix, pgm.height - 1 - iy).unwrap();
            assert_eq!(gray, PGM_FREE, "{model:?} at ({}, {})", pose.x, pose.y);
        }
        let yaml = &pair.yaml;
        assert!(yaml.contains("# log: \"corridor.log\"\n"), "{yaml}");
        assert!(yaml.contains("# pose source: corrected"), "{yaml}");
        let named = format!("# cell model: {}", model.name());
        assert!(yaml.contains(&named), "{yaml}");
        assert!(yaml.contains("# cells drawn: "), "{yaml}");
        assert!(
            yaml.contains("# settings other than the defaults: none\n"),
            "{yaml}"
        );
        // The lines map_server reads are untouched by the comments.
        assert!(yaml.contains("\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"));
    }
}

/// The hit/miss odds model draws at its own cut and says which; the
/// others at the export's thresholds.
#[test]
fn the_cut_a_model_is_drawn_at_is_the_one_its_yaml_names() {
    let bytes = corridor_log();
    for model in LogCellModel::ALL {
        let settings = LogMapSettings {
            model,
            ..LogMapSettings::default()
        };
        let mut pane = LogPane::new(read_scans(&bytes[..]).unwrap(), settings).unwrap();
        pane.advance(usize::MAX);
        let yaml = pane.export_map(None).yaml;
        let cut = match model.trinary_cut() {
            None => "occupied above p 0.65, free below p 0.196 (map_server's thresholds)".into(),
            Some((o, f)) => {
                format!("occupied above p {o}, free below p {f} (the cell model's own cut")
            }
        };
        assert!(yaml.contains(&format!("# cells drawn: {cut}")), "{yaml}");
    }
    assert_eq!(LogCellModel::HitMissOdds.trinary_cut(), Some((0.5, 0.5)));
}

/// The range from `(x, y)` along `angle` to a post of radius 0.1 m at
/// `(cx, cy)`, if the beam meets it.
fn to_post(x: f64, y: f64, angle: f64, (cx, cy): (f64, f64)) -> Option<f64> {
    let (s, c) = angle.sin_cos();
    let (dx, dy) = (cx - x, cy - y);
    let along = dx * c + dy * s;
    let off2 = dx * dx + dy * dy - along * along;
    let r2 = 0.1 * 0.1;
    (along > 0.0 && off2 <= r2).then(|| along - (r2 - off2).sqrt())
}

/// A robot crossing an open square outdoors at 0.5 m a scan: a row of
/// posts 4 m to its left returns a few beams of each scan, every other
/// beam sees open sky (a no-return past the range cap).
fn open_square_log() -> Vec<u8> {
    use std::f64::consts::{FRAC_PI_2, PI};
    let posts: Vec<(f64, f64)> = (0..8).map(|k| (k as f64 * 2.0, 4.0)).collect();
    let scans: Vec<_> = (0..24)
        .map(|k| {
            let (x, y, theta) = (k as f64 * 0.5, 0.0, 0.0);
            let ranges = (0..180)
                .map(|i| {
                    let a = theta - FRAC_PI_2 + i as f64 * PI / 179.0;
                    posts
                        .iter()
                        .filter_map(|&p| to_post(x, y, a, p))
                        .fold(81.9, f64::min)
                })
                .collect();
            (x, y, theta, ranges)
        })
        .collect();
    flaser_log(&scans)
}

/// Outdoors, where most beams return nothing and no-returns clear
/// nothing, each pose's cell rests on the few returns' lines alone: one
/// weak miss per scan. The laser stood in that cell, so every model
/// draws it free.
#[test]
fn an_open_square_with_few_returns_keeps_the_robot_s_path_free() {
    let bytes = open_square_log();
    for model in LogCellModel::ALL {
        let settings = LogMapSettings {
            model,
            ..LogMapSettings::default()
        };
        let mut pane = LogPane::new(read_scans(&bytes[..]).unwrap(), settings).unwrap();
        pane.advance(usize::MAX);
        let pair = pane.export_map(None);
        let pgm = read_pgm(&pair.pgm).unwrap();
        let g = pane.grid().geometry();
        assert!(
            pair.yaml
                .contains("# free cells rest on: the laser's own cell at every scan"),
            "{}",
            pair.yaml
        );
        let returns = pgm.pixels.iter().filter(|&&p| p == PGM_OCCUPIED).count();
        assert!(returns > 0, "{model:?}: the posts are drawn");
        for pose in pane.poses() {
            let (ix, iy) = g.world_to_cell(pose.x, pose.y).unwrap();
            let gray = pgm.at(ix, pgm.height - 1 - iy).unwrap();
            assert_eq!(gray, PGM_FREE, "{model:?} at ({}, {})", pose.x, pose.y);
        }
    }
}

#![cfg(not(target_arch = "wasm32"))]
//! A real log's cell models (`apps::real_log`, docs/ARCHITECTURE.md "Real
//! logs"): the default model clears a stray return and a thinly crossed
//! floor, every model is selectable and refused by name when misspelt, a
//! second pane shows another model of the same log, and the map's extent
//! holds every cell the log carved.

use occgrid::apps::real_log::{LogCellModel, LogMapSettings, LogPane, RealLogSession};
use occgrid::io::carmen::read_scans;
use occgrid::mapping::walls::WallModel;
use occgrid::poses::PoseSourceKind;

mod log_support;
use log_support::flaser_log;

fn pane(bytes: &[u8], settings: LogMapSettings) -> LogPane {
    LogPane::new(read_scans(bytes).unwrap(), settings).unwrap()
}

/// The probability of occupancy at world point `(x, y)`.
fn p_at(b: &LogPane, x: f64, y: f64) -> f64 {
    let grid = b.grid();
    let (ix, iy) = grid.geometry().world_to_cell(x, y).unwrap();
    grid.probability_at(ix, iy).unwrap()
}

/// A wall 6 m ahead across a half circle of 180 beams, seen from the
/// origin; in scan `stray` (if any) the middle beam returns at 3 m instead
/// (a person passing, a leaf).
fn wall_scans(n: usize, stray: Option<usize>) -> Vec<u8> {
    let scans: Vec<_> = (0..n)
        .map(|k| {
            let rs = (0..180)
                .map(|i| {
                    if Some(k) == stray && i == 90 {
                        3.0
                    } else {
                        6.0
                    }
                })
                .collect();
            (0.0, 0.0, 0.0, rs)
        })
        .collect();
    flaser_log(&scans)
}

/// The export's thresholds: occupied above 0.65, free below 0.196.
const FREE: f64 = 0.196;
const OCCUPIED: f64 = 0.65;

#[test]
fn a_speck_from_one_stray_return_is_erased_by_later_misses_under_the_default() {
    let bytes = wall_scans(4, Some(0));
    let mut b = pane(&bytes, LogMapSettings::default());
    b.seek(1).unwrap();
    b.advance(usize::MAX);
    assert!(
        p_at(&b, 3.0, 0.0) > OCCUPIED,
        "the stray return is on the map"
    );
    // Three beams through the same cell to the wall behind it.
    b.seek(4).unwrap();
    b.advance(usize::MAX);
    let p = p_at(&b, 3.0, 0.0);
    assert!(p < FREE, "the speck is floor again, p = {p}");
    // The same scans keep the wall.
    assert!(p_at(&b, 6.0, 0.0) > OCCUPIED);
}

#[test]
fn a_cell_crossed_by_one_beam_reads_free_under_the_default() {
    let b = {
        let mut b = pane(&wall_scans(1, None), LogMapSettings::default());
        b.advance(usize::MAX);
        b
    };
    for r in [0.5, 2.0, 4.5] {
        let p = p_at(&b, r, 0.0);
        assert!(p < FREE, "{r} m along the middle beam: p = {p}");
    }
    assert!(p_at(&b, 6.0, 0.0) > OCCUPIED, "its return is a wall");
    // The chapter's filter needs four such beams (Table 9.2: l_free = -0.4,
    // free below l = -1.41), and stays selectable as the lesson.
    let chapter = LogMapSettings {
        model: LogCellModel::LogOdds,
        ..LogMapSettings::default()
    };
    let mut b = pane(&wall_scans(1, None), chapter);
    b.advance(usize::MAX);
    let p = p_at(&b, 2.0, 0.0);
    assert!(
        p > FREE && p < 0.5,
        "one beam leaves the chapter's cell gray: {p}"
    );
}

/// The PGM's pixels (after its four header lines) and its width.
fn pgm_pixels(pgm: &[u8]) -> (Vec<u8>, usize) {
    let mut lines = 0;
    let mut at = 0;
    while lines < 4 {
        if pgm[at] == b'\n' {
            lines += 1;
        }
        at += 1;
    }
    let header = std::str::from_utf8(&pgm[..at]).unwrap();
    let size: Vec<usize> = header
        .lines()
        .nth(2)
        .unwrap()
        .split(' ')
        .map(|v| v.parse().unwrap())
        .collect();
    (pgm[at..].to_vec(), size[0])
}

/// Free cells (254) on the image's outer ring.
fn free_on_border(b: &LogPane) -> usize {
    let (pixels, w) = pgm_pixels(&b.export_map(None).pgm);
    let h = pixels.len() / w;
    (0..pixels.len())
        .filter(|&i| {
            let (c, r) = (i % w, i / w);
            (c == 0 || r == 0 || c == w - 1 || r == h - 1) && pixels[i] == 254
        })
        .count()
}

/// A robot in a 2 m room with an open doorway: the beams through it see
/// nothing (no-returns past the range cap). Under Table 9.2's walls they
/// clear free space out to the no-return reach, 5 m, past every wall the
/// log saw; under the default walls a run of 20 no-returns clears nothing
/// (`mapping::neighbour_support`). Either way the map's extent holds the
/// reach.
#[test]
fn the_map_s_extent_holds_every_cell_the_log_carved_so_no_free_cell_lies_on_its_border() {
    let rs: Vec<f64> = (0..180)
        .map(|i| if (80..100).contains(&i) { 50.0 } else { 2.0 })
        .collect();
    let bytes = flaser_log(&[(0.0, 0.0, 0.0, rs)]);
    // The default first: one beam makes its cells free.
    for (model, walls) in [
        LogCellModel::HitCounting,
        LogCellModel::LogOdds,
        LogCellModel::HitMissOdds,
    ]
    .into_iter()
    .flat_map(|m| [(m, WallModel::Table92), (m, WallModel::Incidence)])
    {
        let mut b = pane(
            &bytes,
            LogMapSettings {
                model,
                walls,
                resolution: 0.1,
                ..LogMapSettings::default()
            },
        );
        b.advance(usize::MAX);
        assert_eq!(free_on_border(&b), 0, "{model:?}");
        // The clearing reaches 5 m, and the map holds it with its margin.
        let g = b.grid();
        let right = g.geometry().origin()[0] + g.geometry().width() as f64 * 0.1;
        assert!(right >= 5.0 + 1.0 - 1e-9, "east edge at {right} m");
    }
    let table_9_2 = LogMapSettings {
        walls: WallModel::Table92,
        ..LogMapSettings::default()
    };
    let mut b = pane(&bytes, table_9_2);
    b.advance(usize::MAX);
    assert!(p_at(&b, 4.8, 0.0) < FREE, "the doorway's clearing is free");
    assert!(
        p_at(&pane_built(&bytes), 4.8, 0.0) >= FREE,
        "by default nothing returned there: not free"
    );
}

fn pane_built(bytes: &[u8]) -> LogPane {
    let mut b = pane(bytes, LogMapSettings::default());
    b.advance(usize::MAX);
    b
}

#[test]
fn every_model_is_selectable_and_a_misspelt_one_is_refused_by_name() {
    for (model, name) in LogCellModel::ALL.into_iter().zip(LogCellModel::NAMES) {
        assert_eq!(model.name(), name);
        assert_eq!(LogCellModel::from_name("model", name).unwrap(), model);
        let b = pane_built_with(model);
        assert_eq!(b.model(), model);
        assert!(b.counts().occupied > 0, "{name}");
        // Cartographer's misses are weak: six beams do not clear a cell.
        if model != LogCellModel::HitMissOdds {
            assert!(b.counts().free > 0, "{name}");
        }
    }
    let e = LogCellModel::from_name("model", "counting")
        .unwrap_err()
        .to_string();
    assert!(e.contains("model") && e.contains("\"counting\""), "{e}");
    let e: serde_json::Error =
        serde_json::from_str::<LogMapSettings>(r#"{"model": "log_odds"}"#).unwrap_err();
    assert!(e.to_string().contains("log_odds"), "{e}");
    let same = LogMapSettings {
        compare_model: Some(LogCellModel::HitCounting),
        ..LogMapSettings::default()
    };
    let e = same.validate().unwrap_err().to_string();
    assert!(
        e.contains("compareModel") && e.contains("hit-counting"),
        "{e}"
    );
    assert_eq!(LogMapSettings::chapter().model, LogCellModel::LogOdds);
}

fn pane_built_with(model: LogCellModel) -> LogPane {
    let mut b = pane(
        &wall_scans(6, Some(1)),
        LogMapSettings {
            model,
            ..LogMapSettings::default()
        },
    );
    b.advance(usize::MAX);
    b
}

/// Two models side by side: the session's second pane maps the same scans
/// at the same poses with the other model, and each pane's map is the one a
/// pane of that model alone makes.
#[test]
fn a_second_pane_shows_the_same_log_under_another_model() {
    let bytes = wall_scans(4, Some(0));
    let settings = LogMapSettings {
        compare_model: Some(LogCellModel::LogOdds),
        ..LogMapSettings::default()
    };
    let mut s = RealLogSession::new(bytes.clone());
    s.configure(settings).unwrap();
    while !s.read(1000).unwrap().progress.finished {}
    while !s.build_slice(u64::MAX).unwrap().finished {}
    let state = s.state();
    let models: Vec<_> = state.panes.iter().map(|p| (p.poses, p.model)).collect();
    assert_eq!(
        models,
        [
            (PoseSourceKind::Corrected, LogCellModel::HitCounting),
            (PoseSourceKind::Corrected, LogCellModel::LogOdds)
        ]
    );
    assert!(
        state.panes[1].caption.contains("Table 9.2"),
        "{}",
        state.panes[1].caption
    );
    for (k, model) in [LogCellModel::HitCounting, LogCellModel::LogOdds]
        .into_iter()
        .enumerate()
    {
        let alone = {
            let mut b = pane(
                &bytes,
                LogMapSettings {
                    model,
                    ..LogMapSettings::default()
                },
            );
            b.advance(usize::MAX);
            b
        };
        assert_eq!(
            s.pane(k).unwrap().export_map(None),
            alone.export_map(None),
            "{model:?}"
        );
    }
    // The stray return: free under the default, gray under Table 9.2.
    assert!(p_at(s.pane(0).unwrap(), 3.0, 0.0) < FREE);
    assert!(p_at(s.pane(1).unwrap(), 3.0, 0.0) > FREE);
    // Dropping the comparison drops the pane.
    s.configure(LogMapSettings::default()).unwrap();
    assert_eq!(s.state().panes.len(), 1);
}

/// Floor between two beams' axes, where they part by more than a cell, is
/// free under the defaults (each beam as wide as the beam spacing, Table
/// 9.2's β); with thin beams it stays gray in one-cell pinholes.
#[test]
fn floor_between_neighbouring_beams_is_free_under_the_defaults() {
    // A wall 10 m ahead; between beams 90 (bearing 0) and 91 (1°), 8 m
    // out, they are 14 cm apart, and the cell midway lies on neither.
    let bytes = flaser_log(&[(0.0, 0.0, 0.0, vec![10.0; 180])]);
    let (x, y) = (
        8.0 * 0.5f64.to_radians().cos(),
        8.0 * 0.5f64.to_radians().sin(),
    );
    let run = |between_beams: bool| {
        let mut b = pane(
            &bytes,
            LogMapSettings {
                between_beams,
                ..LogMapSettings::default()
            },
        );
        b.advance(usize::MAX);
        p_at(&b, x, y)
    };
    assert!(LogMapSettings::default().between_beams);
    assert!(!LogMapSettings::chapter().between_beams);
    let (wide, thin) = (run(true), run(false));
    assert!(wide < FREE, "p = {wide}");
    assert_eq!(thin, 0.5, "never crossed: unknown");
}

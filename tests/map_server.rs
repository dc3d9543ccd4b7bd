#![cfg(not(target_arch = "wasm32"))]
//! The ROS `map_server` pair: the YAML and PGM follow the format exactly,
//! and the PGM read back matches the map cell by cell.

use occgrid::apps::real_log::{LogMapSettings, LogPane};
use occgrid::geometry::GridGeometry;
use occgrid::grid::{probability, FilterSettings, LogOddsGrid};
use occgrid::io::carmen::read_scans;
use occgrid::io::map_server::{map_server_pair, read_pgm, FREE_THRESH, OCCUPIED_THRESH};

fn datasets() -> std::path::PathBuf {
    std::env::var_os("OCCGRID_DATASETS")
        .map(Into::into)
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/datasets").into())
}

/// A 7 x 5 map at 5 cm whose lower-left corner is at (-1.25 m, 2.5 m),
/// with one cell in each state.
fn small_map() -> LogOddsGrid {
    let g = GridGeometry::new(7, 5, 0.05, -1.25, 2.5).unwrap();
    let mut m = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
    m.apply(g.index(0, 0), 2.0); // south-west corner: occupied (p = 0.88)
    m.apply(g.index(6, 4), -2.0); // north-east corner: free (p = 0.12)
    m.apply(g.index(3, 2), 0.2); // centre: measured but undecided (p = 0.55)
    m
}

/// The gray level map_server's trinary convention gives a probability,
/// computed here independently of the exporter.
fn expected_gray(grid: &LogOddsGrid, i: usize) -> u8 {
    let l = grid.log_odds()[i];
    let p = probability(l as f64);
    if l == grid.l0() {
        205
    } else if p > 0.65 {
        0
    } else if p < 0.196 {
        254
    } else {
        205
    }
}

fn split_header(pgm: &[u8]) -> (String, &[u8]) {
    // P5, one comment, size, maxval: four newline-terminated lines.
    let mut end = 0;
    for _ in 0..4 {
        end += pgm[end..].iter().position(|&b| b == b'\n').unwrap() + 1;
    }
    (String::from_utf8(pgm[..end].to_vec()).unwrap(), &pgm[end..])
}

#[test]
fn the_yaml_names_image_resolution_lower_left_origin_and_thresholds() {
    let pair = map_server_pair(&small_map(), "lab.pgm");
    assert_eq!(
        pair.yaml,
        "image: lab.pgm\n\
         mode: trinary\n\
         resolution: 0.05\n\
         origin: [-1.25, 2.5, 0.0]\n\
         negate: 0\n\
         occupied_thresh: 0.65\n\
         free_thresh: 0.196\n"
    );
    assert_eq!((OCCUPIED_THRESH, FREE_THRESH), (0.65, 0.196));
    let unnamed = map_server_pair(&small_map(), "");
    assert!(unnamed.yaml.starts_with("image: map.pgm\n"));
    let spaced = map_server_pair(&small_map(), "my lab.pgm");
    assert!(spaced.yaml.starts_with("image: \"my lab.pgm\"\n"));
}

#[test]
fn the_pgm_has_a_p5_header_one_byte_per_cell_and_only_the_three_gray_levels() {
    let pair = map_server_pair(&small_map(), "lab.pgm");
    let (header, raster) = split_header(&pair.pgm);
    assert_eq!(header, "P5\n# CREATOR: occgrid 0.050 m/pix\n7 5\n255\n");
    assert_eq!(raster.len(), 7 * 5);
    assert!(raster.iter().all(|g| [0, 205, 254].contains(g)));
    // North up: the first image row is the grid's top row (iy = 4), whose
    // last pixel is the free north-east cell; the last row's first pixel
    // is the occupied south-west cell.
    assert_eq!(raster[6], 254);
    assert_eq!(raster[4 * 7], 0);
    assert_eq!(
        raster[2 * 7 + 3],
        205,
        "p = 0.55 lies between the thresholds"
    );
    assert_eq!(raster.iter().filter(|&&g| g == 205).count(), 33);
}

#[test]
fn the_origin_puts_a_world_point_on_the_pixel_map_server_gives_it() {
    // An occupied cell at a known world point; map_server's reading of the
    // pair must place the black pixel's cell around that point.
    let g = GridGeometry::new(40, 30, 0.1, -3.2, 1.7).unwrap();
    let mut m = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
    let (wx, wy) = (-0.93, 3.44);
    let (ix, iy) = g.world_to_cell(wx, wy).unwrap();
    m.apply(g.index(ix, iy), 3.0);
    let pair = map_server_pair(&m, "p.pgm");
    let pgm = read_pgm(&pair.pgm).unwrap();
    let black: Vec<(usize, usize)> = (0..pgm.height)
        .flat_map(|row| (0..pgm.width).map(move |col| (col, row)))
        .filter(|&(c, r)| pgm.at(c, r) == Some(0))
        .collect();
    assert_eq!(black.len(), 1);
    let (col, row) = black[0];
    // The loader flips rows (pixel row 0 is the top) and puts the
    // lower-left corner of the lower-left pixel at `origin`.
    let origin: Vec<f64> = pair
        .yaml
        .lines()
        .find_map(|l| l.strip_prefix("origin: ["))
        .unwrap()
        .trim_end_matches(']')
        .split(", ")
        .map(|v| v.parse().unwrap())
        .collect();
    let res = 0.1;
    let cell_y = pgm.height - 1 - row;
    let (x0, y0) = (
        origin[0] + col as f64 * res,
        origin[1] + cell_y as f64 * res,
    );
    assert!(
        x0 <= wx && wx < x0 + res,
        "x: [{x0}, {}) misses {wx}",
        x0 + res
    );
    assert!(
        y0 <= wy && wy < y0 + res,
        "y: [{y0}, {}) misses {wy}",
        y0 + res
    );
    assert_eq!(origin[2], 0.0);
}

#[test]
fn the_intel_map_read_back_from_its_pgm_matches_every_cell() {
    let bytes = std::fs::read(datasets().join("intel-corrected.log.gz")).unwrap();
    let scans = read_scans(&bytes[..]).unwrap();
    let mut build = LogPane::new(scans, LogMapSettings::chapter()).unwrap();
    build.advance(usize::MAX);
    let grid = &build.grid().to_dense().unwrap();
    let geo = *grid.geometry();
    let pair = map_server_pair(grid, "intel.pgm");
    let pgm = read_pgm(&pair.pgm).unwrap();
    assert_eq!(
        (pgm.width, pgm.height, pgm.max_value),
        (geo.width(), geo.height(), 255)
    );
    assert_eq!(pgm.comments, [" CREATOR: occgrid 0.050 m/pix"]);
    let mut counts = [0usize; 3];
    for row in 0..pgm.height {
        for col in 0..pgm.width {
            let i = geo.index(col, geo.height() - 1 - row);
            let gray = pgm.at(col, row).unwrap();
            assert_eq!(gray, expected_gray(grid, i), "pixel ({col}, {row})");
            counts[match gray {
                0 => 0,
                254 => 1,
                _ => 2,
            }] += 1;
        }
    }
    // A building and the clearing its no-returns carve: the chapter's
    // no-returns clear 30 m through windows and doors, and the map's
    // extent holds all of it (1657 x 1597 cells; 850 x 811 with the
    // real-log default's 5 m clearing): walls under one percent of the map,
    // free space an
    // eighth (with l_free = -0.40, one or two free readings leave p at
    // 0.40 or 0.31, above free_thresh), the rest gray.
    let n = geo.len() as f64;
    let [occ, free, unknown] = counts.map(|c| c as f64 / n);
    assert!(occ > 0.005 && occ < 0.02, "occupied {occ}");
    assert!(free > 0.08 && free < 0.3, "free {free}");
    assert!(unknown > 0.6 && unknown < 0.95, "unknown {unknown}");
    let origin_line = format!("origin: [{}, {}, 0.0]", geo.origin()[0], geo.origin()[1]);
    assert!(pair.yaml.contains(&origin_line), "{}", pair.yaml);
    // The log's extent, snapped outwards to whole cells, reads cleanly.
    assert!(
        pair.yaml.contains("origin: [-37.7, -48.85, 0.0]"),
        "{}",
        pair.yaml
    );
}

/// Reads a stored zip back with the standard layout: the end record, the
/// central directory, each local header, and checks every CRC.
fn unzip(zip: &[u8]) -> Vec<(String, Vec<u8>)> {
    let u16at = |i: usize| u16::from_le_bytes([zip[i], zip[i + 1]]) as usize;
    let u32at = |i: usize| u32::from_le_bytes(zip[i..i + 4].try_into().unwrap()) as usize;
    let end = zip.len() - 22;
    assert_eq!(u32at(end), 0x0605_4b50, "end of central directory");
    let (count, cd_offset) = (u16at(end + 10), u32at(end + 16));
    let mut at = cd_offset;
    let mut files = Vec::new();
    for _ in 0..count {
        assert_eq!(u32at(at), 0x0201_4b50, "central directory header");
        let (crc, size, name_len, local) = (
            u32at(at + 16),
            u32at(at + 24),
            u16at(at + 28),
            u32at(at + 42),
        );
        let name = String::from_utf8(zip[at + 46..at + 46 + name_len].to_vec()).unwrap();
        assert_eq!(u32at(local), 0x0403_4b50, "local header");
        assert_eq!(u16at(local + 8), 0, "stored");
        let data_at = local + 30 + u16at(local + 26) + u16at(local + 28);
        let data = zip[data_at..data_at + size].to_vec();
        let mut c = flate2::Crc::new();
        c.update(&data);
        assert_eq!(c.sum() as usize, crc, "{name}: crc");
        files.push((name, data));
        at += 46 + name_len;
    }
    files
}

#[test]
fn the_zip_holds_the_pgm_and_a_yaml_that_names_it() {
    let pair = map_server_pair(&small_map(), "whatever.pgm");
    let (file, zip) = occgrid::io::map_server::zip_pair(&pair, "intel lab/map");
    assert_eq!(file, "intel_lab_map.zip");
    let files = unzip(&zip);
    assert_eq!(files.len(), 2);
    assert_eq!(files[0].0, "intel_lab_map.pgm");
    assert_eq!(files[0].1, pair.pgm);
    assert_eq!(files[1].0, "intel_lab_map.yaml");
    let yaml = String::from_utf8(files[1].1.clone()).unwrap();
    assert_eq!(
        yaml,
        pair.yaml
            .replace("image: whatever.pgm", "image: intel_lab_map.pgm")
    );
    // Deterministic: the same map gives the same bytes.
    assert_eq!(
        occgrid::io::map_server::zip_pair(&pair, "intel lab/map").1,
        zip
    );
    assert_eq!(occgrid::io::map_server::zip_pair(&pair, "").0, "map.zip");
    assert_eq!(
        occgrid::io::map_server::zip_pair(&pair, "../..").0,
        "_...zip",
        "no path"
    );
}

/// The YAML's fields as `map_server` reads them (flat `key: value` lines).
fn yaml_field(yaml: &str, key: &str) -> f64 {
    yaml.lines()
        .find_map(|l| l.strip_prefix(&format!("{key}: ")))
        .unwrap_or_else(|| panic!("no {key} in {yaml}"))
        .parse()
        .unwrap()
}

/// What `map_server` makes of the pair: each pixel's `occ = (255 - gray) /
/// 255` (negate 0), occupied if above `occupied_thresh`, free if below
/// `free_thresh`, unknown otherwise; the three counts.
fn loaded_by_map_server(pair: &occgrid::io::map_server::MapServerPair) -> [usize; 3] {
    let occ_t = yaml_field(&pair.yaml, "occupied_thresh");
    let free_t = yaml_field(&pair.yaml, "free_thresh");
    assert_eq!(yaml_field(&pair.yaml, "negate"), 0.0);
    let pgm = read_pgm(&pair.pgm).unwrap();
    let mut counts = [0usize; 3];
    for &gray in &pgm.pixels {
        let occ = (255.0 - gray as f64) / 255.0;
        counts[if occ > occ_t {
            0
        } else if occ < free_t {
            1
        } else {
            2
        }] += 1;
    }
    counts
}

#[test]
fn map_server_loads_unknown_gray_as_unknown_and_the_counts_agree_with_the_file() {
    // Gray 205 on its own, as map_server reads it under the YAML.
    let pair = map_server_pair(&small_map(), "m.pgm");
    let pgm = read_pgm(&pair.pgm).unwrap();
    let gray = pgm.pixels.iter().filter(|&&g| g == 205).count();
    assert!(gray > 0);
    let [_, free, unknown] = loaded_by_map_server(&pair);
    assert_eq!((free, unknown), (1, gray), "gray 205 must load as unknown");

    // A real log: what the session counts (the panel's and the CLI's
    // figures) is what map_server loads from the exported pair.
    let bytes = std::fs::read(datasets().join("aces-corrected.log.gz")).unwrap();
    let mut session = occgrid::apps::real_log::RealLogSession::new(bytes);
    while !session.read(usize::MAX).unwrap().progress.finished {}
    while !session.build_chunk(usize::MAX).unwrap().finished {}
    let pair = session.pane(0).unwrap().export_map(Some("aces"));
    let c = session.pane(0).unwrap().counts();
    let loaded = loaded_by_map_server(&pair);
    assert_eq!([c.occupied, c.free, c.unknown], loaded);
    assert_eq!(c.cells, loaded.iter().sum::<usize>());
    assert_eq!(
        (c.occupied_thresh, c.free_thresh),
        (
            yaml_field(&pair.yaml, "occupied_thresh"),
            yaml_field(&pair.yaml, "free_thresh")
        )
    );
    assert!(loaded[2] > 0 && loaded[1] > 0 && loaded[0] > 0);
}

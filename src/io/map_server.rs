//! Export of a map as a ROS `map_server` pair: a trinary PGM image and the
//! YAML file that tells `map_server` (ROS 1) or `nav2_map_server` how to read
//! it (docs/ARCHITECTURE.md, "Real logs").
//!
//! This is the last step of the data flow: any [`Grid`] a widget has
//! built (a simulated lap, a real log) leaves the project through
//! [`map_server_pair`]; [`zip_pair`] packs the two files into one download
//! whose names agree with the YAML. [`read_pgm`] reads such an image back,
//! so the tests can check the round trip cell by cell.
//!
//! The format, as the loader reads it:
//!
//! * The image is a binary greymap (`P5`, maxval 255), one pixel per cell,
//!   its first row the map's northernmost row: the loader flips the rows so
//!   that cell (0, 0) is the lower-left pixel.
//! * A trinary map holds three gray levels only: occupied 0 (black),
//!   free 254 (white) and unknown 205 (gray), the levels `map_saver` writes.
//! * The loader turns a pixel of gray `g` into `occ = (255 - g) / 255`
//!   (with `negate: 0`); `occ > occupied_thresh` is occupied,
//!   `occ < free_thresh` is free, anything else unknown.
//! * `origin` is the world pose `[x, y, yaw]` of the lower-left corner of
//!   the lower-left pixel, metres and radians: exactly the grid's origin.

use crate::error::{OccError, Result};
use crate::grid::cell::{Thresholds, Verdict};
use crate::grid::stats::{count_states_between, StateCounts};
use crate::grid::{CellModel, Grid, Store};

/// `occupied_thresh` of the YAML: a cell with `p > 0.65` is exported as
/// occupied.
pub const OCCUPIED_THRESH: f64 = 0.65;
/// `free_thresh` of the YAML: a cell with `p < 0.196` is exported as free.
///
/// ROS 1 `map_saver`'s value (docs/ARCHITECTURE.md, "Real logs"): the loader reads
/// the unknown gray 205 as `occ = 50 / 255 = 0.19608`, just above it, so
/// unknown cells load as unknown. With any higher value (ROS 2's default
/// 0.25) `map_server` and `nav2_map_server` would load every unknown cell as
/// *free*, and a planner would drive into space nobody has seen.
///
/// These two constants are the only thresholds of an export: the image
/// ([`trinary_gray`]), the YAML and the counts a page or the CLI shows for
/// it ([`export_counts`]) all read them.
pub const FREE_THRESH: f64 = 0.196;
/// Gray level of an occupied cell.
pub const PGM_OCCUPIED: u8 = 0;
/// Gray level of a free cell.
pub const PGM_FREE: u8 = 254;
/// Gray level of an unknown cell (and of a cell between the thresholds:
/// a trinary map has no fourth level for "undecided").
pub const PGM_UNKNOWN: u8 = 205;

/// The image used when the caller gives an empty name.
const DEFAULT_IMAGE: &str = "map.pgm";

/// A map as `map_server` loads it: the PGM bytes and the YAML text whose
/// `image:` line names the PGM file (relative to the YAML file).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MapServerPair {
    pub pgm: Vec<u8>,
    pub yaml: String,
}

/// The trinary gray level of a cell: unknown if the cell still holds the
/// prior (whatever the prior is: a cell nobody measured is not free just
/// because the prior was low), else occupied above [`OCCUPIED_THRESH`],
/// free below [`FREE_THRESH`], unknown in between: the cell's
/// [`Verdict`] under the export's thresholds, the one [`export_counts`]
/// counts. The comparisons are strict, as in the loader.
pub fn trinary_gray<M: CellModel>(model: &M, cell: M::Cell) -> u8 {
    gray_of(model, cell, &drawing_thresholds(model))
}

/// The thresholds of an export: [`OCCUPIED_THRESH`] and [`FREE_THRESH`].
pub fn export_thresholds() -> Thresholds {
    Thresholds::new(OCCUPIED_THRESH, FREE_THRESH)
}

/// The thresholds `model`'s cells are drawn by: the export's own
/// ([`export_thresholds`]), or the model's where it states its own
/// ([`CellModel::trinary_cut`]; the YAML then says so). The YAML's
/// `occupied_thresh` and `free_thresh` read the image's three gray levels
/// and stay the export's either way.
pub fn drawing_thresholds<M: CellModel>(model: &M) -> Thresholds {
    cut_thresholds(model.trinary_cut())
}

/// The thresholds of a model's [`CellModel::trinary_cut`].
pub fn cut_thresholds(cut: Option<(f64, f64)>) -> Thresholds {
    let (occupied, free) = cut.unwrap_or((OCCUPIED_THRESH, FREE_THRESH));
    Thresholds::new(occupied, free)
}

#[inline]
fn gray_of<M: CellModel>(model: &M, cell: M::Cell, thresholds: &Thresholds) -> u8 {
    match model.verdict(cell, thresholds) {
        Verdict::Occupied => PGM_OCCUPIED,
        Verdict::Free => PGM_FREE,
        Verdict::Unknown | Verdict::Undecided => PGM_UNKNOWN,
    }
}

/// What an exported map holds, counted with the thresholds its YAML states:
/// cells that load as occupied (gray 0), free (254) and unknown (205: never
/// measured, or measured but between the thresholds).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ExportCounts {
    pub occupied: usize,
    pub free: usize,
    pub unknown: usize,
    pub cells: usize,
    /// The YAML's `occupied_thresh`: occupied means `p >` this.
    pub occupied_thresh: f64,
    /// The YAML's `free_thresh`: free means `p <` this.
    pub free_thresh: f64,
}

/// The cells of `grid` as its export would show them ([`map_server_pair`]).
pub fn export_counts<M: CellModel, S: Store<M::Cell>>(grid: &Grid<M, S>) -> ExportCounts {
    let t = drawing_thresholds(grid.model());
    ExportCounts::from_states(count_states_between(
        grid,
        t.occupied_above(),
        t.free_below(),
    ))
}

impl ExportCounts {
    /// The export's counts from cells counted between its thresholds
    /// (`OCCUPIED_THRESH`, `FREE_THRESH`), however they were counted.
    pub fn from_states(s: StateCounts) -> Self {
        Self {
            occupied: s.occupied,
            free: s.free,
            unknown: s.cells - s.occupied - s.free,
            cells: s.cells,
            occupied_thresh: OCCUPIED_THRESH,
            free_thresh: FREE_THRESH,
        }
    }
}

/// Exports `grid` as a `map_server` pair whose YAML points at
/// `image_name` (an empty name becomes `map.pgm`; a name that is not a
/// plain YAML scalar is written quoted). The image covers the whole map;
/// cells no storage holds are unknown gray 205. Cannot fail: every grid has
/// a valid size, resolution and origin by construction.
pub fn map_server_pair<M: CellModel, S: Store<M::Cell>>(
    grid: &Grid<M, S>,
    image_name: &str,
) -> MapServerPair {
    let g = grid.geometry();
    let (w, h) = (g.width(), g.height());
    let header = format!(
        "P5\n# CREATOR: occgrid {:.3} m/pix\n{w} {h}\n255\n",
        g.resolution()
    );
    let mut pgm = Vec::with_capacity(header.len() + w * h);
    pgm.extend_from_slice(header.as_bytes());
    let model = grid.model();
    let thresholds = drawing_thresholds(model);
    // Image rows run north to south, grid rows south to north.
    for iy in (0..h).rev() {
        grid.store().row_runs(iy, |run| match run.cells {
            None => pgm.extend(std::iter::repeat_n(PGM_UNKNOWN, run.len)),
            Some((cells, _)) => pgm.extend(cells.iter().map(|&c| gray_of(model, c, &thresholds))),
        });
    }
    let yaml = yaml_text(g.resolution(), g.origin(), image_name);
    MapServerPair { pgm, yaml }
}

/// The YAML of a pair: the image's name, the grid's resolution and origin,
/// and the export's thresholds.
fn yaml_text(resolution: f64, [ox, oy]: [f64; 2], image_name: &str) -> String {
    let name = if image_name.is_empty() {
        DEFAULT_IMAGE
    } else {
        image_name
    };
    format!(
        "image: {}\nmode: trinary\nresolution: {}\norigin: [{}, {}, 0.0]\nnegate: 0\noccupied_thresh: {}\nfree_thresh: {}\n",
        yaml_string(name),
        yaml_number(resolution),
        yaml_number(ox),
        yaml_number(oy),
        yaml_number(OCCUPIED_THRESH),
        yaml_number(FREE_THRESH),
    )
}

/// A number as YAML reads it back exactly: Rust's shortest round-trip
/// decimal (never an exponent), with a decimal point so that YAML 1.1
/// loaders see a float, and without the sign of a negative zero.
fn yaml_number(v: f64) -> String {
    let s = format!("{}", v + 0.0);
    if s.contains('.') {
        s
    } else {
        format!("{s}.0")
    }
}

/// A file name as a YAML scalar: bare when it is plainly safe (as
/// `map_saver` writes it), double-quoted with escapes otherwise.
fn yaml_string(s: &str) -> String {
    let plain = s
        .bytes()
        .enumerate()
        .all(|(k, b)| b.is_ascii_alphanumeric() || b == b'_' || (k > 0 && b".-/".contains(&b)));
    if plain {
        return s.to_string();
    }
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 || c == '\u{7f}' => {
                out.push_str(&format!("\\x{:02x}", c as u32))
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A file name's stem for a download: ASCII letters, digits, `.`, `_` and
/// `-` kept, anything else (path separators included) turned into `_`, at
/// most 100 characters; an empty stem becomes `map`.
pub fn file_stem(name: &str) -> String {
    let stem: String = name
        .chars()
        .take(100)
        .map(|c| {
            if c.is_ascii_alphanumeric() || "._-".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    let stem = stem.trim_start_matches('.');
    if stem.is_empty() {
        "map".to_string()
    } else {
        stem.to_string()
    }
}

/// The pair as one zip archive (stored, not compressed) holding
/// `STEM.pgm` and `STEM.yaml`, where `STEM` is [`file_stem`] of `name`; the
/// YAML's `image:` line is rewritten to `STEM.pgm` so that the pair stays
/// loadable whatever name the image was exported under. The archive is the
/// same bytes for the same input (its timestamps are the zip epoch,
/// 1980-01-01).
pub fn zip_pair(pair: &MapServerPair, name: &str) -> (String, Vec<u8>) {
    let stem = file_stem(name);
    let image = format!("{stem}.pgm");
    let body = pair
        .yaml
        .split_once('\n')
        .filter(|(first, _)| first.starts_with("image:"))
        .map_or(pair.yaml.as_str(), |(_, rest)| rest);
    let yaml = format!("image: {image}\n{body}");
    let entries = [
        (image, pair.pgm.as_slice()),
        (format!("{stem}.yaml"), yaml.as_bytes()),
    ];
    (format!("{stem}.zip"), stored_zip(&entries))
}

/// A zip archive of `entries` without compression (PKWARE APPNOTE 6.3:
/// local headers and data, the central directory, its end record; all
/// numbers little-endian).
fn stored_zip(entries: &[(String, &[u8])]) -> Vec<u8> {
    const DOS_DATE: u16 = (1 << 5) | 1; // 1980-01-01
    fn u16le(out: &mut Vec<u8>, v: u16) {
        out.extend_from_slice(&v.to_le_bytes());
    }
    fn u32le(out: &mut Vec<u8>, v: u32) {
        out.extend_from_slice(&v.to_le_bytes());
    }
    // Sizes fit in 32 bits: an image has at most 2^28 cells (a tiled map's
    // extent limit).
    let mut out = Vec::new();
    let mut central = Vec::new();
    for (name, data) in entries {
        let crc = super::gzip::crc32(data);
        let offset = out.len() as u32;
        // Version 1.0, no flags, method 0 (stored), time 0, date, crc,
        // sizes, name length, no extra field.
        let fields = |out: &mut Vec<u8>| {
            u16le(out, 10);
            u16le(out, 0);
            u16le(out, 0);
            u16le(out, 0);
            u16le(out, DOS_DATE);
            u32le(out, crc);
            u32le(out, data.len() as u32);
            u32le(out, data.len() as u32);
            u16le(out, name.len() as u16);
            u16le(out, 0);
        };
        u32le(&mut out, 0x0403_4b50);
        fields(&mut out);
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(data);
        u32le(&mut central, 0x0201_4b50);
        u16le(&mut central, 20); // made by: version 2.0
        fields(&mut central);
        u16le(&mut central, 0); // comment length
        u16le(&mut central, 0); // disk number
        u16le(&mut central, 0); // internal attributes
        u32le(&mut central, 0); // external attributes
        u32le(&mut central, offset);
        central.extend_from_slice(name.as_bytes());
    }
    let (cd_offset, cd_size) = (out.len() as u32, central.len() as u32);
    out.extend_from_slice(&central);
    u32le(&mut out, 0x0605_4b50);
    u16le(&mut out, 0);
    u16le(&mut out, 0);
    u16le(&mut out, entries.len() as u16);
    u16le(&mut out, entries.len() as u16);
    u32le(&mut out, cd_size);
    u32le(&mut out, cd_offset);
    u16le(&mut out, 0);
    out
}

/// A binary greymap (`P5`) read back: `pixels` row by row from the top,
/// `width * height` bytes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Pgm {
    pub width: usize,
    pub height: usize,
    pub max_value: u16,
    pub pixels: Vec<u8>,
    /// The comment lines of the header, without their `#`.
    pub comments: Vec<String>,
}

impl Pgm {
    /// Gray level of the pixel in image column `col`, row `row` (row 0 at
    /// the top), or `None` outside the image.
    pub fn at(&self, col: usize, row: usize) -> Option<u8> {
        if col >= self.width || row >= self.height {
            return None;
        }
        self.pixels.get(row * self.width + col).copied()
    }
}

/// Reads a binary greymap with 8-bit samples (maxval 1 to 255), the kind
/// [`map_server_pair`] writes. Strict: the raster must be exactly
/// `width * height` bytes after the single whitespace byte that ends the
/// header. Errors name the header line they were found on.
pub fn read_pgm(bytes: &[u8]) -> Result<Pgm> {
    let mut pos = 0;
    let mut line = 1;
    let err = |line: usize, reason: String| OccError::Parse { line, reason };
    if bytes.get(0..2) != Some(b"P5".as_slice()) {
        return Err(err(
            1,
            "not a binary PGM: the file does not start with P5".into(),
        ));
    }
    pos += 2;
    let mut comments = Vec::new();
    let mut fields = [0usize; 3];
    for (k, name) in ["width", "height", "maxval"].iter().enumerate() {
        // Whitespace and comments before each field.
        loop {
            match bytes.get(pos) {
                Some(b'\n') => {
                    line += 1;
                    pos += 1;
                }
                Some(b) if b.is_ascii_whitespace() => pos += 1,
                Some(b'#') => {
                    let end = bytes[pos..]
                        .iter()
                        .position(|&b| b == b'\n')
                        .map_or(bytes.len(), |n| pos + n);
                    comments.push(String::from_utf8_lossy(&bytes[pos + 1..end]).into_owned());
                    pos = end;
                }
                _ => break,
            }
        }
        let start = pos;
        while bytes.get(pos).is_some_and(u8::is_ascii_digit) {
            pos += 1;
        }
        let digits = std::str::from_utf8(&bytes[start..pos]).unwrap_or("");
        let value: usize = digits
            .parse()
            .map_err(|_| err(line, format!("PGM {name} is missing or not a whole number")))?;
        fields[k] = value;
    }
    let [width, height, max_value] = fields;
    if width == 0 || height == 0 {
        return Err(err(
            line,
            format!("PGM size must be at least 1 x 1, found {width} x {height}"),
        ));
    }
    if !(1..=255).contains(&max_value) {
        return Err(err(
            line,
            format!("PGM maxval must be 1 to 255 (8-bit samples), found {max_value}"),
        ));
    }
    match bytes.get(pos) {
        Some(b) if b.is_ascii_whitespace() => pos += 1,
        _ => {
            return Err(err(
                line,
                "PGM header must end with one whitespace byte after maxval".into(),
            ))
        }
    }
    let n = width
        .checked_mul(height)
        .ok_or_else(|| err(line, format!("PGM size {width} x {height} is too large")))?;
    let raster = &bytes[pos..];
    if raster.len() != n {
        return Err(err(
            line,
            format!(
                "PGM raster holds {} bytes, expected width x height = {n}",
                raster.len()
            ),
        ));
    }
    Ok(Pgm {
        width,
        height,
        max_value: max_value as u16,
        pixels: raster.to_vec(),
        comments,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::GridGeometry;
    use crate::grid::FilterSettings;
    use crate::grid::LogOddsGrid;

    #[test]
    fn yaml_numbers_keep_a_decimal_point_and_round_trip() {
        assert_eq!(yaml_number(-25.0), "-25.0");
        assert_eq!(yaml_number(0.05), "0.05");
        assert_eq!(yaml_number(-0.0), "0.0");
        assert_eq!(yaml_number(1e-7), "0.0000001");
        let v = -12.345678901234567;
        assert_eq!(yaml_number(v).parse::<f64>().unwrap(), v);
    }

    #[test]
    fn image_names_are_quoted_only_when_needed() {
        assert_eq!(yaml_string("intel-map.pgm"), "intel-map.pgm");
        assert_eq!(yaml_string("maps/a_1.pgm"), "maps/a_1.pgm");
        assert_eq!(yaml_string("my map.pgm"), "\"my map.pgm\"");
        assert_eq!(yaml_string("-x.pgm"), "\"-x.pgm\"");
        assert_eq!(yaml_string("a\"b\n.pgm"), "\"a\\\"b\\n.pgm\"");
        assert_eq!(yaml_string("a: b"), "\"a: b\"");
    }

    #[test]
    fn cells_between_the_thresholds_and_at_the_prior_are_unknown_gray() {
        let g = GridGeometry::new(4, 1, 0.1, 0.0, 0.0).unwrap();
        let mut m = LogOddsGrid::new(
            g,
            FilterSettings {
                prior: 0.1,
                clamp: 10.0,
            },
        )
        .unwrap();
        // Cell 0 stays at the prior 0.1: below free_thresh, yet unknown.
        m.apply(1, 3.0); // p = 0.69
        m.apply(2, 2.0); // p = 0.45
        m.apply(3, -1.0); // p = 0.04
        let grays: Vec<u8> = (0..4)
            .map(|i| trinary_gray(m.model(), m.log_odds()[i]))
            .collect();
        assert_eq!(grays, [205, 0, 205, 254]);
    }

    #[test]
    fn pgm_reader_rejects_damaged_headers_with_their_line() {
        assert!(read_pgm(b"P2\n1 1\n255\n\x00").is_err());
        let e = read_pgm(b"P5\n# c\n2 x\n255\n").unwrap_err();
        assert_eq!(
            e,
            OccError::Parse {
                line: 3,
                reason: "PGM height is missing or not a whole number".into()
            }
        );
        let e = read_pgm(b"P5\n2 2\n255\n\x00\x00\x00").unwrap_err();
        assert!(e.to_string().contains("3 bytes"), "{e}");
        assert!(read_pgm(b"P5\n2 2\n65535\n\x00\x00\x00\x00")
            .unwrap_err()
            .to_string()
            .contains("maxval"));
        assert!(read_pgm(b"P5\n0 2\n255\n").is_err());
        assert!(read_pgm(b"P5\n99999999999999999999 2\n255\n").is_err());
        let p = read_pgm(b"P5 # c1\n# c2\n2 1 255 \x07\x08").unwrap();
        assert_eq!((p.width, p.height, p.at(1, 0)), (2, 1, Some(8)));
        assert_eq!(p.comments, [" c1", " c2"]);
    }

    #[test]
    fn tiled_export_covers_the_whole_extent_and_matches_the_dense_export() {
        use crate::geometry::GridGeometry;
        use crate::grid::TiledGrid;
        let e = GridGeometry::sparse(130, 70, 0.05, -2.0, 1.0).unwrap();
        let mut t = TiledGrid::new(e, FilterSettings::default(), 1 << 20).unwrap();
        t.apply_at(3, 2, 2.0);
        t.apply_at(129, 69, -2.0);
        t.apply_at(70, 40, -0.1); // between the thresholds
        let dense = t.to_dense().unwrap();
        assert_eq!(t.tiles_allocated(), 3);
        assert_eq!(
            map_server_pair(&t, "m.pgm"),
            map_server_pair(&dense, "m.pgm")
        );
        assert_eq!(export_counts(&t), export_counts(&dense));
        let pgm = read_pgm(&map_server_pair(&t, "m.pgm").pgm).unwrap();
        assert_eq!((pgm.width, pgm.height), (130, 70));
        assert_eq!(pgm.at(100, 10), Some(PGM_UNKNOWN), "a tile never touched");
        assert_eq!(pgm.at(3, 67), Some(PGM_OCCUPIED));
        assert_eq!(pgm.at(129, 0), Some(PGM_FREE));
    }
}

//! `io::gzip` against a reference: flate2 writes the files and reads them
//! back, and the reader must give the same bytes, or refuse what flate2
//! refuses, in the right words.

use flate2::write::GzEncoder;
use flate2::{Compression, GzBuilder};
use occgrid::io::gzip::{crc32, GzipReader};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::io::{ErrorKind, Read, Write};

fn datasets() -> std::path::PathBuf {
    std::env::var_os("OCCGRID_DATASETS")
        .map(Into::into)
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/datasets").into())
}

fn gzip(data: &[u8], level: u32) -> Vec<u8> {
    let mut gz = GzEncoder::new(Vec::new(), Compression::new(level));
    gz.write_all(data).unwrap();
    gz.finish().unwrap()
}

/// Everything `GzipReader` gives for `bytes`, read `chunk` bytes at a time.
fn ours(bytes: &[u8], chunk: usize) -> std::io::Result<Vec<u8>> {
    let mut reader = GzipReader::new(std::io::BufReader::with_capacity(chunk.max(1), bytes));
    let mut out = Vec::new();
    let mut buf = vec![0u8; chunk];
    loop {
        let n = reader.read(&mut buf)?;
        if n == 0 {
            return Ok(out);
        }
        out.extend_from_slice(&buf[..n]);
    }
}

fn reference(bytes: &[u8]) -> std::io::Result<Vec<u8>> {
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(bytes).read_to_end(&mut out)?;
    Ok(out)
}

#[test]
fn the_crc_is_the_one_of_gzip_and_zip() {
    // The check value of CRC-32/ISO-HDLC.
    assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
    assert_eq!(crc32(b""), 0);
    let mut rng = StdRng::seed_from_u64(1);
    let data: Vec<u8> = (0..10_000).map(|_| rng.random()).collect();
    let mut reference = flate2::Crc::new();
    reference.update(&data);
    assert_eq!(crc32(&data), reference.sum());
}

#[test]
fn every_dataset_inflates_to_the_same_bytes_as_the_reference_reader() {
    let mut read = 0;
    for entry in std::fs::read_dir(datasets()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "gz") {
            let bytes = std::fs::read(&path).unwrap();
            let expected = reference(&bytes).unwrap();
            assert_eq!(ours(&bytes, 64 * 1024).unwrap(), expected, "{path:?}");
            read += 1;
        }
    }
    assert_eq!(read, 6, "the six logs");
}

#[test]
fn any_read_size_and_any_level_give_the_same_bytes() {
    let mut rng = StdRng::seed_from_u64(2);
    // Text that compresses (a log's digits) and bytes that do not.
    let mut data = Vec::new();
    for k in 0..3000 {
        writeln!(data, "FLASER 3 1.{k} 2.5 {:.3} 0 0 0", rng.random::<f64>()).unwrap();
    }
    data.extend((0..20_000).map(|_| rng.random::<u8>()));
    for level in [0, 1, 6, 9] {
        let gz = gzip(&data, level);
        for chunk in [1, 7, 512, 65_536] {
            assert_eq!(
                ours(&gz, chunk).unwrap(),
                data,
                "level {level}, chunk {chunk}"
            );
        }
    }
    assert_eq!(ours(&gzip(b"", 6), 10).unwrap(), b"");
}

#[test]
fn members_one_after_another_read_as_one_file() {
    let mut cat = gzip(b"first line\n", 6);
    cat.extend(gzip(b"", 6));
    cat.extend(gzip(b"second line\n", 9));
    assert_eq!(ours(&cat, 3).unwrap(), b"first line\nsecond line\n");
    assert_eq!(reference(&cat).unwrap(), b"first line\nsecond line\n");
}

#[test]
fn optional_header_fields_are_skipped_and_the_header_crc_checked() {
    let build = |crc: bool| {
        let mut gz = GzBuilder::new()
            .filename("intel.log")
            .comment("a comment of some length ".repeat(40))
            .extra(vec![7u8; 300])
            .mtime(12345)
            .write(Vec::new(), Compression::default());
        gz.write_all(b"ODOM 1 2 3\n").unwrap();
        let mut bytes = gz.finish().unwrap();
        if crc {
            // Set FHCRC and insert the header's CRC-16 before the data.
            let header_end = header_len(&bytes);
            bytes[3] |= 2;
            let crc16 = (crc32(&bytes[..header_end]) as u16).to_le_bytes();
            bytes.splice(header_end..header_end, crc16);
        }
        bytes
    };
    assert_eq!(ours(&build(false), 5).unwrap(), b"ODOM 1 2 3\n");
    let with_crc = build(true);
    assert_eq!(ours(&with_crc, 5).unwrap(), b"ODOM 1 2 3\n");
    assert_eq!(reference(&with_crc).unwrap(), b"ODOM 1 2 3\n");
    // A header CRC that does not match is damage.
    let mut bad = with_crc.clone();
    let at = header_len(&build(false));
    bad[at] ^= 1;
    let e = ours(&bad, 5).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidData);
    assert!(e.to_string().contains("header"), "{e}");
}

/// Length of the header of a member flate2 wrote (FEXTRA, FNAME, FCOMMENT).
fn header_len(bytes: &[u8]) -> usize {
    let mut at = 10;
    let flags = bytes[3];
    if flags & 4 != 0 {
        at += 2 + u16::from_le_bytes([bytes[10], bytes[11]]) as usize;
    }
    for flag in [8, 16] {
        if flags & flag != 0 {
            at += bytes[at..].iter().position(|&b| b == 0).unwrap() + 1;
        }
    }
    at
}

#[test]
fn a_file_cut_anywhere_is_cut_short_and_what_came_before_it_is_kept() {
    let mut data = Vec::new();
    for k in 0..2000 {
        writeln!(data, "ODOM {k} 0 0 0 0 0 {k}").unwrap();
    }
    let gz = gzip(&data, 6);
    for cut in (1..gz.len())
        .step_by(97)
        .chain([gz.len() - 1, gz.len() - 8])
    {
        let mut reader = GzipReader::new(&gz[..cut]);
        let mut out = Vec::new();
        let e = reader.read_to_end(&mut out).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::UnexpectedEof, "cut at {cut}: {e}");
        // Whatever was given is the start of the file.
        assert!(data.starts_with(&out), "cut at {cut}");
        // And the reader stays ended.
        assert_eq!(reader.read(&mut [0u8; 16]).unwrap(), 0);
    }
}

#[test]
fn damage_is_refused_as_invalid_data_naming_what_is_wrong() {
    let data: Vec<u8> = (0..50_000u32)
        .flat_map(|k| (k % 251).to_le_bytes())
        .collect();
    let gz = gzip(&data, 6);
    let refused = |bytes: &[u8]| {
        let e = ours(bytes, 4096).unwrap_err();
        assert!(reference(bytes).is_err(), "the reference refuses it too");
        (e.kind(), e.to_string())
    };
    // The trailer's CRC, then its length.
    let mut bad = gz.clone();
    let n = bad.len();
    bad[n - 8] ^= 0x55;
    assert_eq!(
        refused(&bad),
        (
            ErrorKind::InvalidData,
            "the CRC of the inflated data does not match the file's".into()
        )
    );
    let mut bad = gz.clone();
    bad[n - 1] ^= 1;
    let (kind, text) = refused(&bad);
    assert_eq!(kind, ErrorKind::InvalidData);
    assert!(text.contains("not as long"), "{text}");
    // Another method than deflate, reserved flags.
    let mut bad = gz.clone();
    bad[2] = 7;
    assert!(refused(&bad).1.contains("method"));
    let mut bad = gz.clone();
    bad[3] = 0x80;
    assert!(refused(&bad).1.contains("reserved"));
    // Garbage after a member.
    let mut bad = gz.clone();
    bad.extend_from_slice(b"not gzip at all");
    assert!(refused(&bad).1.contains("not another one"));
    // Garbage in the deflate stream (a block type that does not exist).
    let mut bad = gzip(b"x", 6);
    bad[10] = 0xff;
    let (kind, _) = refused(&bad);
    assert_eq!(kind, ErrorKind::InvalidData);
}

#[test]
fn random_bytes_behind_the_magic_never_panic_or_hang() {
    let mut rng = StdRng::seed_from_u64(4);
    for _ in 0..2000 {
        let len = rng.random_range(0..300);
        let mut bytes = vec![0x1f, 0x8b, 8, rng.random_range(0..32)];
        bytes.extend((0..len).map(|_| rng.random::<u8>()));
        // Ends with data or with one of the two errors; never a panic.
        match ours(&bytes, rng.random_range(1..64)) {
            Ok(_) => {}
            Err(e) => assert!(
                matches!(e.kind(), ErrorKind::InvalidData | ErrorKind::UnexpectedEof),
                "{e:?}"
            ),
        }
    }
}

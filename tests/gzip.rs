//! `io::gzip` against a reference: flate2 writes the files and reads them
//! back, and the reader must give the same bytes, or refuse what flate2
//! refuses, in the right words. Then what the reference does not settle:
//! zero padding after the last member, reads paused anywhere and resumed,
//! and files that inflate to almost nothing, which the CARMEN loader must
//! read in calls bounded by their bytes.

use flate2::write::GzEncoder;
use flate2::{Compression, GzBuilder};
use occgrid::io::carmen::LogLoader;
use occgrid::io::gzip::{crc32, GzipReader};
use occgrid::io::LogBudget;
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

#[test]
fn zero_padding_after_the_last_member_is_read_as_the_end_of_the_file() {
    // Tape and block devices pad an archive with zeros; GNU gzip and
    // Python's gzip read it.
    let data = b"ODOM 1 2 3\nFLASER 1 2.5 0 0 0 0 0 0\n";
    for zeros in [1, 7, 512, 100_000] {
        let mut padded = gzip(data, 6);
        padded.extend(vec![0u8; zeros]);
        for chunk in [1, 5, 4096] {
            assert_eq!(ours(&padded, chunk).unwrap(), data, "{zeros} zeros");
        }
    }
    // Anything else after the padding is still damage, and so is a member
    // after it: padding ends the file.
    for tail in [&b"x"[..], &gzip(b"more\n", 6)[..]] {
        let mut bad = gzip(data, 6);
        bad.extend([0, 0, 0]);
        bad.extend_from_slice(tail);
        let e = ours(&bad, 4096).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::InvalidData);
        assert!(e.to_string().contains("zero bytes"), "{e}");
    }
    // Zeros where the first member should be are not padding.
    assert!(ours(&[0u8; 16], 16).is_err());
}

/// A `BufRead` over `bytes` that hands out `chunk` bytes at a time and says
/// "not now" (`WouldBlock`) before each: a caller bounding its input.
struct Stutter<'a> {
    bytes: &'a [u8],
    chunk: usize,
    ready: bool,
}

impl Read for Stutter<'_> {
    fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
        let n = std::io::BufRead::fill_buf(self)?.len().min(out.len());
        out[..n].copy_from_slice(&self.bytes[..n]);
        std::io::BufRead::consume(self, n);
        Ok(n)
    }
}

impl std::io::BufRead for Stutter<'_> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        self.ready = !self.ready;
        if !self.ready {
            return Err(ErrorKind::WouldBlock.into());
        }
        Ok(&self.bytes[..self.chunk.min(self.bytes.len())])
    }
    fn consume(&mut self, n: usize) {
        self.bytes = &self.bytes[n..];
    }
}

#[test]
fn a_read_paused_anywhere_resumes_where_it_was_and_gives_the_same_bytes() {
    let mut file = GzBuilder::new()
        .filename("a name of some length.log")
        .comment("a comment")
        .extra(vec![7u8; 40])
        .write(Vec::new(), Compression::default());
    file.write_all(b"ODOM 1 2 3\n".repeat(300).as_slice())
        .unwrap();
    let mut file = file.finish().unwrap();
    let header = header_len(&file);
    file[3] |= 2; // FHCRC
    let crc16 = (crc32(&file[..header]) as u16).to_le_bytes();
    file.splice(header..header, crc16);
    file.extend(gzip(b"", 6));
    file.extend(gzip(b"last\n", 9));
    file.extend([0u8; 9]);
    let expected = [b"ODOM 1 2 3\n".repeat(300), b"last\n".to_vec()].concat();
    for chunk in [1, 2, 3, 7, 64] {
        let mut reader = GzipReader::new(Stutter {
            bytes: &file,
            chunk,
            ready: false,
        });
        let (mut out, mut pauses) = (Vec::new(), 0);
        let mut buf = [0u8; 100];
        loop {
            match reader.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => out.extend_from_slice(&buf[..n]),
                Err(e) if e.kind() == ErrorKind::WouldBlock => pauses += 1,
                Err(e) => panic!("chunks of {chunk}: {e}"),
            }
        }
        assert_eq!(out, expected, "chunks of {chunk}");
        assert!(pauses * chunk >= file.len(), "{pauses} pauses");
    }
}

/// One laser line: what each hostile file below holds once inflated.
const SCAN: &[u8] = b"FLASER 3 1 2 3 0 0 0 0 0 0\n";

/// `n` empty gzip members (a header, a deflate block holding nothing, a
/// trailer: 20 bytes each), then one member holding [`SCAN`].
fn empty_members_then_a_scan(n: usize) -> Vec<u8> {
    let empty = [
        0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    ];
    let mut file = empty.repeat(n);
    file.extend(gzip(SCAN, 6));
    file
}

/// One member whose deflate stream is `n` empty fixed-Huffman blocks (10
/// bits each: the block header, then end-of-block) and a stored block
/// holding [`SCAN`].
fn empty_blocks_then_a_scan(n: usize) -> Vec<u8> {
    let mut bits: Vec<u8> = [0, 1, 0, 0, 0, 0, 0, 0, 0, 0].repeat(n);
    bits.extend([1, 0, 0]); // BFINAL, stored
    bits.resize(bits.len().div_ceil(8) * 8, 0);
    let mut file = vec![0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3];
    file.extend(
        bits.chunks(8)
            .map(|b| (0..8).map(|i| b[i] << i).sum::<u8>()),
    );
    let len = SCAN.len() as u16;
    file.extend(len.to_le_bytes().into_iter().chain((!len).to_le_bytes()));
    file.extend(SCAN);
    file.extend(
        crc32(SCAN)
            .to_le_bytes()
            .into_iter()
            .chain((SCAN.len() as u32).to_le_bytes()),
    );
    file
}

/// Reads `file` through the CARMEN loader, one scan a call at most and
/// `budget` bytes of the file a call: no call may take more, and every
/// byte is taken by the end. The calls made and the scans read.
fn read_in_bounded_calls(file: &[u8], budget: u64) -> (usize, usize) {
    let mut loader = LogLoader::with_budget(
        file,
        LogBudget {
            compressed_bytes_per_read: budget,
            ..LogBudget::default()
        },
    );
    let (mut calls, mut taken) = (0, 0);
    loop {
        let p = loader.read(1).unwrap();
        calls += 1;
        let took = p.bytes_read - taken;
        assert!(took <= budget, "call {calls} took {took} bytes");
        taken = p.bytes_read;
        if p.finished {
            assert_eq!(taken, file.len() as u64);
            return (calls, p.scans);
        }
    }
}

#[test]
fn gzip_files_that_inflate_to_almost_nothing_are_read_in_calls_bounded_by_their_bytes() {
    let budget = 4 << 10;
    // 5,000 empty members; a 256 kB name and comment; 40,000 empty deflate
    // blocks; 50 kB of zero padding. Each used to be read in one call,
    // however long.
    let mut named = GzBuilder::new()
        .filename(vec![b'n'; 256 << 10])
        .comment(vec![b'c'; 256 << 10])
        .write(Vec::new(), Compression::default());
    named.write_all(SCAN).unwrap();
    let hostile = [
        empty_members_then_a_scan(5_000),
        named.finish().unwrap(),
        empty_blocks_then_a_scan(40_000),
    ];
    let mut padded = gzip(SCAN, 6);
    padded.extend(vec![0u8; 50_000]);
    for file in hostile.iter().chain([&padded]) {
        let (calls, scans) = read_in_bounded_calls(file, budget);
        assert_eq!(scans, 1);
        assert!(calls >= file.len() / budget as usize, "{calls} calls");
    }
    // Well-formed gzip all the same (the reference caps header fields at
    // 64 kB, where RFC 1952 sets no bound).
    for file in [&hostile[0], &hostile[2]] {
        assert_eq!(reference(file).unwrap(), SCAN);
    }
    // The page's session, at the default budget: its first call returns
    // early, unfinished, and the calls after it finish the read.
    let bomb = empty_members_then_a_scan(20_000);
    let mut session = occgrid::apps::real_log::RealLogSession::new(bomb.clone());
    let first = session.read(1).unwrap().progress;
    assert!(!first.finished && first.bytes_read <= LogBudget::default().compressed_bytes_per_read);
    while !session.read(1).unwrap().progress.finished {}
    assert_eq!(session.pane(0).unwrap().scans().len(), 1);
}

/// The hostile files at full size (2,000,000 empty members, a 40 MB name,
/// 4,000,000 empty deflate blocks), read as the page reads them, one scan
/// a call at the default budget: prints the longest call. A measurement,
/// run with `cargo test --release --test gzip -- --ignored --nocapture`.
#[test]
#[ignore = "a measurement: 45 MB of input, seconds to read"]
fn full_size_hostile_files_longest_read_call() {
    let mut named = GzBuilder::new()
        .filename(vec![b'n'; 40_000_000])
        .write(Vec::new(), Compression::default());
    named.write_all(SCAN).unwrap();
    let files = [
        (
            "2,000,000 empty members",
            empty_members_then_a_scan(2_000_000),
        ),
        ("a 40 MB name", named.finish().unwrap()),
        (
            "4,000,000 empty blocks",
            empty_blocks_then_a_scan(4_000_000),
        ),
    ];
    for (what, file) in files {
        let mut loader = LogLoader::new(&file[..]);
        let (mut calls, mut longest) = (0, 0.0f64);
        let all = std::time::Instant::now();
        loop {
            let t = std::time::Instant::now();
            let p = loader.read(1).unwrap();
            longest = longest.max(t.elapsed().as_secs_f64() * 1e3);
            calls += 1;
            if p.finished {
                assert_eq!(p.scans, 1);
                break;
            }
        }
        let total = all.elapsed().as_secs_f64() * 1e3;
        println!(
            "{what}: {} bytes, {calls} calls, longest {longest:.1} ms, all {total:.0} ms",
            file.len()
        );
    }
}

#![cfg(not(target_arch = "wasm32"))]
//! Hostile and damaged bags: each refused with an error naming the record
//! and its byte, never a panic or a hang; a bag cut short read to the cut.

mod bag_support;

use bag_support::{laser_scan, laser_scan_def, robot_bag, BagSpec, Compression, Writer, MAGIC};
use occgrid::io::{open_log, read_log, LogBudget};

fn refusal(bytes: Vec<u8>) -> String {
    let e = read_log(bytes).expect_err("refused").to_string();
    assert!(e.contains("byte"), "names no byte: {e}");
    e
}

#[test]
fn bad_magic_is_refused_with_the_bytes_found() {
    let (mut bag, _) = robot_bag(&BagSpec::default());
    bag[5] = b'9';
    let e = refusal(bag);
    assert!(
        e.contains("magic bytes") && e.contains("first 8 bytes"),
        "{e}"
    );
}

#[test]
fn a_length_past_the_end_of_a_whole_file_is_refused_by_record_and_byte() {
    let (mut bag, _) = robot_bag(&BagSpec::default());
    // The Header record at byte 8: its length made huge.
    bag[9..17].copy_from_slice(&(1u64 << 60).to_le_bytes());
    let e = refusal(bag);
    assert!(
        e.contains("Header record at byte 8") && e.contains("runs past"),
        "{e}"
    );
    // A string inside a record that claims more than the record holds.
    let mut w = Writer::new(Compression::Unchunked);
    w.schema(1, "sensor_msgs/msg/LaserScan", &laser_scan_def());
    let mut bag = w.finish(false);
    let schema_at = bag.windows(1).position(|b| b[0] == 0x03).unwrap();
    let name_len = schema_at + 9 + 2;
    bag[name_len..name_len + 4].copy_from_slice(&u32::MAX.to_le_bytes());
    let e = refusal(bag);
    assert!(
        e.contains(&format!("Schema record at byte {schema_at}")) && e.contains("name"),
        "{e}"
    );
}

#[test]
fn a_crc_mismatch_is_refused_for_a_chunk_and_the_summary() {
    let mut w = Writer::new(Compression::Zstd);
    w.lie_chunk_crc = Some(0x1234_5678);
    w.schema(1, "sensor_msgs/msg/LaserScan", &laser_scan_def());
    let e = refusal(w.finish(false));
    assert!(
        e.contains("Chunk record at byte")
            && e.contains("fails its CRC")
            && e.contains("0x12345678"),
        "{e}"
    );
    let (mut bag, _) = robot_bag(&BagSpec::default());
    let n = bag.len();
    // The last byte of the summary section's Statistics record.
    bag[n - 8 - 29 - 1] ^= 0xff;
    let e = refusal(bag);
    assert!(
        e.contains("Footer record at byte") && e.contains("fails its CRC"),
        "{e}"
    );
}

#[test]
fn a_chunk_bomb_is_refused_before_inflating_or_at_its_stated_size() {
    for compression in [Compression::Zstd, Compression::Lz4, Compression::None] {
        // States 1 TiB: refused before anything is inflated.
        let mut w = Writer::new(compression);
        w.lie_chunk_size = Some(1 << 40);
        w.schema(1, "sensor_msgs/msg/LaserScan", &laser_scan_def());
        let e = refusal(w.finish(false));
        assert!(
            e.contains("uncompressed_size 1099511627776 is over"),
            "{compression:?}: {e}"
        );
        // States 10 bytes and inflates to more: cut at 11.
        let mut w = Writer::new(compression);
        w.lie_chunk_size = Some(10);
        w.schema(1, "sensor_msgs/msg/LaserScan", &"#\n".repeat(1 << 20));
        let e = refusal(w.finish(false));
        assert!(
            e.contains("inflate past the uncompressed_size of 10 bytes"),
            "{compression:?}: {e}"
        );
    }
}

#[test]
fn a_schema_that_lies_about_its_fields_is_refused_at_its_first_message() {
    let mut w = Writer::new(Compression::Unchunked);
    // range_min and range_max swapped with ranges: another layout.
    let lying = laser_scan_def().replace("float32 range_min\nfloat32 range_max\n", "");
    w.schema(1, "sensor_msgs/msg/LaserScan", &lying);
    w.channel(1, 1, "/scan");
    w.message(
        1,
        1.0,
        &laser_scan(false, 1.0, "laser", 0.0, 0.1, 8.0, &[1.0; 10]),
    );
    let e = refusal(w.finish(false));
    assert!(
        e.contains("Message record at byte")
            && e.contains("its schema defines sensor_msgs/LaserScan as"),
        "{e}"
    );
}

#[test]
fn a_million_element_ranges_array_is_refused_by_count() {
    let mut w = Writer::new(Compression::Zstd);
    w.schema(1, "sensor_msgs/msg/LaserScan", &laser_scan_def());
    w.channel(1, 1, "/scan");
    w.message(
        1,
        1.0,
        &laser_scan(false, 1.0, "laser", 0.0, 1e-5, 8.0, &vec![1.0; 1_000_000]),
    );
    let e = refusal(w.finish(false));
    assert!(
        e.contains("ranges: 1000000 elements, more than the 10000"),
        "{e}"
    );
    // A count past the message's end, without the readings.
    let mut w = Writer::new(Compression::Unchunked);
    w.schema(1, "sensor_msgs/msg/LaserScan", &laser_scan_def());
    w.channel(1, 1, "/scan");
    let mut data = laser_scan(false, 1.0, "laser", 0.0, 0.1, 8.0, &[1.0; 3]);
    let count_at = data.len() - 4 - 12 - 4;
    data[count_at..count_at + 4].copy_from_slice(&9_000u32.to_le_bytes());
    w.message(1, 1.0, &data);
    let e = refusal(w.finish(false));
    assert!(e.contains("past the message's end"), "{e}");
}

#[test]
fn stamps_running_backwards_are_refused_by_message() {
    let (bag, _) = robot_bag(&BagSpec {
        stamp: |k| 1_700_000_000.0 + if k == 5 { 1.0 } else { k as f64 * 0.5 },
        ..BagSpec::default()
    });
    let e = refusal(bag);
    assert!(
        e.contains("runs backwards") && e.contains("topic \"/scan\""),
        "{e}"
    );
}

#[test]
fn a_bag_cut_short_keeps_the_scans_before_the_cut_with_a_warning() {
    for compression in [
        Compression::Unchunked,
        Compression::None,
        Compression::Zstd,
        Compression::Lz4,
    ] {
        let spec = BagSpec {
            compression,
            scans: 40,
            ..BagSpec::default()
        };
        let (bag, truth) = robot_bag(&spec);
        let cut = bag.len() * 2 / 3;
        let mut source = open_log(bag[..cut].to_vec(), LogBudget::default()).unwrap();
        let progress = loop {
            let p = source.read(usize::MAX).unwrap();
            if p.finished {
                break p;
            }
        };
        let w = progress.warning.unwrap();
        assert!(
            w.contains(&format!("it ends at byte {cut}")),
            "{compression:?}: {w}"
        );
        let scans = source.scans();
        assert!(
            scans.len() > 5 && scans.len() < 40,
            "{compression:?}: {}",
            scans.len()
        );
        for (p, t) in scans.poses().iter().zip(&truth) {
            assert!((p.x - t[0]).abs() < 1e-6, "{compression:?}");
        }
    }
}

#[test]
fn every_prefix_of_a_small_bag_is_read_or_refused_without_a_panic() {
    let (bag, _) = robot_bag(&BagSpec {
        scans: 3,
        beams: 8,
        ..BagSpec::default()
    });
    for n in (0..bag.len()).step_by(7) {
        let mut bytes = bag[..n].to_vec();
        if n < MAGIC.len() {
            bytes = MAGIC[..5].iter().chain(&bytes).copied().collect();
        }
        let _ = read_log(bytes);
    }
}

#[test]
fn a_data_section_crc_mismatch_is_refused_at_the_data_end_record() {
    let (mut bag, _) = robot_bag(&BagSpec::default());
    // A byte of the Header's library name: read by nothing but the CRC.
    let at = bag.windows(6).position(|w| w == b"occgri").unwrap();
    bag[at] = b'O';
    let e = refusal(bag);
    assert!(
        e.contains("Data End record at byte") && e.contains("fails its CRC"),
        "{e}"
    );
}

#[test]
fn a_footer_whose_summary_points_into_the_data_is_refused() {
    let (mut bag, _) = robot_bag(&BagSpec {
        summary: false,
        ..BagSpec::default()
    });
    let n = bag.len();
    // summary_start: the Header record at byte 8; no summary CRC.
    let footer = n - 8 - 29;
    bag[footer + 9..footer + 17].copy_from_slice(&8u64.to_le_bytes());
    let e = refusal(bag);
    assert!(
        e.contains("Header record at byte 8") && e.contains("summary_start points at it"),
        "{e}"
    );
}

/// A bag of three scans in `base_link`, the odometry's child frame, in lz4
/// chunks with `skip` (skippable frames) before and after each chunk's
/// frame.
fn lz4_bag(skip: Option<Vec<u8>>) -> Vec<u8> {
    use bag_support::{odometry, odometry_def};
    let mut w = Writer::new(Compression::Lz4);
    w.lz4_skippable = skip;
    w.schema(1, "sensor_msgs/msg/LaserScan", &laser_scan_def());
    w.schema(2, "nav_msgs/msg/Odometry", &odometry_def());
    w.channel(1, 1, "/scan");
    w.channel(2, 2, "/odom");
    for k in 0..3 {
        let t = 10.0 + k as f64;
        let at = |t: f64| [t, 0.5 * t, 0.1];
        w.message(
            2,
            t - 0.5,
            &odometry(false, t - 0.5, "base_link", at(t - 0.5)),
        );
        let ranges = [1.0 + k as f32, 2.0, 3.0];
        w.message(
            1,
            t,
            &laser_scan(false, t, "base_link", 0.0, 0.1, 8.0, &ranges),
        );
        w.message(
            2,
            t + 0.5,
            &odometry(false, t + 0.5, "base_link", at(t + 0.5)),
        );
    }
    w.finish(true)
}

#[test]
fn lz4_skippable_frames_are_passed_over_and_one_cut_short_is_refused() {
    let plain = read_log(lz4_bag(None)).unwrap();
    assert_eq!(plain.len(), 3);
    for magic in [0x184d_2a50u32, 0x184d_2a5f] {
        let mut skip = magic.to_le_bytes().to_vec();
        skip.extend_from_slice(&5u32.to_le_bytes());
        skip.extend_from_slice(b"notes");
        let skipped = read_log(lz4_bag(Some(skip))).unwrap();
        assert_eq!(skipped, plain, "magic {magic:#x}");
    }
    let mut cut = 0x184d_2a53u32.to_le_bytes().to_vec();
    cut.extend_from_slice(&0xffff_fff0u32.to_le_bytes());
    let e = refusal(lz4_bag(Some(cut)));
    assert!(e.contains("a skippable frame past the end"), "{e}");
}

#![cfg(not(target_arch = "wasm32"))]
//! What reading a CARMEN log may cost (`io::carmen`'s "Memory and
//! budgets"): each `LogLoader::read` call bounded by scans, lines and bytes,
//! one line held at a time while streaming, the kept scans within their
//! budget before anything is allocated. (Gzip files that inflate to almost
//! nothing are in `tests/gzip.rs`.)

use occgrid::apps::real_log::RealLogSession;
use occgrid::io::carmen::{LogLoader, LogReader, MAX_LINE_BYTES};
use occgrid::io::LogBudget;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::io::Read;

/// The ACES building's log: 440 scans in 8,700 lines.
fn aces() -> Vec<u8> {
    let dir = std::env::var_os("OCCGRID_DATASETS")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/datasets").into());
    let path = dir.join("aces-corrected.log.gz");
    std::fs::read(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}
const ACES_LINES: usize = 8700;

#[test]
fn the_loader_reports_progress_in_chunks_and_ends_with_every_scan() {
    let bytes = aces();
    // Bounded by scans alone (the compressed bytes a call may take are
    // not), then at the default budget, where they are too.
    let unbounded = LogBudget {
        compressed_bytes_per_read: u64::MAX,
        ..LogBudget::default()
    };
    for budget in [unbounded, LogBudget::default()] {
        let by_scans = budget == unbounded;
        let mut loader = LogLoader::with_budget(&bytes[..], budget);
        let (mut last, mut scans, mut calls) = (0, 0, 0);
        loop {
            let p = loader.read(100).unwrap();
            calls += 1;
            assert!(p.bytes_read >= last && p.bytes_read <= bytes.len() as u64);
            assert!(p.bytes_read - last <= budget.compressed_bytes_per_read);
            assert!(p.scans - scans <= 100);
            (last, scans) = (p.bytes_read, p.scans);
            if p.finished {
                assert_eq!((p.scans, p.records, p.beams), (440, ACES_LINES, 440 * 180));
                break;
            }
            if by_scans {
                assert_eq!(p.scans, calls * 100);
            }
        }
        if by_scans {
            assert_eq!(calls, 5);
        } else {
            assert!(calls as u64 >= bytes.len() as u64 / budget.compressed_bytes_per_read);
        }
        assert_eq!(loader.into_scans().len(), 440);
    }
}

// Peak heap use of the current thread, for the streaming test below (other
// tests run on other threads and do not count).
struct Counting;
thread_local! {
    static LIVE: Cell<isize> = const { Cell::new(0) };
    static PEAK: Cell<isize> = const { Cell::new(0) };
}
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = LIVE.try_with(|l| {
            l.set(l.get() + layout.size() as isize);
            let _ = PEAK.try_with(|p| p.set(p.get().max(l.get())));
        });
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        let _ = LIVE.try_with(|l| l.set(l.get() - layout.size() as isize));
        System.dealloc(ptr, layout)
    }
}
#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// A log generated on the fly: `total` bytes of ODOM lines with a FLASER
/// line every hundredth line, never held in memory.
struct Generated {
    total: usize,
    produced: usize,
    pending: Vec<u8>,
    lines: usize,
}

impl Read for Generated {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.pending.is_empty() {
            if self.produced >= self.total {
                return Ok(0);
            }
            self.lines += 1;
            let line = if self.lines.is_multiple_of(100) {
                format!(
                    "FLASER 180 {} 1 2 0.5 1 2 0.5 {} h {}\n",
                    "3.25 ".repeat(180).trim_end(),
                    self.lines,
                    self.lines
                )
            } else {
                format!(
                    "ODOM 1.0 2.0 0.5 0 0 0 {} host {}\n",
                    self.lines, self.lines
                )
            };
            self.pending = line.into_bytes();
        }
        let n = buf.len().min(self.pending.len());
        buf[..n].copy_from_slice(&self.pending[..n]);
        self.pending.drain(..n);
        self.produced += n;
        Ok(n)
    }
}

#[test]
fn streaming_a_100_mb_log_holds_about_one_line_in_memory() {
    let total = 100 << 20;
    let source = Generated {
        total,
        produced: 0,
        pending: Vec::new(),
        lines: 0,
    };
    LIVE.with(|l| l.set(0));
    PEAK.with(|p| p.set(0));
    let mut reader = LogReader::new(source);
    let mut scans = 0;
    for record in &mut reader {
        let r = record.unwrap();
        assert_eq!(r.ranges.len(), 180);
        scans += 1;
    }
    let peak = PEAK.with(|p| p.get());
    assert!(reader.bytes_read() >= total as u64);
    assert!(scans > 15_000, "{scans} scans");
    // The reader's buffer (64 kB), one line and one record: a quarter of a
    // megabyte at most, against the log's 100 MB.
    assert!(peak < 256 << 10, "peak heap {peak} bytes");
    const { assert!(MAX_LINE_BYTES <= 1 << 20) };
}

/// A gzip file of `lines` FLASER lines of `beams` beams each, built here.
fn flaser_bomb(lines: usize, beams: usize) -> Vec<u8> {
    use std::io::Write;
    let ranges = "12.34 ".repeat(beams);
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    for k in 0..lines {
        writeln!(gz, "FLASER {beams} {ranges}1 2 0.5 1 2 0.5 {k} host {k}").unwrap();
    }
    gz.finish().unwrap()
}

#[test]
fn a_gzip_bomb_of_valid_lines_is_refused_at_the_budget_before_allocating_and_the_session_survives()
{
    // 200 lines of 10,000 beams: 12 MB of text, 8 MB of f32 ranges to keep,
    // against a budget lowered to 1 MiB for the test.
    let bomb = flaser_bomb(200, 10_000);
    let budget = LogBudget {
        kept_bytes: 1 << 20,
        ..LogBudget::default()
    };
    LIVE.with(|l| l.set(0));
    PEAK.with(|p| p.set(0));
    let mut session = RealLogSession::with_budget(bomb.clone(), budget);
    let e = loop {
        match session.read(usize::MAX) {
            Ok(r) => assert!(!r.progress.finished, "the bomb was kept whole"),
            Err(e) => break e.to_string(),
        }
    };
    let peak = PEAK.with(|p| p.get()) as usize;
    // Scans kept to the budget, the reader's line (at most 1 MiB) and
    // buffers: never the 8 MB the whole log would take.
    assert!(
        peak < bomb.len() + (1 << 20) + (1 << 20) + (512 << 10),
        "peak heap {peak} bytes"
    );
    assert!(e.contains("over the budget of 1.0 MiB"), "{e}");
    assert!(e.contains("need 1.0 MiB (27 scans, 270000 beams)"), "{e}");
    assert!(e.starts_with("line 27:"), "{e}");
    // Usable after the refusal: the same error again, settings still taken,
    // other calls refused in words; no panic.
    assert_eq!(session.read(10).unwrap_err().to_string(), e);
    assert!(session.configure(Default::default()).unwrap().is_none());
    assert!(session.build_chunk(1).is_err());
    assert!(!session.awaiting_settings());
    // Under the default budget the same bomb is kept (8 MB is well within).
    let mut ok = RealLogSession::new(bomb);
    while !ok.read(usize::MAX).unwrap().progress.finished {}
    assert_eq!(ok.pane(0).unwrap().scans().beams(), 2_000_000);
}

#[test]
fn blank_lines_are_read_in_bounded_steps_and_a_log_without_laser_lines_says_so() {
    use std::io::Write;
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    gz.write_all(&vec![b'\n'; 300_000]).unwrap();
    gz.write_all(b"ODOM 1 2 3\n# a comment\n").unwrap();
    let blank = gz.finish().unwrap();
    let budget = LogBudget {
        records_per_read: 1000,
        ..LogBudget::default()
    };
    let mut session = RealLogSession::with_budget(blank, budget);
    let (mut calls, mut lines) = (0, 0);
    let e = loop {
        match session.read(usize::MAX) {
            Ok(r) => {
                assert!(
                    r.progress.records - lines <= 1000,
                    "one call read {} lines",
                    r.progress.records - lines
                );
                lines = r.progress.records;
                calls += 1;
            }
            Err(e) => break e.to_string(),
        }
    };
    assert!(calls >= 299, "{calls} calls");
    assert!(
        e.contains("no FLASER or ROBOTLASER1 lines") && e.contains("300002 lines"),
        "{e}"
    );
    assert!(!e.contains("resolution"), "{e}");
    assert!(
        !session.awaiting_settings(),
        "no settings can map an empty log"
    );
    assert_eq!(session.read(1).unwrap_err().to_string(), e);

    // Bytes bound a call too: 64 kB of text per call over long comments.
    let mut text = Vec::new();
    for _ in 0..200 {
        text.extend_from_slice(b"# ");
        text.extend(std::iter::repeat_n(b'x', 10_000));
        text.push(b'\n');
    }
    let mut loader = LogLoader::with_budget(
        &text[..],
        LogBudget {
            bytes_per_read: 64 << 10,
            ..LogBudget::default()
        },
    );
    let mut steps = 0;
    while !loader.read(usize::MAX).unwrap().finished {
        steps += 1;
    }
    // 64 kB and the line that crosses it per call: at least 25 calls.
    assert!(steps >= 25, "{steps} steps for 2 MB");
}

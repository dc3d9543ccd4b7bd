//! Reading CARMEN laser logs.
//!
//! A CARMEN log is text, one message per line, the message type first.
//! The mapper needs the laser lines with their corrected poses:
//!
//! `FLASER n r_1 … r_n x y theta odom_x odom_y odom_theta ipc_ts host logger_ts`
//!
//! FLASER scans cover 180 degrees starting at `-pi/2` (CARMEN's convention:
//! 181, 361 or 721 beams include both ends, any other count does not).
//! Other message types are skipped. Files may be gzip-compressed (detected
//! from the gzip magic bytes) and are read as a stream, line by line.

use crate::error::{OccError, Result};
use crate::scan::{Pose, Scan};
use std::io::{BufRead, BufReader, Read};

/// A parsed log: its laser scans in file order.
#[derive(Debug, Clone, PartialEq)]
pub struct CarmenLog {
    pub scans: Vec<Scan>,
    /// Lines read, laser or not.
    pub lines: usize,
}

/// Angle between consecutive FLASER beams for a scan of `n` beams.
pub fn flaser_angle_increment(n: usize) -> f64 {
    use std::f64::consts::PI;
    match n {
        181 | 361 | 721 => PI / (n - 1) as f64,
        _ => PI / n as f64,
    }
}

/// Reads a log from bytes, gzip-compressed or plain.
pub fn parse_bytes(bytes: &[u8]) -> Result<CarmenLog> {
    if bytes.starts_with(&[0x1f, 0x8b]) {
        read_log(BufReader::new(flate2::read::MultiGzDecoder::new(bytes)))
    } else {
        read_log(bytes)
    }
}

/// Reads a log from a stream: only the current line is held in memory
/// besides the scans.
pub fn read_log<R: Read>(reader: R) -> Result<CarmenLog> {
    let mut reader = BufReader::new(reader);
    let mut line = Vec::new();
    let mut scans = Vec::new();
    let mut number = 0;
    loop {
        line.clear();
        let n = reader
            .read_until(b'\n', &mut line)
            .map_err(|e| OccError::Parse {
                line: number + 1,
                reason: format!("cannot read the file: {e}"),
            })?;
        if n == 0 {
            break;
        }
        number += 1;
        let text = std::str::from_utf8(&line).map_err(|_| OccError::Parse {
            line: number,
            reason: "not text (invalid UTF-8)".into(),
        })?;
        let mut fields = text.split_ascii_whitespace();
        if fields.next() == Some("FLASER") {
            scans.push(parse_flaser(fields).map_err(|reason| OccError::Parse {
                line: number,
                reason,
            })?);
        }
    }
    Ok(CarmenLog {
        scans,
        lines: number,
    })
}

fn parse_flaser<'a>(
    mut fields: impl Iterator<Item = &'a str>,
) -> std::result::Result<Scan, String> {
    let mut next_number = |what: &str| -> std::result::Result<f64, String> {
        let token = fields
            .next()
            .ok_or_else(|| format!("FLASER line ends before {what}"))?;
        let v: f64 = token
            .parse()
            .map_err(|_| format!("FLASER {what} is not a number: {token:?}"))?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(format!("FLASER {what} is not finite: {token}"))
        }
    };
    let n = next_number("beam count")?;
    if !(n >= 1.0 && n <= 10_000.0 && n.fract() == 0.0) {
        return Err(format!(
            "FLASER beam count must be a whole number from 1 to 10000, found {n}"
        ));
    }
    let n = n as usize;
    let mut ranges = Vec::with_capacity(n);
    for i in 0..n {
        let r = next_number(&format!("range {}", i + 1))?;
        if r < 0.0 {
            return Err(format!("FLASER range {} is negative: {r}", i + 1));
        }
        ranges.push(r);
    }
    let x = next_number("x")?;
    let y = next_number("y")?;
    let theta = next_number("theta")?;
    let pose = Pose::new(x, y, theta).map_err(|e| e.to_string())?;
    Scan::uniform(
        pose,
        ranges,
        -std::f64::consts::FRAC_PI_2,
        flaser_angle_increment(n),
    )
    .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_flaser_and_skips_other_messages() {
        let text = "# comment\nODOM 1 2 3\nFLASER 3 1.0 2.0 3.0 0.5 -1.5 0.1 0 0 0 1.0 host 1.0\n";
        let log = parse_bytes(text.as_bytes()).unwrap();
        assert_eq!(log.scans.len(), 1);
        assert_eq!(log.lines, 3);
        let s = &log.scans[0];
        assert_eq!(s.ranges(), &[1.0, 2.0, 3.0]);
        assert_eq!(
            s.pose(),
            Pose {
                x: 0.5,
                y: -1.5,
                theta: 0.1
            }
        );
        assert!(
            (s.bearings()[1] - (-std::f64::consts::FRAC_PI_2 + std::f64::consts::PI / 3.0)).abs()
                < 1e-12
        );
    }

    #[test]
    fn malformed_lines_are_reported_with_their_number() {
        let e = parse_bytes(b"ODOM\nFLASER 3 1.0 2.0\n").unwrap_err();
        assert_eq!(
            e,
            OccError::Parse {
                line: 2,
                reason: "FLASER line ends before range 3".into()
            }
        );
        let e = parse_bytes(b"FLASER 2 1.0 nan 0 0 0\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("line 1:") && e.contains("range 2"), "{e}");
        let e = parse_bytes(b"FLASER 2 1.0 -3 0 0 0\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("negative"), "{e}");
        let e = parse_bytes(&[0x46, 0xff, 0xfe, b'\n'])
            .unwrap_err()
            .to_string();
        assert!(e.contains("UTF-8"), "{e}");
        let e = parse_bytes(&[0x1f, 0x8b, 1, 2, 3]).unwrap_err().to_string();
        assert!(e.contains("line 1"), "{e}");
    }
}

//! A log file opened by the reader of its format: the one place that
//! knows every format's reader ([`open_log`]).

use super::carmen;
use super::log_source::{LogBudget, LogFormat, LogSource};
use super::ros2;
use crate::error::Result;
use crate::sensors::ScanLog;
use std::io::Cursor;

/// A reader of `bytes` in whichever format their first bytes name, within
/// `budget`: an error for a format the core knows but does not read.
pub fn open_log(bytes: Vec<u8>, budget: LogBudget) -> Result<Box<dyn LogSource>> {
    let head = &bytes[..bytes.len().min(8)];
    match LogFormat::sniff(head)? {
        LogFormat::Carmen => Ok(Box::new(carmen::LogLoader::with_budget(
            Cursor::new(bytes),
            budget,
        ))),
        LogFormat::Mcap => Ok(Box::new(ros2::BagLoader::new(bytes, budget))),
    }
}

/// Every scan of `bytes`, in whichever format, read to the end within the
/// default budget.
pub fn read_log(bytes: Vec<u8>) -> Result<ScanLog> {
    let mut source = open_log(bytes, LogBudget::default())?;
    loop {
        if source.read(usize::MAX)?.finished {
            return Ok(source.into_scans());
        }
    }
}

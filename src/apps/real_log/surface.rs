//! What a page asks of the session beyond one pane's own calls (which it
//! makes on [`RealLogSession::pane`] and [`RealLogSession::pane_mut`]): a
//! session made for a named file, and the robot at a scan refused by name
//! when the log has no such scan (docs/ARCHITECTURE.md, "Sessions and
//! panes").

use super::RealLogSession;
use crate::error::{invalid, Result};
use crate::render::overlay::RobotMark;

impl RealLogSession {
    /// A session about to read `bytes` (gzip or plain text), `name` its
    /// file's name.
    pub fn with_log(bytes: Vec<u8>, name: &str) -> Self {
        let mut session = Self::idle();
        session.open(bytes, name);
        session
    }

    /// The robot at scan `k` over pane `pane`, or an error naming the scan.
    pub fn robot_at(&self, pane: usize, k: usize) -> Result<RobotMark> {
        let robot = self.pane(pane)?.robot_at(k);
        robot.ok_or_else(|| invalid("scan", k, "a scan of the log"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FLASER: &str = "FLASER 4 1.0 2.0 3.0 2.5 0.5 -1.5 0.1 0 0 0 1.0 host 1.0\n";

    #[test]
    fn a_named_session_reads_and_refuses_a_scan_it_lacks_by_name() {
        let mut s = RealLogSession::with_log(FLASER.repeat(3).into_bytes(), "lab.log");
        s.read(usize::MAX).unwrap();
        s.build_slice(u64::MAX).unwrap();
        assert!(s.robot_at(0, 2).is_ok());
        let e = s.robot_at(0, 3).unwrap_err().to_string();
        assert!(e.contains("invalid scan: 3"), "{e}");
        let e = s.robot_at(7, 0).unwrap_err().to_string();
        assert!(e.contains("pane"), "{e}");
        let pair = s.pane(0).unwrap().export_map(Some("lab"));
        assert!(pair.yaml.starts_with("image: lab.pgm"), "{}", pair.yaml);
    }
}

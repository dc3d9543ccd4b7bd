//! Logs made up in the native real-log tests, shared by their files.

/// A log as text: one FLASER line per `(x, y, theta, ranges)`.
pub fn flaser_log(scans: &[(f64, f64, f64, Vec<f64>)]) -> Vec<u8> {
    let mut text = String::new();
    for (k, (x, y, th, rs)) in scans.iter().enumerate() {
        let r: Vec<String> = rs.iter().map(|r| format!("{r:.3}")).collect();
        text.push_str(&format!(
            "FLASER {} {} {x} {y} {th} {x} {y} {th} {k} host {k}\n",
            rs.len(),
            r.join(" ")
        ));
    }
    text.into_bytes()
}

//! How an exported map was made, in comment lines of its YAML that
//! `map_server` ignores: the log's file name, the pose source (for
//! simulated odometry, that it was simulated and with which seed), the
//! cell model and where the image draws its cells, what the free cells
//! rest on, and every setting that differs from the defaults (docs/ARCHITECTURE.md, "Real logs"). The file
//! alone then says what a reader is looking at.

use super::settings::{LogCellModel, LogMapSettings, HIT_RATIO};
use crate::grid::HitMissOdds;
use crate::io::map_server::{FREE_THRESH, OCCUPIED_THRESH};
use crate::mapping::neighbour_support::MAX_NO_RETURN_GAP;
use crate::mapping::walls::WallModel;
use crate::poses::PoseSourceKind;

/// What one export says of its making.
#[derive(Debug, Clone, Copy)]
pub struct Provenance<'a> {
    /// The log's file name as the reader opened it (`None`: not given).
    pub log_file: Option<&'a str>,
    pub source: PoseSourceKind,
    pub model: LogCellModel,
    pub settings: &'a LogMapSettings,
}

impl Provenance<'_> {
    /// The comment lines, each ending in a newline.
    pub fn yaml_comments(&self) -> String {
        let log = self.log_file.map_or("(not named)".into(), quoted);
        let cut = self.model.trinary_cut();
        let drawn = match cut {
            None => format!(
                "occupied above p {OCCUPIED_THRESH}, free below p {FREE_THRESH} (map_server's thresholds)"
            ),
            Some((occupied, free)) => format!(
                "occupied above p {occupied}, free below p {free} (the cell model's own cut: its odds need dozens of misses to fall below map_server's free_thresh {FREE_THRESH})"
            ),
        };
        format!(
            "# log: {log}\n# pose source: {}\n# cell model: {}\n# cells drawn: {drawn}\n# free cells rest on: {}\n# settings other than the defaults: {}\n",
            self.source.provenance(self.settings.seed),
            cell_model(self.model, self.settings.clamp),
            free_evidence(self.settings.walls),
            changed_settings(self.settings),
        )
    }
}

/// The cell model and its parameters.
fn cell_model(model: LogCellModel, clamp: f64) -> String {
    let name = model.name();
    match model {
        LogCellModel::LogOdds => {
            format!("{name} (Table 9.1's filter with Table 9.2's evidence, clamp {clamp})")
        }
        LogCellModel::HitCounting => {
            format!(
                "{name} (GMapping's hits and visits, occupied above a hit ratio of {HIT_RATIO})"
            )
        }
        LogCellModel::HitMissOdds => {
            let m = HitMissOdds::cartographer();
            format!(
                "{name} (Cartographer's odds: hit {}, miss {}, within [{}, {}])",
                m.p_hit, m.p_miss, m.p_min, m.p_max
            )
        }
    }
}

/// What a free cell of the map rests on under `walls`: a reader of the
/// image learns which of its white cells a beam saw and which the robot
/// stood in (`mapping::insertion`, `mapping::neighbour_support`).
fn free_evidence(walls: WallModel) -> String {
    match walls {
        WallModel::Incidence => format!(
            "the laser's own cell at every scan (the robot stood there), and each beam's line short of its return where its neighbours' returns do not contradict it; a no-return clears only between returns at most {:.0} degrees apart, as far as both saw free",
            MAX_NO_RETURN_GAP.to_degrees()
        ),
        WallModel::Table92 => {
            "every beam's line up to its reading (Table 9.2 as printed), a no-return's out to the no-return reach".into()
        }
    }
}

/// `text` in double quotes, on one line: a quote, a backslash and every
/// control character (line breaks; YAML 1.1 also breaks lines at NEL, LS
/// and PS) written as an escape, so that a file name cannot start a line
/// of its own in the YAML.
fn quoted(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() || c == '\u{2028}' || c == '\u{2029}' => {
                out.push_str(&format!("\\u{:04x}", c as u32))
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Every field of `settings` that differs from the defaults, as a page
/// spells it ([`LogMapSettings::FIELDS`]), with its value; `none` when
/// none does. The pose source, its seed and the cell model are this map's
/// own lines (a session's second pane shows another model than `model`,
/// and its `compareModel` is this map's model), so `poses`, `seed`,
/// `model` and `compareModel` are left to them.
fn changed_settings(settings: &LogMapSettings) -> String {
    let d = LogMapSettings::default();
    let s = settings;
    let number = |v: f64| format!("{v:?}");
    let named = |v: Option<LogCellModel>| v.map_or("none".into(), |m| quoted(m.name()));
    let fields: [(&str, bool, String); 14] = [
        (
            "resolution",
            s.resolution != d.resolution,
            number(s.resolution),
        ),
        ("rangeCap", s.range_cap != d.range_cap, number(s.range_cap)),
        ("alpha", s.alpha != d.alpha, number(s.alpha)),
        ("lOcc", s.l_occ != d.l_occ, number(s.l_occ)),
        ("lFree", s.l_free != d.l_free, number(s.l_free)),
        ("clamp", s.clamp != d.clamp, number(s.clamp)),
        ("margin", s.margin != d.margin, number(s.margin)),
        (
            "noReturnReach",
            s.no_return_reach != d.no_return_reach,
            number(s.no_return_reach),
        ),
        ("walls", s.walls != d.walls, quoted(wall_name(s.walls))),
        ("poses", s.poses != d.poses, quoted(s.poses.name())),
        ("seed", s.seed != d.seed, s.seed.to_string()),
        ("model", s.model != d.model, quoted(s.model.name())),
        (
            "compareModel",
            s.compare_model != d.compare_model,
            named(s.compare_model),
        ),
        (
            "betweenBeams",
            s.between_beams != d.between_beams,
            s.between_beams.to_string(),
        ),
    ];
    debug_assert!(fields.iter().map(|f| f.0).eq(LogMapSettings::FIELDS));
    let changed: Vec<String> = fields
        .into_iter()
        .filter(|f| f.1 && !OWN_LINES.contains(&f.0))
        .map(|(field, _, value)| format!("{field} {value}"))
        .collect();
    if changed.is_empty() {
        "none".into()
    } else {
        changed.join(", ")
    }
}

/// The fields an export states on lines of their own.
const OWN_LINES: [&str; 4] = ["poses", "seed", "model", "compareModel"];

/// A wall model's name as a page spells it.
fn wall_name(walls: WallModel) -> &'static str {
    match walls {
        WallModel::Table92 => WallModel::NAMES[0],
        WallModel::Incidence => WallModel::NAMES[1],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn comments(log: Option<&str>, source: PoseSourceKind, settings: &LogMapSettings) -> String {
        Provenance {
            log_file: log,
            source,
            model: settings.model,
            settings,
        }
        .yaml_comments()
    }

    #[test]
    fn a_default_map_names_its_log_source_model_and_no_changes() {
        let s = LogMapSettings::default();
        let text = comments(Some("intel.log.gz"), PoseSourceKind::Corrected, &s);
        assert!(text.contains("# log: \"intel.log.gz\"\n"), "{text}");
        assert!(text.contains("# pose source: corrected"), "{text}");
        assert!(text.contains("# cell model: hit-counting"), "{text}");
        assert!(
            text.contains("# settings other than the defaults: none\n"),
            "{text}"
        );
        assert!(text.lines().all(|l| l.starts_with("# ")), "{text}");
        assert!(
            text.contains("# free cells rest on: the laser's own cell at every scan"),
            "{text}"
        );
        assert!(text.contains("at most 5 degrees apart"), "{text}");
    }

    /// The chapter's recipe says its free cells are every beam's line.
    #[test]
    fn the_chapter_s_recipe_names_what_its_free_cells_rest_on() {
        let s = LogMapSettings {
            walls: WallModel::Table92,
            ..LogMapSettings::default()
        };
        let text = comments(None, PoseSourceKind::Corrected, &s);
        assert!(
            text.contains("# free cells rest on: every beam's line up to its reading"),
            "{text}"
        );
    }

    #[test]
    fn changed_settings_and_simulated_odometry_are_named() {
        let s = LogMapSettings {
            no_return_reach: 3.0,
            seed: 7,
            poses: PoseSourceKind::DeadReckoning,
            model: LogCellModel::HitMissOdds,
            ..LogMapSettings::default()
        };
        let text = comments(None, s.poses, &s);
        assert!(text.contains("odometry simulated"), "{text}");
        assert!(text.contains("seed 7"), "{text}");
        assert!(text.contains("noReturnReach 3.0"), "{text}");
        assert!(text.contains("# pose source: dead-reckoning"), "{text}");
        assert!(
            !text.contains("seed 7,") && !text.contains("model \""),
            "{text}"
        );
        assert!(text.contains("the cell model's own cut"), "{text}");
    }

    /// Every field is compared: each one changed alone is named.
    #[test]
    fn each_changed_field_is_named() {
        let d = LogMapSettings::default();
        let changed = [
            LogMapSettings {
                resolution: 0.1,
                ..d
            },
            LogMapSettings {
                range_cap: 20.0,
                ..d
            },
            LogMapSettings { alpha: 0.3, ..d },
            LogMapSettings { l_occ: 1.0, ..d },
            LogMapSettings { l_free: -1.0, ..d },
            LogMapSettings { clamp: 2.0, ..d },
            LogMapSettings { margin: 2.0, ..d },
            LogMapSettings {
                no_return_reach: 2.0,
                ..d
            },
            LogMapSettings {
                walls: WallModel::Table92,
                ..d
            },
            LogMapSettings {
                poses: PoseSourceKind::ScanMatched,
                ..d
            },
            LogMapSettings { seed: 9, ..d },
            LogMapSettings {
                model: LogCellModel::LogOdds,
                ..d
            },
            LogMapSettings {
                compare_model: Some(LogCellModel::LogOdds),
                ..d
            },
            LogMapSettings {
                between_beams: false,
                ..d
            },
        ];
        for (s, field) in changed.iter().zip(LogMapSettings::FIELDS) {
            let text = changed_settings(s);
            if OWN_LINES.contains(&field) {
                assert_eq!(text, "none", "{field}");
            } else {
                assert!(text.starts_with(&format!("{field} ")), "{field}: {text}");
            }
        }
    }

    /// A file name cannot start a line of its own in the YAML.
    #[test]
    fn a_hostile_file_name_stays_on_its_comment_line() {
        let s = LogMapSettings::default();
        let text = comments(
            Some("a\nimage: evil.pgm\r\"x\u{2028}y\u{85}"),
            PoseSourceKind::Corrected,
            &s,
        );
        assert!(text.lines().all(|l| l.starts_with("# ")), "{text}");
        assert!(!text.contains(['\r', '\u{2028}', '\u{85}']), "{text}");
    }
}

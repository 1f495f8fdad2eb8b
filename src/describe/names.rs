//! Which frame, eye, row and column a file of externally rendered frames is:
//! read from its name by a regular expression with named groups, or by a
//! template such as `{eye}_{frame}_{row}_{col}.png` (easier to type than a
//! regex). Only `frame` is required, so an untiled capture (one image per
//! eye and frame) or a mono one (no eye) can be described too.

use regex::Regex;

use crate::error::{Error, Result};

/// The default: ufcsr capture's names (`tiles/f0012_left_r2_c3.png`), the
/// row and column optional (`f0012_left.png` is an untiled eye image).
pub const DEFAULT_PATTERN: &str =
    r"f(?P<frame>\d+)_(?P<eye>[A-Za-z0-9]+)(?:_r(?P<row>\d+)_c(?P<col>\d+))?\.(?i:png)$";

/// The eye a name without an `eye` group is given: one eye, called `left`.
pub(crate) const DEFAULT_EYE: &str = "left";

/// What a file's name says.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct TileName {
    pub frame: u32,
    pub eye: String,
    pub row: u32,
    pub col: u32,
}

/// A compiled `--pattern`.
#[derive(Debug, Clone)]
pub(crate) struct NamePattern {
    regex: Regex,
    /// The pattern as given, for messages.
    pub text: String,
}

impl NamePattern {
    /// A regex when the text has a named group (`(?P<frame>` or `(?<frame>`),
    /// else a template: `{frame}`, `{row}`, `{col}` match digits, `{eye}`
    /// letters and digits, `*` any characters but `/`, `?` one; the template
    /// matches the end of the path (`Left_{frame}.png` finds `x/Left_0012.png`).
    pub(crate) fn new(text: &str) -> Result<NamePattern> {
        let is_regex = text.contains("(?P<") || text.contains("(?<");
        let source = if is_regex { text.to_string() } else { template_to_regex(text)? };
        let regex = Regex::new(&source).map_err(|error| {
            Error::BadOptions(format!("--pattern {text:?} is not a valid pattern: {error}"))
        })?;
        let names: Vec<&str> = regex.capture_names().flatten().collect();
        if !names.contains(&"frame") {
            return Err(Error::BadOptions(format!(
                "--pattern {text:?} has no `frame` group: name it (?P<frame>\\d+) in a regex or {{frame}} in a template"
            )));
        }
        if let Some(unknown) = names.iter().find(|n| !["frame", "eye", "row", "col"].contains(n)) {
            return Err(Error::BadOptions(format!(
                "--pattern {text:?}: unknown group {unknown:?} (the groups are frame, eye, row and col)"
            )));
        }
        Ok(NamePattern { regex, text: text.to_string() })
    }

    /// What `relative` (a path with `/` separators) says, `None` when it does
    /// not match; an error when a group holds no number it must hold.
    pub(crate) fn read(&self, relative: &str) -> std::result::Result<Option<TileName>, String> {
        let Some(captures) = self.regex.captures(relative) else { return Ok(None) };
        let group = |name: &str| captures.name(name).map(|m| m.as_str()).filter(|s| !s.is_empty());
        let number = |name: &str, default: Option<u32>| -> std::result::Result<u32, String> {
            match group(name) {
                Some(text) => text.parse::<u32>().map_err(|_| {
                    format!(
                        "its {name} {text:?} (from --pattern) is not a whole number from 0 to {}",
                        u32::MAX
                    )
                }),
                None => {
                    default.ok_or_else(|| format!("--pattern matched it but its `{name}` group is empty"))
                }
            }
        };
        Ok(Some(TileName {
            frame: number("frame", None)?,
            eye: group("eye").map_or_else(|| DEFAULT_EYE.to_string(), str::to_lowercase),
            row: number("row", Some(0))?,
            col: number("col", Some(0))?,
        }))
    }
}

/// `{eye}_{frame}.png` → `(?:^|/)(?P<eye>[A-Za-z0-9]+)_(?P<frame>\d+)\.png$`.
fn template_to_regex(text: &str) -> Result<String> {
    let mut out = String::from("(?:^|/)");
    let mut rest = text;
    while let Some(c) = rest.chars().next() {
        if let Some(tail) = rest.strip_prefix('{') {
            let Some(end) = tail.find('}') else {
                return Err(Error::BadOptions(format!("--pattern {text:?}: a `{{` without its `}}`")));
            };
            let name = &tail[..end];
            match name {
                "frame" | "row" | "col" => out.push_str(&format!(r"(?P<{name}>\d+)")),
                "eye" => out.push_str("(?P<eye>[A-Za-z0-9]+)"),
                _ => {
                    return Err(Error::BadOptions(format!(
                        "--pattern {text:?}: unknown field {{{name}}} (the fields are {{frame}}, {{eye}}, {{row}} and {{col}})"
                    )));
                }
            }
            rest = &tail[end + 1..];
            continue;
        }
        match c {
            '*' => out.push_str("[^/]*"),
            '?' => out.push_str("[^/]"),
            _ => out.push_str(&regex::escape(&c.to_string())),
        }
        rest = &rest[c.len_utf8()..];
    }
    out.push('$');
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn name(frame: u32, eye: &str, row: u32, col: u32) -> TileName {
        TileName { frame, eye: eye.to_string(), row, col }
    }

    #[test]
    fn default_pattern_reads_capture_names_tiled_and_untiled() {
        let pattern = NamePattern::new(DEFAULT_PATTERN).unwrap();
        assert_eq!(pattern.read("tiles/f0012_left_r2_c3.png").unwrap(), Some(name(12, "left", 2, 3)));
        assert_eq!(pattern.read("f0012_Right.PNG").unwrap(), Some(name(12, "right", 0, 0)));
        assert_eq!(pattern.read("pidt.png").unwrap(), None);
    }

    #[test]
    fn templates_match_the_end_of_the_path_with_optional_groups() {
        let pattern = NamePattern::new("{eye}_{frame}_{row}_{col}.png").unwrap();
        assert_eq!(pattern.read("unity/Left_0007_1_4.png").unwrap(), Some(name(7, "left", 1, 4)));
        assert_eq!(pattern.read("unity/Left_0007_1_4.png.bak").unwrap(), None);
        let mono = NamePattern::new("frame_{frame}*.png").unwrap();
        assert_eq!(mono.read("frame_0042_final.png").unwrap(), Some(name(42, DEFAULT_EYE, 0, 0)));
    }

    #[test]
    fn empty_optional_groups_default_and_bad_numbers_are_named() {
        let pattern = NamePattern::new(r"(?P<frame>\d+)_r(?P<row>\d*)\.png$").unwrap();
        assert_eq!(pattern.read("5_r.png").unwrap(), Some(name(5, DEFAULT_EYE, 0, 0)));
        let huge = pattern.read("99999999999_r1.png").unwrap_err();
        assert!(huge.contains("frame \"99999999999\""), "{huge}");
        let words = NamePattern::new(r"(?P<frame>\w+)\.png$").unwrap();
        assert!(words.read("abc.png").unwrap_err().contains("not a whole number"));
    }

    #[test]
    fn patterns_without_frame_or_with_unknown_groups_are_refused() {
        let no_frame = NamePattern::new(r"(?P<eye>\w+)\.png").unwrap_err().to_string();
        assert!(no_frame.contains("no `frame` group"), "{no_frame}");
        let unknown = NamePattern::new(r"(?P<frame>\d+)_(?P<camera>\w+)").unwrap_err().to_string();
        assert!(unknown.contains("unknown group \"camera\""), "{unknown}");
        assert!(NamePattern::new("{frame}_{lens}.png").unwrap_err().to_string().contains("{lens}"));
        assert!(NamePattern::new(r"(?P<frame>\d+").unwrap_err().to_string().contains("not a valid pattern"));
    }
}

//! Where a page came from, for a reader holding only the page: when it was
//! written (UTC; `SOURCE_DATE_EPOCH` fixes it, for reproducible outputs),
//! by which version of ufcsr, with which command line, in which folder (the
//! paths on the page are relative to it).

use std::time::{SystemTime, UNIX_EPOCH};

use crate::output::html::escape::escape;

/// The seconds since 1970 to show: `SOURCE_DATE_EPOCH` when set and valid, else now.
fn epoch_seconds() -> i64 {
    if let Some(fixed) = std::env::var("SOURCE_DATE_EPOCH").ok().and_then(|text| text.trim().parse().ok()) {
        return fixed;
    }
    SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |elapsed| elapsed.as_secs() as i64)
}

/// `seconds` since 1970 as `YYYY-MM-DD HH:MM UTC` (the proleptic Gregorian calendar).
pub(crate) fn utc_date(seconds: i64) -> String {
    let (days, rest) = (seconds.div_euclid(86_400), seconds.rem_euclid(86_400));
    // Days to civil date (H. Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02} {:02}:{:02} UTC", rest / 3600, rest % 3600 / 60)
}

/// One argument as a shell would need it (quoted when it holds anything but
/// plain path characters).
fn shell_word(word: &str) -> String {
    if !word.is_empty() && word.chars().all(|c| c.is_alphanumeric() || "-_./=:,+@%".contains(c)) {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', r"'\''"))
    }
}

/// The provenance paragraph of a page, HTML.
pub(crate) fn paragraph() -> String {
    // args_os: `std::env::args` panics on an argument that is not UTF-8 (a path).
    let command: Vec<String> = std::env::args_os().map(|arg| shell_word(&arg.to_string_lossy())).collect();
    let folder = std::env::current_dir().map(|dir| dir.display().to_string()).unwrap_or_default();
    format!(
        "<p class=\"provenance\">Written {} by ufcsr {}, command line <code>{}</code> in <code>{}</code>.</p>",
        utc_date(epoch_seconds()),
        env!("CARGO_PKG_VERSION"),
        escape(&command.join(" ")),
        escape(&folder)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_are_civil_utc_and_arguments_are_quoted_for_a_shell() {
        assert_eq!(utc_date(0), "1970-01-01 00:00 UTC");
        assert_eq!(utc_date(951_782_400), "2000-02-29 00:00 UTC");
        assert_eq!(utc_date(1_796_342_400 + 3_660), "2026-12-04 01:01 UTC");
        assert_eq!(shell_word("results/A"), "results/A");
        assert_eq!(shell_word("my results"), "'my results'");
        assert_eq!(shell_word("it's"), r"'it'\''s'");
    }
}

//! Numbers for people: counts with thousands separators (`160,000`, not
//! `160000.0`) and axis ticks that are whole numbers where the quantity is,
//! shared by the plots and the HTML pages.

/// `value` with a comma between each group of three digits.
pub(crate) fn grouped(value: u64) -> String {
    let digits = value.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (index, digit) in digits.chars().enumerate() {
        if index > 0 && (digits.len() - index).is_multiple_of(3) {
            out.push(',');
        }
        out.push(digit);
    }
    out
}

/// An axis tick: a whole, grouped number when the axis spans more than 10
/// units, else one decimal (`0.5`).
pub(crate) fn tick(value: f64, span: f64) -> String {
    if span > 10.0 {
        let rounded = value.round();
        if rounded < 0.0 { format!("-{}", grouped(-rounded as u64)) } else { grouped(rounded as u64) }
    } else {
        format!("{value:.1}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_are_grouped_by_thousands_and_ticks_are_whole_on_wide_axes() {
        assert_eq!(grouped(0), "0");
        assert_eq!(grouped(999), "999");
        assert_eq!(grouped(1000), "1,000");
        assert_eq!(grouped(160_000), "160,000");
        assert_eq!(grouped(16_777_216), "16,777,216");
        assert_eq!(tick(160_000.0, 200_000.0), "160,000");
        assert_eq!(tick(-20.4, 100.0), "-20");
        assert_eq!(tick(0.5, 2.0), "0.5");
    }
}

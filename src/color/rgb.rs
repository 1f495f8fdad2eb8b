//! 24-bit RGB colours: the currency of UFCSR.
//!
//! Every texel of a palette, every part of a legend and every background is a
//! colour; packing them as `0xRRGGBB` in a `u32` makes them usable directly as
//! indices into dense 2^24 tables, which is what keeps counting fast.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// Number of distinct 24-bit colours (= 4096 × 4096, the canonical palette).
pub const COLOR_COUNT: usize = 1 << 24;

/// A 24-bit RGB colour packed as `0xRRGGBB`.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Color(u32);

impl Color {
    /// The UFCSR default background, `#000FFF`.
    pub const DEFAULT_BACKGROUND: Color = Color(0x000FFF);

    /// Builds a colour from its channels.
    pub const fn from_rgb(r: u8, g: u8, b: u8) -> Color {
        Color(((r as u32) << 16) | ((g as u32) << 8) | b as u32)
    }

    /// Builds a colour from a packed `0xRRGGBB` value; higher bits are dropped.
    pub const fn from_packed(packed: u32) -> Color {
        Color(packed & 0x00FF_FFFF)
    }

    /// The packed `0xRRGGBB` value, usable as an index into a 2^24 table.
    pub const fn packed(self) -> u32 {
        self.0
    }

    /// The `[r, g, b]` channels.
    pub const fn rgb(self) -> [u8; 3] {
        [(self.0 >> 16) as u8, (self.0 >> 8) as u8, self.0 as u8]
    }
}

impl fmt::Display for Color {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{:06X}", self.0)
    }
}

impl fmt::Debug for Color {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

/// Why a colour string was rejected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("invalid colour {0:?}: expected #RRGGBB (six hex digits)")]
pub struct ParseColorError(pub String);

impl FromStr for Color {
    type Err = ParseColorError;

    /// Parses `#RRGGBB` (the `#` is optional, hex digits in either case).
    fn from_str(text: &str) -> Result<Color, ParseColorError> {
        let trimmed = text.trim();
        let digits = trimmed.strip_prefix('#').unwrap_or(trimmed);
        if digits.len() != 6 || !digits.bytes().all(|b| b.is_ascii_hexdigit()) {
            return Err(ParseColorError(text.to_string()));
        }
        u32::from_str_radix(digits, 16).map(Color).map_err(|_| ParseColorError(text.to_string()))
    }
}

impl Serialize for Color {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

/// `#RRGGBB` in capitals, as ufcsr writes a colour.
impl schemars::JsonSchema for Color {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Color".into()
    }
    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "description": "#RRGGBB, upper case.",
            "type": "string",
            "pattern": "^#[0-9A-F]{6}$"
        })
    }
}

impl<'de> Deserialize<'de> for Color {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Color, D::Error> {
        let text = String::deserialize(deserializer)?;
        text.parse().map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_prints_hex() {
        assert_eq!("#000FFF".parse::<Color>().unwrap(), Color::from_packed(0x000FFF));
        assert_eq!("0a0000".parse::<Color>().unwrap(), Color::from_rgb(10, 0, 0));
        assert_eq!(Color::from_rgb(1, 2, 255).to_string(), "#0102FF");
        for bad in ["", "#12345", "#1234567", "#GG0000", "red"] {
            assert!(bad.parse::<Color>().is_err(), "{bad}");
        }
    }
}

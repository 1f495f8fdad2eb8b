//! Legends and captions drawn into raster pictures: text wrapped to the
//! picture's width with the kerned text layout of the figures
//! ([`crate::output::figure::text_width`]), so it is never cut off at the
//! right edge, and colour swatches with their labels flowing across lines.
//! One routine for every raster picture that needs a key: the placement
//! overview (`placement.png`) and the capture's inspect pictures.

use crate::output::figure::{KernedBitmap, text_width};

/// Text size of captions and legends on screen-sized pictures, plotters
/// pixels (about 11 px capitals).
pub const LEGEND_TEXT_PX: f64 = 15.0;
/// Line height of captions and legends at [`LEGEND_TEXT_PX`], pixels.
pub const LEGEND_LINE: u32 = 20;
const INK: [u8; 3] = [20, 20, 20];

/// The plotters text size that prints at `points` when a picture
/// `width_px` wide is printed `width_mm` wide (plotters draws size `s` at
/// an em of `s / 1.24` pixels, see [`crate::output::figure::pt`]).
pub fn text_px_for(points: f64, width_px: u32, width_mm: f64) -> f64 {
    points * crate::output::figure::MM_PER_PT / width_mm * f64::from(width_px) * 1.24
}

/// One legend entry: a colour and what it means.
#[derive(Debug, Clone, PartialEq)]
pub struct LegendEntry {
    pub color: [u8; 3],
    pub label: String,
}

/// Texts and swatches placed on a picture, at one text size.
#[derive(Debug, Clone, PartialEq)]
pub struct TextLayout {
    /// Plotters text size ([`LEGEND_TEXT_PX`] on screen-sized pictures).
    pub size: f64,
    /// `(x, y of the line's top, text)`.
    pub texts: Vec<(i32, i32, String)>,
    /// `(x, y, colour)` of a swatch square ([`TextLayout::swatch`] pixels).
    pub swatches: Vec<(i32, i32, [u8; 3])>,
}

impl TextLayout {
    /// An empty layout for text of plotters size `size`.
    pub fn new(size: f64) -> TextLayout {
        TextLayout { size, texts: Vec::new(), swatches: Vec::new() }
    }

    /// Line height, pixels (4/3 of the size: [`LEGEND_LINE`] at 15).
    pub fn line(&self) -> u32 {
        (self.size * 4.0 / 3.0).round() as u32
    }

    /// Side of a swatch, pixels (12 at 15).
    pub fn swatch(&self) -> u32 {
        (self.size * 0.8).round() as u32
    }

    /// The kerned width of `text` at this size, pixels (0 without a font).
    pub fn width(&self, text: &str) -> f64 {
        f64::from(text_width(text, self.size))
    }

    /// The middle of swatch `index`, where its colour shows.
    pub fn swatch_centre(&self, index: usize) -> (i32, i32) {
        let (x, y, _) = self.swatches[index];
        let half = (self.swatch() / 2) as i32;
        (x + half, y + half)
    }

    /// Wraps `text` to `room` pixels from `(x, y)`; returns the top of
    /// the line after it.
    pub fn paragraph(&mut self, text: &str, x: u32, y: u32, room: f64) -> u32 {
        let mut y = y;
        for line in wrap(text, self.size, room) {
            self.texts.push((x as i32, y as i32, line));
            y += self.line();
        }
        y
    }

    /// Lays out `entries` from `(x0, y)` within `room` pixels, flowing left
    /// to right and onto new lines (a label wider than the room ends in
    /// "…"); returns the top of the line after them.
    pub fn entries(&mut self, entries: &[LegendEntry], x0: u32, y: u32, room: f64) -> u32 {
        let (left, mut y) = (f64::from(x0), y);
        let (swatch, gap, entry_gap) = (self.swatch(), self.swatch() / 2 - 1, self.swatch() * 3 / 2);
        let mut x = left;
        for entry in entries {
            let label = fit(&entry.label, self.size, room - f64::from(swatch + gap));
            let width = f64::from(swatch + gap) + self.width(&label);
            if x > left && x + width > left + room {
                x = left;
                y += self.line();
            }
            self.swatches.push((x as i32, (y + self.line() / 7) as i32, entry.color));
            self.texts.push(((x as u32 + swatch + gap) as i32, y as i32, label));
            x += width + f64::from(entry_gap);
        }
        if entries.is_empty() { y } else { y + self.line() }
    }

    /// Draws the swatches (outlined) and, when a font is found, the texts
    /// onto `rgb` (`[width, height]`).
    pub fn draw(&self, rgb: &mut [u8], [width, height]: [u32; 2]) {
        let side = self.swatch() as i32;
        for &(x, y, color) in &self.swatches {
            for dy in 0..side {
                for dx in 0..side {
                    let edge = dx == 0 || dy == 0 || dx + 1 == side || dy + 1 == side;
                    let (px, py) = (x + dx, y + dy);
                    if px >= 0 && py >= 0 && (px as u32) < width && (py as u32) < height {
                        let i = (py as usize * width as usize + px as usize) * 3;
                        rgb[i..i + 3].copy_from_slice(&if edge { INK } else { color });
                    }
                }
            }
        }
        draw_texts(rgb, [width, height], &self.texts, self.size);
    }
}

/// `text` broken at spaces into lines no wider than `room` at `size` (a
/// word wider than the room is cut to fit, see [`fit`]).
pub(crate) fn wrap(text: &str, size: f64, room: f64) -> Vec<String> {
    let width = |t: &str| f64::from(text_width(t, size));
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split(' ') {
        let candidate = if line.is_empty() { word.to_string() } else { format!("{line} {word}") };
        if width(&candidate) <= room || line.is_empty() {
            line = candidate;
        } else {
            lines.push(std::mem::take(&mut line));
            line = word.to_string();
        }
    }
    lines.push(line);
    lines.into_iter().map(|line| fit(&line, size, room)).collect()
}

/// `text`, cut and ended with "…" where it is wider than `room` at `size`.
pub(crate) fn fit(text: &str, size: f64, room: f64) -> String {
    if f64::from(text_width(text, size)) <= room {
        return text.to_string();
    }
    // Each prefix's width with the ellipsis, measured in one pass: the longest that fits.
    let widths = crate::output::figure::widths_with_end(text, '…', size);
    let keep = (0..widths.len()).rev().find(|&k| f64::from(widths[k]) <= room).unwrap_or(0);
    let kept: String = text.chars().take(keep).collect();
    format!("{kept}…")
}

/// Draws `texts` (kerned, black, at `size`) when a font is found: text is
/// a courtesy the files beside say too.
pub(crate) fn draw_texts(rgb: &mut [u8], [width, height]: [u32; 2], texts: &[(i32, i32, String)], size: f64) {
    use plotters::prelude::*;
    if texts.is_empty() || !crate::output::plot_font_available() {
        return;
    }
    let root = KernedBitmap(BitMapBackend::with_buffer(rgb, (width, height))).into_drawing_area();
    let style = ("sans-serif", size).into_font().color(&BLACK);
    let mut drawn: std::result::Result<(), _> = Ok(());
    for (x, y, text) in texts {
        drawn = drawn.and(root.draw(&Text::new(text.clone(), (*x, *y), style.clone())));
    }
    let _ = drawn.and(root.present());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrapped_lines_and_legend_labels_fit_their_room() {
        if !crate::output::plot_font_available() {
            eprintln!("skipped: no font (set UFCSR_FONT)");
            return;
        }
        let text = "a long caption of many words that cannot fit on one line of three hundred pixels at all";
        let lines = wrap(text, LEGEND_TEXT_PX, 300.0);
        assert!(lines.len() >= 2, "{lines:?}");
        assert_eq!(lines.join(" "), text, "wrapping loses no word");
        let mut layout = TextLayout::new(LEGEND_TEXT_PX);
        assert!(lines.iter().all(|l| layout.width(l) <= 300.0));
        let entries: Vec<LegendEntry> = ["door", "a_very_long_part_name_that_is_wider_than_the_room_given"]
            .iter()
            .map(|l| LegendEntry { color: [200, 0, 0], label: l.to_string() })
            .collect();
        let next = layout.entries(&entries, 6, 10, 200.0);
        assert_eq!(next, 10 + 2 * LEGEND_LINE, "the long entry goes onto its own line");
        assert!(layout.texts[1].2.ends_with('…'));
        assert!(layout.texts.iter().all(|(x, _, t)| f64::from(*x) + layout.width(t) <= 206.0));
        // 7 pt at 183 mm on a 1600-pixel picture: plotters size 26.8.
        assert!((text_px_for(7.0, 1600, 183.0) - 26.77).abs() < 0.01);
    }

    #[test]
    fn fitting_a_long_label_measures_each_glyph_a_bounded_number_of_times() {
        if !crate::output::plot_font_available() {
            eprintln!("skipped: no font (set UFCSR_FONT)");
            return;
        }
        let name: String = "windshield_rail_left_".chars().cycle().take(10_000).collect();
        crate::output::figure::GLYPHS_MEASURED.with(|count| count.set(0));
        let fitted = fit(&name, LEGEND_TEXT_PX, 300.0);
        let measured = crate::output::figure::GLYPHS_MEASURED.with(std::cell::Cell::get);
        // One pass (10,000 glyphs), where cutting one character at a time measured ~50 million.
        assert!(measured <= 2 * name.len(), "{measured} glyphs measured for a {}-character name", name.len());
        assert!(fitted.ends_with('…') && fitted.len() < 100, "{fitted}");
        assert!(TextLayout::new(LEGEND_TEXT_PX).width(&fitted) <= 300.0);
        // The longest prefix that fits: one more character would not.
        let kept: String = fitted.chars().take(fitted.chars().count() - 1).collect();
        let longer: String = name.chars().take(kept.chars().count() + 1).collect();
        assert!(TextLayout::new(LEGEND_TEXT_PX).width(&format!("{longer}…")) > 300.0);
    }

    /// A layout measured before anything was drawn (placement.png's is)
    /// finds the font itself: measured first, the width is a real one.
    #[test]
    fn text_is_measured_with_the_font_even_before_anything_was_drawn() {
        let width = TextLayout::new(LEGEND_TEXT_PX).width("front_license_plate");
        if crate::output::plot_font_available() {
            assert!(width > 100.0, "front_license_plate measured {width} px wide");
        } else {
            eprintln!("skipped: no font (set UFCSR_FONT)");
        }
    }
}

//! The look shared by every figure: an embedded font, a colour-blind-safe palette, a
//! perceptually uniform colour map and the font sizes.
//!
//! # Fonts
//! Figures must render on a machine without system fonts or fontconfig, so text goes through
//! plotters' pure-Rust `ab_glyph` path with DejaVu Sans (Bitstream Vera licence: free to embed
//! and redistribute) compiled into the binary by the `dejavu` crate. [`init_fonts`] registers it
//! under the family name [`FAMILY`] = `"sans-serif"`. The bitmap backend rasterizes with it; the
//! SVG backend writes `<text font-family="sans-serif">`, which every SVG viewer resolves to its
//! default sans-serif face (DejaVu Sans where installed; metrics of other sans faces are close
//! enough that the layout computed with DejaVu holds).
//!
//! # Colours
//! Categories use the Okabe–Ito palette (Okabe & Ito 2008, "Color Universal Design"), which stays
//! distinguishable under the common colour-vision deficiencies. Continuous values use viridis
//! (van der Walt & Smith), perceptually uniform and readable in grey scale.

use plotters::style::{FontStyle, IntoFont, RGBColor, TextStyle};
use std::sync::Once;

/// The font family name every figure uses (registered by [`init_fonts`]).
pub const FAMILY: &str = "sans-serif";

/// Numeric guards shared by the figures. They decide how a figure is drawn, never a number
/// written to a file.
pub mod guard {
    /// A length, span or weight denominator a figure divides by is at least this (a degenerate
    /// range still draws instead of dividing by zero).
    pub const SPAN_FLOOR: f64 = 1e-12;
    /// An axis or colour scale whose data are all zero spans this instead (the data's unit).
    pub const SCALE_FLOOR: f64 = 1e-9;
    /// Two coordinates closer than this are the same value (absolute, in the data's unit, or
    /// relative where a value's magnitude multiplies it).
    pub const SAME: f64 = 1e-9;
    /// An axis range or depth extent narrower than this is degenerate and gets a default width.
    pub const MIN_EXTENT: f64 = 1e-6;
    /// A width, pad or spacing a figure lays out from its data is at least this (the data's
    /// unit: a scene of a single point, or rays at one angle, still get a frame).
    pub const MIN_LAYOUT: f64 = 1e-3;
}

/// Title size (px).
pub const TITLE: f64 = 30.0;
/// Axis description size (px).
pub const AXIS: f64 = 26.0;
/// Tick label size (px).
pub const TICK: f64 = 21.0;
/// Legend and annotation size (px).
pub const LEGEND: f64 = 21.0;

static FONTS: Once = Once::new();

/// A text style of the embedded family at `size` px (anchor top-left, black).
pub fn text(size: f64) -> TextStyle<'static> {
    TextStyle::from((FAMILY, size).into_font())
}

/// Register the embedded DejaVu Sans (regular, bold, oblique) with plotters under [`FAMILY`].
/// Idempotent and thread-safe; every renderer calls it first.
pub fn init_fonts() {
    FONTS.call_once(|| {
        // The bytes are a valid TrueType font shipped by the `dejavu` crate; a failure here
        // would be a broken build, not bad user input, so it is ignored (text would then fail
        // to draw with a FontUnavailable error that names the cause).
        let _ = plotters::style::register_font(FAMILY, FontStyle::Normal, dejavu::sans::regular());
        let _ = plotters::style::register_font(FAMILY, FontStyle::Bold, dejavu::sans::bold());
        let _ = plotters::style::register_font(FAMILY, FontStyle::Italic, dejavu::sans::oblique());
        let _ = plotters::style::register_font(FAMILY, FontStyle::Oblique, dejavu::sans::oblique());
    });
}

/// Okabe–Ito black.
pub const BLACK: RGBColor = RGBColor(0, 0, 0);
/// Okabe–Ito orange.
pub const ORANGE: RGBColor = RGBColor(0xE6, 0x9F, 0x00);
/// Okabe–Ito sky blue.
pub const SKY_BLUE: RGBColor = RGBColor(0x56, 0xB4, 0xE9);
/// Okabe–Ito bluish green.
pub const GREEN: RGBColor = RGBColor(0x00, 0x9E, 0x73);
/// Okabe–Ito yellow.
pub const YELLOW: RGBColor = RGBColor(0xF0, 0xE4, 0x42);
/// Okabe–Ito blue.
pub const BLUE: RGBColor = RGBColor(0x00, 0x72, 0xB2);
/// Okabe–Ito vermillion.
pub const VERMILLION: RGBColor = RGBColor(0xD5, 0x5E, 0x00);
/// Okabe–Ito reddish purple.
pub const PURPLE: RGBColor = RGBColor(0xCC, 0x79, 0xA7);
/// A neutral grey for guides and de-emphasized data.
pub const GREY: RGBColor = RGBColor(0x99, 0x99, 0x99);
/// A light grey for backgrounds of maps and grids.
pub const LIGHT_GREY: RGBColor = RGBColor(0xE8, 0xE8, 0xE8);

/// Okabe–Ito colours in the order used for series (black last: it is kept for references).
pub const SERIES: [RGBColor; 7] = [BLUE, VERMILLION, GREEN, PURPLE, ORANGE, SKY_BLUE, BLACK];

/// The `i`-th series colour (cycling).
pub fn series(i: usize) -> RGBColor {
    SERIES[i % SERIES.len()]
}

/// Viridis sampled at eleven equally spaced stops (matplotlib's `_viridis_data`, every 25.5th).
const VIRIDIS: [(u8, u8, u8); 11] = [
    (0x44, 0x01, 0x54),
    (0x48, 0x24, 0x75),
    (0x41, 0x44, 0x87),
    (0x35, 0x5f, 0x8d),
    (0x2a, 0x78, 0x8e),
    (0x21, 0x91, 0x8c),
    (0x22, 0xa8, 0x84),
    (0x44, 0xbf, 0x70),
    (0x7a, 0xd1, 0x51),
    (0xbd, 0xdf, 0x26),
    (0xfd, 0xe7, 0x25),
];

/// Viridis at `t` ∈ [0, 1] (clamped; NaN maps to 0), linear between the stops.
pub fn viridis(t: f64) -> RGBColor {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let lerp = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    RGBColor(lerp(a.0, b.0), lerp(a.1, b.1), lerp(a.2, b.2))
}

/// `c` darkened toward black by `f` ∈ [0, 1].
pub fn darken(c: RGBColor, f: f64) -> RGBColor {
    let g = |v: u8| (v as f64 * (1.0 - f)).round() as u8;
    RGBColor(g(c.0), g(c.1), g(c.2))
}

/// `c` lightened toward white by `f` ∈ [0, 1].
pub fn lighten(c: RGBColor, f: f64) -> RGBColor {
    let g = |v: u8| (v as f64 + (255.0 - v as f64) * f).round() as u8;
    RGBColor(g(c.0), g(c.1), g(c.2))
}

/// "Nice" tick positions covering `[lo, hi]` with about `n` intervals (1-2-5 steps).
pub fn nice_ticks(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    if !lo.is_finite() || !hi.is_finite() || hi <= lo {
        return vec![lo];
    }
    let raw = (hi - lo) / n.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// [`tick_label`] for plotters' label formatters (`.x_label_formatter(&style::fmt_tick)`).
pub fn fmt_tick(v: &f64) -> String {
    tick_label(*v)
}

/// A tick label: integers without decimals, otherwise the shortest of a few fixed precisions.
pub fn tick_label(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if (v - v.round()).abs() < guard::SAME * v.abs().max(1.0) {
        return format!("{}", v.round() as i64);
    }
    for p in 1..4 {
        let s = format!("{v:.p$}");
        if (s.parse::<f64>().unwrap_or(f64::NAN) - v).abs() < guard::SAME * v.abs() {
            return s;
        }
    }
    format!("{v:.3}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_and_monotone_luminance() {
        assert_eq!(viridis(0.0), RGBColor(0x44, 0x01, 0x54));
        assert_eq!(viridis(1.0), RGBColor(0xfd, 0xe7, 0x25));
        // Viridis is designed with monotonically increasing lightness; check relative luminance.
        let lum = |c: RGBColor| 0.2126 * c.0 as f64 + 0.7152 * c.1 as f64 + 0.0722 * c.2 as f64;
        let mut prev = -1.0;
        for k in 0..=100 {
            let l = lum(viridis(k as f64 / 100.0));
            assert!(l > prev, "luminance not increasing at {k}");
            prev = l;
        }
    }

    #[test]
    fn ticks_are_nice_and_cover() {
        let t = nice_ticks(0.0, 9.3, 5);
        assert_eq!(t, vec![0.0, 2.0, 4.0, 6.0, 8.0]);
        let t = nice_ticks(-1.0, 1.0, 4);
        assert_eq!(t, vec![-1.0, -0.5, 0.0, 0.5, 1.0]);
        assert_eq!(tick_label(2.5), "2.5");
        assert_eq!(tick_label(-4.0), "-4");
    }
}

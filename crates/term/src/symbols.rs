//! Sub-cell symbol sets: a cell split into 1×2, 2×2, 2×3 or 2×4 pixels,
//! each drawn in the foreground or the background colour by one glyph.
//!
//! A glyph is named by its mask: bit `row · columns + column` is set where
//! the glyph paints the foreground (row 0 at the top). Every mask of a set
//! has a glyph, so choosing one is a table lookup ([`Symbols::glyph`]).
//!
//! Code points: quadrants are the Block Elements (U+2580–U+259F).
//! Sextants are Unicode 13's U+1FB00–U+1FB3B, the 64 masks in counting
//! order without the four that already exist (empty, left half, right
//! half, full). Octants are Unicode 16's U+1CD00–U+1CDE5, the 256 masks in
//! counting order without the 26 that exist elsewhere ([`OCTANT_ELSEWHERE`]).

/// Which glyphs draw a cell, chafa's names.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Symbols {
    /// `▀`: one pixel wide, two tall (every terminal font has it).
    #[default]
    Half,
    /// Quadrants (`▘▝▖▗▚▞…`): 2×2 pixels, Unicode 1.
    Quad,
    /// Sextants: 2×3 pixels, Unicode 13 (U+1FB00).
    Sextant,
    /// Octants: 2×4 pixels, Unicode 16 (U+1CD00).
    Octant,
}

/// Quadrant glyphs by mask (bit 0 upper left, 1 upper right, 2 lower
/// left, 3 lower right).
const QUADRANTS: [char; 16] = [
    ' ', '▘', '▝', '▀', '▖', '▌', '▞', '▛', '▗', '▚', '▐', '▜', '▄', '▙', '▟', '█',
];

/// The octant masks Unicode 16 left out of U+1CD00–U+1CDE5 because a
/// character with that picture existed (or came with them elsewhere), in
/// mask order.
pub const OCTANT_ELSEWHERE: [(u8, char); 26] = [
    (0x00, ' '),
    (0x01, '\u{1CEA8}'), // LEFT HALF UPPER ONE QUARTER BLOCK
    (0x02, '\u{1CEAB}'), // RIGHT HALF UPPER ONE QUARTER BLOCK
    (0x03, '\u{1FB82}'), // UPPER ONE QUARTER BLOCK
    (0x05, '▘'),
    (0x0A, '▝'),
    (0x0F, '▀'),
    (0x14, '\u{1FBE6}'), // MIDDLE LEFT ONE QUARTER BLOCK
    (0x28, '\u{1FBE7}'), // MIDDLE RIGHT ONE QUARTER BLOCK
    (0x3F, '\u{1FB85}'), // UPPER THREE QUARTERS BLOCK
    (0x40, '\u{1CEA3}'), // LEFT HALF LOWER ONE QUARTER BLOCK
    (0x50, '▖'),
    (0x55, '▌'),
    (0x5A, '▞'),
    (0x5F, '▛'),
    (0x80, '\u{1CEA0}'), // RIGHT HALF LOWER ONE QUARTER BLOCK
    (0xA0, '▗'),
    (0xA5, '▚'),
    (0xAA, '▐'),
    (0xAF, '▜'),
    (0xC0, '▂'),
    (0xF0, '▄'),
    (0xF5, '▙'),
    (0xFA, '▟'),
    (0xFC, '▆'),
    (0xFF, '█'),
];

impl Symbols {
    /// Every set, in the order the key cycles them.
    pub const ALL: [Symbols; 4] = [
        Symbols::Half,
        Symbols::Quad,
        Symbols::Sextant,
        Symbols::Octant,
    ];

    /// Pixel columns per cell.
    pub fn columns(self) -> usize {
        match self {
            Symbols::Half => 1,
            _ => 2,
        }
    }

    /// Pixel rows per cell.
    pub fn rows(self) -> usize {
        match self {
            Symbols::Half | Symbols::Quad => 2,
            Symbols::Sextant => 3,
            Symbols::Octant => 4,
        }
    }

    /// Pixels per cell.
    pub fn pixels(self) -> usize {
        self.columns() * self.rows()
    }

    /// Width over height of one pixel on a cell twice as tall as wide (the
    /// usual terminal font): the projection widens the view by this so the
    /// picture keeps its proportions.
    pub fn pixel_aspect(self) -> f32 {
        self.rows() as f32 / (2.0 * self.columns() as f32)
    }

    /// The name `--symbols` takes (chafa's).
    pub fn name(self) -> &'static str {
        match self {
            Symbols::Half => "half",
            Symbols::Quad => "quad",
            Symbols::Sextant => "sextant",
            Symbols::Octant => "octant",
        }
    }

    /// The next set (the key's cycle).
    pub fn next(self) -> Symbols {
        let i = Symbols::ALL.iter().position(|&s| s == self).unwrap_or(0);
        Symbols::ALL[(i + 1) % Symbols::ALL.len()]
    }

    /// Cells needed to show `width × height` pixels.
    pub fn cells_for_pixels(self, width: usize, height: usize) -> (usize, usize) {
        (width.div_ceil(self.columns()), height.div_ceil(self.rows()))
    }

    /// The glyph painting the foreground where `mask` has bits (bits past
    /// the set's pixels are ignored).
    pub fn glyph(self, mask: u8) -> char {
        match self {
            Symbols::Half => [' ', '▀', '▄', '█'][mask as usize & 3],
            Symbols::Quad => QUADRANTS[mask as usize & 15],
            Symbols::Sextant => sextant(mask & 63),
            Symbols::Octant => octant(mask),
        }
    }

    /// The mask of `ch` in this set, if the set draws it.
    pub fn mask_of(self, ch: char) -> Option<u8> {
        (0..1u16 << self.pixels())
            .map(|m| m as u8)
            .find(|&m| self.glyph(m) == ch)
    }
}

fn sextant(mask: u8) -> char {
    match mask {
        0 => ' ',
        21 => '▌',
        42 => '▐',
        63 => '█',
        m => {
            // Counting order, minus the masks below it that are elsewhere.
            let skipped = 1 + u32::from(m > 21) + u32::from(m > 42);
            char::from_u32(0x1FB00 + u32::from(m) - skipped).unwrap_or(' ')
        }
    }
}

fn octant(mask: u8) -> char {
    let below = OCTANT_ELSEWHERE.partition_point(|&(m, _)| m < mask);
    match OCTANT_ELSEWHERE.get(below) {
        Some(&(m, ch)) if m == mask => ch,
        _ => char::from_u32(0x1CD00 + u32::from(mask) - below as u32).unwrap_or(' '),
    }
}

/// True for a glyph of any set: one cell wide in every terminal that draws
/// it, so the backend can keep its cursor bookkeeping across it.
pub fn is_block_glyph(ch: char) -> bool {
    matches!(ch as u32, 0x2580..=0x259F | 0x1FB00..=0x1FB3B | 0x1CD00..=0x1CDE5)
        || OCTANT_ELSEWHERE.iter().any(|&(_, c)| c == ch)
}

/// A line showing every glyph of `symbols` between bars, for checking the
/// font: each should fill exactly one cell.
pub fn test_line(symbols: Symbols) -> String {
    let mut line = format!("{:<8}|", symbols.name());
    for mask in 0..1u16 << symbols.pixels() {
        line.push(symbols.glyph(mask as u8));
    }
    line.push('|');
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_set_maps_masks_to_distinct_glyphs() {
        for s in Symbols::ALL {
            let n = 1usize << s.pixels();
            let mut seen: Vec<char> = (0..n).map(|m| s.glyph(m as u8)).collect();
            seen.sort_unstable();
            seen.dedup();
            assert_eq!(seen.len(), n, "{s:?}");
            for m in 0..n {
                assert_eq!(s.mask_of(s.glyph(m as u8)), Some(m as u8));
                assert!(is_block_glyph(s.glyph(m as u8)) || m == 0);
            }
        }
    }

    #[test]
    fn block_ends_land_on_the_last_code_points() {
        assert_eq!(Symbols::Sextant.glyph(1), '\u{1FB00}');
        assert_eq!(Symbols::Sextant.glyph(62), '\u{1FB3B}');
        assert_eq!(Symbols::Octant.glyph(4), '\u{1CD00}');
        assert_eq!(Symbols::Octant.glyph(0xFE), '\u{1CDE5}');
    }
}

//! The xterm 256-colour and 16-colour palettes, and a lookup table that maps
//! any 24-bit colour to its perceptually nearest entry in one memory read.
//!
//! Nearness is measured in OKLab with hue differences weighted up
//! ([`HUE_WEIGHT`]) and chroma lost weighted up ([`CHROMA_LOSS_WEIGHT`]), so a
//! dull red goes to a red cube entry rather than to the grey of the same
//! lightness. The 16 colours also weigh chroma gained up
//! ([`CHROMA_GAIN_WEIGHT_16`]): their nearest chromatic entries are full
//! primaries, and without it a grey or a dark tint takes one. The table has
//! 64 levels per channel, even in lightness rather than in sRGB (2¹⁸ bins,
//! each answered for the bin's centre). Each bin also keeps the second-best
//! entry (so a pixel can avoid the background's entry) and an ordered-dither
//! partner with its share, kept only where mixing the two lowers the error.
//!
//! A bin is answered the first time a colour in it is asked for, and kept:
//! building all 2¹⁸ at once held the first 256-colour frame back by about
//! 0.2 s (0.1 s in 16 colours), where a frame asks for a few thousand.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicU32, Ordering};

use ratatui::style::Color;

use super::oklab::{Lab, lab_from_linear, linear_rgb, to_linear};
use relief_core::framebuffer::Rgb;

/// How much more a difference in hue counts than one in lightness.
pub const HUE_WEIGHT: f32 = 2.0;

/// How much more chroma lost counts than chroma gained or lightness: without
/// it the dull reds of the brick go to the grey of the same lightness (the
/// grey has no hue to differ in). On the reference frame the chromatic
/// pixels shown grey fall from 42 % (plain OKLab, as with the former sRGB
/// distance) to 20 % at 3, while the mean OKLab error stays within 0.5 % of
/// the plain nearest entry's; at 4 they fall to 15 % but the error grows
/// 2 % and more pixels jump to a neighbouring hue (`tests/term/colour.rs`).
pub const CHROMA_LOSS_WEIGHT: f32 = 3.0;

/// With 16 colours, how much more chroma gained counts than lightness: a
/// hue is added only where the colour really has one. The ANSI colours are
/// all saturated, so a light grey sits as near to cyan (same lightness, chroma
/// gained) as to the next grey (lightness off), and plain OKLab or the 256
/// weights show greys 169–190 as cyan. At 3 the reference frames at 160×96
/// fall from mean CIELAB ΔE 64 to 27 on the object (docs/colour.md); 2 leaves
/// 31, 5 gains under 1 more.
pub const CHROMA_GAIN_WEIGHT_16: f32 = 3.0;

/// A pixel that is not the background but whose nearest entry is the
/// background's takes its second-best entry only when that one is at most this
/// many times as far (plain OKLab); otherwise the background's entry is the
/// honest answer. In 256 colours there is always a near second (the greys); in
/// 16 colours the second for a dark tint is a full primary or the middle grey,
/// and forcing it turned every dark pixel of the object bright: (11,3,16)
/// showed as blue (0,0,238).
pub const SUBSTITUTE_RATIO_16: f32 = 1.2;

/// Dither only where the two-entry mix has at most this fraction of the
/// nearest entry's error: a smaller gain is not worth the texture it adds.
pub const DITHER_GAIN: f32 = 0.7;

/// The six channel levels of the xterm colour cube (indices 16..=231).
pub const CUBE_LEVELS: [u8; 6] = [0, 95, 135, 175, 215, 255];

/// Grey `232 + i` of the xterm palette is `8 + 10·i`.
pub fn grey_level(i: usize) -> u8 {
    (8 + 10 * i) as u8
}

/// The 16 ANSI colours with xterm's default RGB values.
pub const ANSI16: [(Rgb, Color); 16] = [
    ([0, 0, 0], Color::Black),
    ([205, 0, 0], Color::Red),
    ([0, 205, 0], Color::Green),
    ([205, 205, 0], Color::Yellow),
    ([0, 0, 238], Color::Blue),
    ([205, 0, 205], Color::Magenta),
    ([0, 205, 205], Color::Cyan),
    ([229, 229, 229], Color::Gray),
    ([127, 127, 127], Color::DarkGray),
    ([255, 0, 0], Color::LightRed),
    ([0, 255, 0], Color::LightGreen),
    ([255, 255, 0], Color::LightYellow),
    ([92, 92, 255], Color::LightBlue),
    ([255, 0, 255], Color::LightMagenta),
    ([0, 255, 255], Color::LightCyan),
    ([255, 255, 255], Color::White),
];

/// One palette entry.
#[derive(Clone, Copy, Debug)]
pub struct Entry {
    /// What the terminal is sent.
    pub color: Color,
    /// What the terminal shows (xterm's default values).
    pub rgb: Rgb,
    lab: Lab,
    chroma: f32,
    linear: [f32; 3],
}

impl Entry {
    fn new(color: Color, rgb: Rgb) -> Entry {
        let linear = linear_rgb(rgb);
        let lab = lab_from_linear(linear);
        Entry {
            color,
            rgb,
            lab,
            chroma: lab.chroma(),
            linear,
        }
    }
}

/// The answer for one table bin; entries are positions in [`Palette::entries`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Pick {
    pub best: u8,
    /// The next best entry (used where `best` is the background's); `best`
    /// itself where the next is too far to stand in for it.
    pub second: u8,
    /// The entry ordered dithering mixes in.
    pub partner: u8,
    /// Pixels in 16 that take the partner; 0: no dithering here.
    pub share: u8,
}

impl Pick {
    /// Marks a packed pick: a bin still 0 has not been answered yet (the
    /// share, at most 16, leaves the top bit free).
    const FILLED: u32 = 1 << 31;

    fn pack(self) -> u32 {
        u32::from_le_bytes([self.best, self.second, self.partner, self.share]) | Self::FILLED
    }

    fn unpack(v: u32) -> Pick {
        let [best, second, partner, share] = (v & !Self::FILLED).to_le_bytes();
        Pick {
            best,
            second,
            partner,
            share,
        }
    }
}

/// A palette with its lookup table.
pub struct Palette {
    pub entries: Vec<Entry>,
    /// Each bin's [`Pick::pack`]ed answer once asked for, 0 until then.
    /// Any thread may answer a bin: the answer is the same whoever computes
    /// it, so a plain store is enough.
    table: Box<[AtomicU32]>,
    channel: &'static Channel,
    candidates: fn(Rgb, &mut Vec<u8>),
    weights: Weights,
}

/// How a palette weighs the parts of the distance that picks entries.
#[derive(Clone, Copy, Debug)]
struct Weights {
    hue: f32,
    chroma_loss: f32,
    chroma_gain: f32,
    /// See [`SUBSTITUTE_RATIO_16`]; infinite: the second is always offered.
    substitute: f32,
}

const BITS: u32 = 6;
const LEVELS: usize = 1 << BITS;

/// Channel value → table level. Levels are even steps of the cube root of
/// linear light (the lightness scale OKLab is built on), so the dark end,
/// where a step of one is visible, gets narrow bins: 0 has a bin of its own,
/// and no bin is wider than 6 values.
struct Channel {
    level: [u8; 256],
    /// Middle of the values each level covers (linear light).
    centre: [f32; LEVELS],
}

fn channel() -> &'static Channel {
    static C: OnceLock<Channel> = OnceLock::new();
    C.get_or_init(|| {
        let mut level = [0u8; 256];
        let (mut lo, mut hi) = ([255usize; LEVELS], [0usize; LEVELS]);
        for (v, slot) in level.iter_mut().enumerate() {
            let l = to_linear(v as f32 / 255.0).cbrt();
            let i = ((l * LEVELS as f32) as usize).min(LEVELS - 1);
            *slot = i as u8;
            lo[i] = lo[i].min(v);
            hi[i] = hi[i].max(v);
        }
        let centre = std::array::from_fn(|i| {
            // Levels no value falls in are never read.
            let mid = if lo[i] <= hi[i] {
                (lo[i] + hi[i]) as f32 / 2.0
            } else {
                0.0
            };
            to_linear(mid / 255.0)
        });
        Channel { level, centre }
    })
}

/// Table bin of a colour.
#[inline]
fn bin(level: &[u8; 256], rgb: Rgb) -> usize {
    ((level[rgb[0] as usize] as usize) << (2 * BITS))
        | ((level[rgb[1] as usize] as usize) << BITS)
        | level[rgb[2] as usize] as usize
}

impl Palette {
    /// The xterm 256-colour palette without the 16 theme colours (their
    /// values differ from terminal to terminal): cube 16..=231, greys 232..=255.
    pub fn xterm256() -> &'static Palette {
        static P: OnceLock<Palette> = OnceLock::new();
        P.get_or_init(Palette::new_xterm256)
    }

    /// A palette as [`Palette::xterm256`], with a table of its own (the
    /// bench measures a first frame with it).
    pub fn new_xterm256() -> Palette {
        let mut entries = Vec::with_capacity(240);
        for (r, &lr) in CUBE_LEVELS.iter().enumerate() {
            for (g, &lg) in CUBE_LEVELS.iter().enumerate() {
                for (b, &lb) in CUBE_LEVELS.iter().enumerate() {
                    let index = 16 + 36 * r + 6 * g + b;
                    let rgb = [lr, lg, lb];
                    entries.push(Entry::new(Color::Indexed(index as u8), rgb));
                }
            }
        }
        for i in 0..24 {
            entries.push(Entry::new(
                Color::Indexed(232 + i as u8),
                [grey_level(i); 3],
            ));
        }
        let weights = Weights {
            hue: HUE_WEIGHT,
            chroma_loss: CHROMA_LOSS_WEIGHT,
            chroma_gain: 1.0,
            substitute: f32::INFINITY,
        };
        Palette::build(entries, candidates_256, weights)
    }

    /// The 16 ANSI colours.
    pub fn ansi16() -> &'static Palette {
        static P: OnceLock<Palette> = OnceLock::new();
        P.get_or_init(Palette::new_ansi16)
    }

    /// A palette as [`Palette::ansi16`], with a table of its own.
    pub fn new_ansi16() -> Palette {
        let entries = ANSI16.iter().map(|&(rgb, c)| Entry::new(c, rgb)).collect();
        let weights = Weights {
            hue: HUE_WEIGHT,
            chroma_loss: CHROMA_LOSS_WEIGHT,
            chroma_gain: CHROMA_GAIN_WEIGHT_16,
            substitute: SUBSTITUTE_RATIO_16,
        };
        Palette::build(entries, |_, out| out.extend(0..16), weights)
    }

    /// The table's answer for `rgb` (its bin answered now if it was not yet).
    #[inline]
    pub fn pick(&self, rgb: Rgb) -> Pick {
        let i = bin(&self.channel.level, rgb);
        match self.table[i].load(Ordering::Relaxed) {
            0 => self.answer(i),
            v => Pick::unpack(v),
        }
    }

    /// Answers bin `i` for its centre and keeps the answer.
    #[cold]
    fn answer(&self, i: usize) -> Pick {
        let mask = LEVELS - 1;
        let levels = [i >> (2 * BITS), (i >> BITS) & mask, i & mask];
        let lin = levels.map(|l| self.channel.centre[l]);
        let srgb = |lin: f32| (super::oklab::from_linear(lin) * 255.0).round() as u8;
        let mut cands = Vec::with_capacity(80);
        (self.candidates)(lin.map(srgb), &mut cands);
        let pick = self.bin_pick(lin, &cands);
        self.table[i].store(pick.pack(), Ordering::Relaxed);
        pick
    }

    /// Position of the entry nearest to `rgb` (the table's answer).
    #[inline]
    pub fn nearest(&self, rgb: Rgb) -> usize {
        self.pick(rgb).best as usize
    }

    /// Position of the entry nearest to the colour `lab` among all entries,
    /// without the table (the reference the table is checked against).
    pub fn nearest_exact(&self, lab: Lab) -> usize {
        let all: Vec<u8> = (0..self.entries.len() as u8).collect();
        self.ranked(lab, &all).0 as usize
    }

    /// Best and second-best of `candidates` for the colour `lab`.
    fn ranked(&self, lab: Lab, candidates: &[u8]) -> (u8, u8) {
        let chroma = lab.chroma();
        let (mut best, mut second) = ((f32::MAX, 0u8), (f32::MAX, 0u8));
        for &i in candidates {
            let e = &self.entries[i as usize];
            let d = weighted2(self.weights, lab, chroma, e);
            if d < best.0 {
                second = best;
                best = (d, i);
            } else if d < second.0 {
                second = (d, i);
            }
        }
        (best.1, second.1)
    }

    /// A palette of `entries` whose table answers each bin the first time
    /// it is asked, among the `candidates` for the bin's centre.
    fn build(entries: Vec<Entry>, candidates: fn(Rgb, &mut Vec<u8>), weights: Weights) -> Palette {
        Palette {
            entries,
            table: (0..LEVELS * LEVELS * LEVELS)
                .map(|_| AtomicU32::new(0))
                .collect(),
            channel: channel(),
            candidates,
            weights,
        }
    }

    /// The pick for the colour with linear RGB `lin`.
    fn bin_pick(&self, lin: [f32; 3], cands: &[u8]) -> Pick {
        let lab = lab_from_linear(lin);
        let (best, second) = self.ranked(lab, cands);
        let p0 = &self.entries[best as usize];
        // No second where it is much further than the best (see
        // SUBSTITUTE_RATIO_16): the quantizer then keeps the best.
        let far = lab.distance(self.entries[second as usize].lab);
        let second = if far > self.weights.substitute * lab.distance(p0.lab) {
            best
        } else {
            second
        };
        // The dither partner sits on the other side of the colour from the
        // best entry: the entry nearest to the colour mirrored through it.
        let mirrored = Lab {
            l: 2.0 * lab.l - p0.lab.l,
            a: 2.0 * lab.a - p0.lab.a,
            b: 2.0 * lab.b - p0.lab.b,
        };
        let mut partner = (f32::MAX, best);
        for &i in cands {
            if i != best {
                let d = mirrored.distance(self.entries[i as usize].lab);
                if d < partner.0 {
                    partner = (d, i);
                }
            }
        }
        let partner = partner.1;
        let mut pick = Pick {
            best,
            second,
            partner,
            share: 0,
        };
        if partner == best {
            return pick;
        }
        // The share of the partner whose mix (in linear light, as the eye
        // averages a fine pattern) comes closest to the colour.
        let p1 = &self.entries[partner as usize];
        let d: [f32; 3] = std::array::from_fn(|k| p1.linear[k] - p0.linear[k]);
        let v: [f32; 3] = std::array::from_fn(|k| lin[k] - p0.linear[k]);
        let dd = d.iter().map(|x| x * x).sum::<f32>();
        if dd <= 0.0 {
            return pick;
        }
        let t = (d.iter().zip(&v).map(|(a, b)| a * b).sum::<f32>() / dd).clamp(0.0, 1.0);
        let share = (t * 16.0).round() as u8;
        if share == 0 || share == 16 {
            return pick;
        }
        let f = share as f32 / 16.0;
        let mix = lab_from_linear(std::array::from_fn(|k| p0.linear[k] + f * d[k]));
        let chroma = lab.chroma();
        let err0 = weighted2(self.weights, lab, chroma, p0);
        let err_mix = weighted2_lab(self.weights, lab, chroma, mix, mix.chroma());
        if err_mix < DITHER_GAIN * DITHER_GAIN * err0 {
            pick.share = share;
        }
        pick
    }
}

/// The distance that picks entries: squared OKLab distance split into
/// lightness, chroma and hue (ΔE² = ΔL² + ΔC² + ΔH², ΔH² = Δa² + Δb² − ΔC²),
/// with hue differences and chroma lost (and, in 16 colours, gained) weighted up.
#[inline]
fn weighted2(w: Weights, lab: Lab, chroma: f32, e: &Entry) -> f32 {
    weighted2_lab(w, lab, chroma, e.lab, e.chroma)
}

#[inline]
fn weighted2_lab(w: Weights, lab: Lab, chroma: f32, other: Lab, other_chroma: f32) -> f32 {
    let dl = lab.l - other.l;
    let (da, db) = (lab.a - other.a, lab.b - other.b);
    let dc = chroma - other_chroma;
    let dh2 = (da * da + db * db - dc * dc).max(0.0);
    let wc = if dc > 0.0 {
        w.chroma_loss
    } else {
        w.chroma_gain
    };
    dl * dl + wc * dc * dc + w.hue * dh2
}

/// Entries of the 256-colour palette worth comparing for `rgb`: the cube
/// levels bracketing each channel and one more on either side (up to 4×4×4
/// cube entries), and the five greys around the colour's mean. The
/// perceptually nearest entry is among them (checked against a search of
/// the whole palette in the tests).
fn candidates_256(rgb: Rgb, out: &mut Vec<u8>) {
    let range = |v: u8| {
        let below = CUBE_LEVELS.iter().rposition(|&l| l <= v).unwrap_or(0);
        below.saturating_sub(1)..=(below + 2).min(5)
    };
    for r in range(rgb[0]) {
        for g in range(rgb[1]) {
            for b in range(rgb[2]) {
                out.push((36 * r + 6 * g + b) as u8);
            }
        }
    }
    let mean = (rgb[0] as usize + rgb[1] as usize + rgb[2] as usize) / 3;
    let grey = (mean.saturating_sub(3) / 10).min(23);
    for i in grey.saturating_sub(2)..=(grey + 2).min(23) {
        out.push((216 + i) as u8);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    impl Palette {
        /// The whole table as it was built at first use before bins were
        /// answered on demand: every bin in order, red slowest.
        fn whole_table(&self) -> Vec<Pick> {
            let ch = channel();
            let srgb = |lin: f32| (super::super::oklab::from_linear(lin) * 255.0).round() as u8;
            let mut table = Vec::with_capacity(LEVELS * LEVELS * LEVELS);
            let mut cands = Vec::with_capacity(256);
            for r in 0..LEVELS {
                for g in 0..LEVELS {
                    for b in 0..LEVELS {
                        let lin = [ch.centre[r], ch.centre[g], ch.centre[b]];
                        cands.clear();
                        (self.candidates)(lin.map(srgb), &mut cands);
                        table.push(self.bin_pick(lin, &cands));
                    }
                }
            }
            table
        }
    }

    /// Every colour of a grid of step 3 (86³) and 200 000 random ones.
    fn many_colours() -> Vec<Rgb> {
        let steps: Vec<u8> = (0..=255).step_by(3).collect();
        let mut out = Vec::new();
        for &r in &steps {
            for &g in &steps {
                for &b in &steps {
                    out.push([r, g, b]);
                }
            }
        }
        let mut s = 0x9e37_79b9u32;
        for _ in 0..200_000 {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            out.push([s as u8, (s >> 8) as u8, (s >> 16) as u8]);
        }
        out
    }

    #[test]
    fn bins_answered_on_demand_equal_the_table_built_whole() {
        let colours = many_colours();
        for new in [Palette::new_xterm256, Palette::new_ansi16] {
            let whole = new().whole_table();
            let level = &channel().level;
            // A new palette asked in two orders from two threads at once,
            // then everything again (answers kept).
            let lazy = new();
            std::thread::scope(|scope| {
                scope.spawn(|| {
                    colours.iter().for_each(|&c| {
                        let _ = lazy.pick(c);
                    })
                });
                scope.spawn(|| {
                    colours.iter().rev().for_each(|&c| {
                        let _ = lazy.pick(c);
                    })
                });
            });
            for &rgb in &colours {
                assert_eq!(lazy.pick(rgb), whole[bin(level, rgb)], "{rgb:?}");
            }
        }
    }

    #[test]
    fn the_table_agrees_with_a_search_of_the_whole_palette() {
        // Bin centres: the table's answer must be the exact nearest entry.
        let p = Palette::xterm256();
        let mut s = 12345u32;
        for _ in 0..4000 {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            let rgb = [s as u8, (s >> 8) as u8, (s >> 16) as u8];
            let ch = channel();
            let centre = rgb.map(|c| ch.centre[ch.level[c as usize] as usize]);
            let got = p.nearest(rgb);
            let want = p.nearest_exact(lab_from_linear(centre));
            assert_eq!(got, want, "{rgb:?}");
        }
    }

    #[test]
    fn dither_partners_only_where_the_mix_is_closer() {
        let p = Palette::xterm256();
        // Black has a bin of its own and is an entry: nothing to mix.
        assert_eq!(p.pick([0, 0, 0]).share, 0);
        // Bins holding an entry mix in at most a trace (their centre is a
        // value or two off the entry).
        assert!(p.pick([95, 135, 175]).share <= 2);
        assert!(p.pick([128, 128, 128]).share <= 2);
        // Halfway between two greys' worth of a dark cube step: mixing helps.
        let between = p.pick([0, 0, 50]);
        assert!(between.share > 0, "{between:?}");
    }
}

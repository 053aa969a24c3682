//! How a level's texels are stored: at the precision their source has
//! (docs/textures.md, "Memory"). Every read gives `f32` RGBA in 0..1 (or
//! −1..1 for normals), so the filters compute as they always have; only
//! what sits in memory between reads is smaller.
//!
//! - `F32`: as computed (textures made in memory, such as the built-in
//!   ones, float pictures, anything a caller edits).
//! - `Rgba8`: an 8-bit picture with alpha; k / 255 is exactly what the
//!   float conversion gives.
//! - `Rgb8`: an 8-bit picture without alpha, whose height is the mean of
//!   R, G and B. That mean (in f64, rounded to f32) is not a function of
//!   the 8-bit sum alone, but it is always the sum's mean `s / 765` (in
//!   f32) or the next float up: the fourth byte holds that 0 or 1, so the
//!   height read back is bit for bit the one computed at load.
//! - `Rgba16`: 16-bit pictures and the mip levels of 8- and 16-bit ones
//!   (a mean of 8-bit values needs more than 8 bits): k / 65535.
//! - `Xyz16`: tangent-space normals and their mip levels, three signed
//!   channels in −1..1 (k / 32767), the fourth channel 0.
//! - `Grey8`: the grey of an 8-bit picture (a specular map): the sum
//!   r + g + b and the grey's offset in floats from `s / 765`, exact as
//!   for `Rgb8`.
//! - `Grey16`: the grey of any other picture, k / 65535.
//! - `Widened`: a compact base level of at most [`WIDE_TEXELS`] texels
//!   with an f32 copy of what it reads as beside it (at most 1 MiB, which
//!   stays in a core's L2 cache). Reads go to the copy: an 8-bit bilinear
//!   read then loads four f32 texels instead of converting four 8-bit ones
//!   (about a tenth of a textured Gouraud frame, docs/bench.md). Everything
//!   that depends on the storage (the mip chain's kind, the specular map's
//!   exact grey, the normal map's precision) sees the compact texels, so
//!   nothing but the time changes; the budget counts the copy.

/// RGBA (or height) in 0..1.
pub type Texel = [f32; 4];

#[derive(Clone, Debug)]
pub enum Texels {
    F32(Vec<[f32; 4]>),
    Rgba8(Vec<[u8; 4]>),
    Rgb8(Vec<[u8; 4]>),
    Rgba16(Vec<[u16; 4]>),
    Xyz16(Vec<[i16; 3]>),
    Grey8(Vec<u16>),
    Grey16(Vec<u16>),
    /// Compact texels (never `F32` or `Widened`) and their f32 reads.
    Widened(Box<Texels>, Vec<[f32; 4]>),
}

/// The most texels a level may have to be [`Texels::Widened`] (the budget
/// counts the copy, so the limit lives there).
use relief_core::budget::WIDE_TEXELS;

/// The bits of `s / 765` as f32, for every sum of three bytes.
static MEAN_OF_SUM: [u32; 766] = {
    let mut table = [0u32; 766];
    let mut s = 0;
    while s < 766 {
        table[s] = (s as f32 / 765.0).to_bits();
        s += 1;
    }
    table
};

/// k / 255 for every byte, divided once here: a read is a table lookup,
/// not a division in the sampling loop.
static UNORM8: [f32; 256] = {
    let mut table = [0.0f32; 256];
    let mut k = 0;
    while k < 256 {
        table[k] = k as f32 / 255.0;
        k += 1;
    }
    table
};

/// An 8-bit channel as the float conversion gives it.
#[inline(always)]
fn unorm8(k: u8) -> f32 {
    UNORM8[k as usize]
}

/// k / 65535 exactly as the f32 division rounds it, by one f64 product:
/// the product is within 2^-52 (relative) of k / 65535, while k / 65535 is
/// at least 2^-41 away from any point where f32 rounding changes (an odd
/// denominator never meets a binary fraction), so rounding the product
/// to f32 gives the division's result (checked for every k in the tests).
#[inline(always)]
fn unorm16(k: u16) -> f32 {
    (k as f64 * (1.0 / 65535.0)) as f32
}

#[inline(always)]
fn snorm16(k: i16) -> f32 {
    k as f32 * (1.0 / 32767.0)
}

/// 0..1 to the nearest 16-bit step (NaN to 0).
#[inline]
pub fn to_unorm16(x: f32) -> u16 {
    if x.is_nan() {
        0
    } else {
        (x.clamp(0.0, 1.0) * 65535.0 + 0.5) as u16
    }
}

/// −1..1 to the nearest signed 16-bit step (NaN to 0).
#[inline]
pub fn to_snorm16(x: f32) -> i16 {
    if x.is_nan() {
        0
    } else {
        let k = x.clamp(-1.0, 1.0) * 32767.0;
        (if k < 0.0 { k - 0.5 } else { k + 0.5 }) as i16
    }
}

/// The height of an 8-bit texel without alpha, exactly as computed from
/// floats: the mean of R, G and B in f64, rounded to f32.
#[inline]
pub fn mean_height8(r: u8, g: u8, b: u8) -> f32 {
    ((unorm8(r) as f64 + unorm8(g) as f64 + unorm8(b) as f64) / 3.0) as f32
}

/// The grey of an 8-bit texel as the specular map computes it in f32.
#[inline]
pub fn grey8(r: u8, g: u8, b: u8) -> f32 {
    (unorm8(r) + unorm8(g) + unorm8(b)) / 3.0
}

/// `value`'s offset in floats (0 ..= 3) from `s / 765` after adding `bias`.
fn offset_from_mean(sum: usize, value: f32, bias: i64) -> u8 {
    let off = value.to_bits() as i64 - MEAN_OF_SUM[sum] as i64 + bias;
    debug_assert!((0..4).contains(&off), "offset {off} at sum {sum}");
    off.clamp(0, 3) as u8
}

/// An 8-bit RGB texel without alpha as stored in `Rgb8`.
#[inline]
pub fn pack_rgb8(r: u8, g: u8, b: u8) -> [u8; 4] {
    let sum = r as usize + g as usize + b as usize;
    [r, g, b, offset_from_mean(sum, mean_height8(r, g, b), 0)]
}

/// An 8-bit texel's grey as stored in `Grey8`.
#[inline]
pub fn pack_grey8(r: u8, g: u8, b: u8) -> u16 {
    let sum = r as usize + g as usize + b as usize;
    (sum as u16) << 2 | offset_from_mean(sum, grey8(r, g, b), 1) as u16
}

/// Read access to one kind of storage; the filters are generic over it so
/// each kind gets its own compiled loop (no branch per texel).
pub trait Fetch: Copy {
    fn at(self, i: usize) -> Texel;
    /// Channel 3 alone.
    #[inline(always)]
    fn height(self, i: usize) -> f32 {
        self.at(i)[3]
    }
    fn len(self) -> usize;
    #[inline(always)]
    fn is_empty(self) -> bool {
        self.len() == 0
    }
    /// [`Fetch::at`] without the bounds check.
    ///
    /// # Safety
    /// `i < self.len()`.
    unsafe fn at_unchecked(self, i: usize) -> Texel;
    /// [`Fetch::height`] without the bounds check.
    ///
    /// # Safety
    /// `i < self.len()`.
    #[inline(always)]
    unsafe fn height_unchecked(self, i: usize) -> f32 {
        // SAFETY: the caller keeps i < len.
        unsafe { self.at_unchecked(i)[3] }
    }
}

#[derive(Clone, Copy)]
pub struct F32s<'a>(pub &'a [[f32; 4]]);
#[derive(Clone, Copy)]
pub struct Rgba8s<'a>(pub &'a [[u8; 4]]);
#[derive(Clone, Copy)]
pub struct Rgb8s<'a>(pub &'a [[u8; 4]]);
#[derive(Clone, Copy)]
pub struct Rgba16s<'a>(pub &'a [[u16; 4]]);
#[derive(Clone, Copy)]
pub struct Xyz16s<'a>(pub &'a [[i16; 3]]);
#[derive(Clone, Copy)]
pub struct Grey8s<'a>(pub &'a [u16]);
#[derive(Clone, Copy)]
pub struct Grey16s<'a>(pub &'a [u16]);
/// Unit normals in f32 read as texels `[x, y, z, 0]`.
#[derive(Clone, Copy)]
pub struct Xyz32s<'a>(pub &'a [[f32; 3]]);

macro_rules! fetch_impl {
    ($view:ident, $t:ident => $conv:expr $(, height $h:ident => $height:expr)?) => {
        impl Fetch for $view<'_> {
            #[inline(always)]
            fn at(self, i: usize) -> Texel {
                let $t = self.0[i];
                $conv
            }
            #[inline(always)]
            fn len(self) -> usize {
                self.0.len()
            }
            #[inline(always)]
            unsafe fn at_unchecked(self, i: usize) -> Texel {
                // SAFETY: the caller keeps i < len.
                let $t = unsafe { *self.0.get_unchecked(i) };
                $conv
            }
            $(
            #[inline(always)]
            fn height(self, i: usize) -> f32 {
                let $h = self.0[i];
                $height
            }
            #[inline(always)]
            unsafe fn height_unchecked(self, i: usize) -> f32 {
                // SAFETY: the caller keeps i < len.
                let $h = unsafe { *self.0.get_unchecked(i) };
                $height
            }
            )?
        }
    };
}

fetch_impl!(F32s, t => t);
// A height is the alpha byte alone, not a whole texel's conversion.
fetch_impl!(Rgba8s, t => unorm8x4(t), height t => unorm8(t[3]));
fetch_impl!(Rgb8s, t => rgb8_texel(t));
fetch_impl!(Rgba16s, t => unorm16x4(t));
fetch_impl!(Xyz16s, t => [snorm16(t[0]), snorm16(t[1]), snorm16(t[2]), 0.0]);
fetch_impl!(Grey8s, t => [grey8_value(t); 4]);
fetch_impl!(Grey16s, t => [unorm16(t); 4]);
fetch_impl!(Xyz32s, t => [t[0], t[1], t[2], 0.0]);

/// Four 8-bit channels as floats, k / 255 each (see [`unorm8`]).
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn unorm8x4(t: [u8; 4]) -> Texel {
    t.map(unorm8)
}

/// Four 8-bit channels as floats, k / 255 each, four at a time: with
/// x = k / 256 (exact), x + x·fl(1/255) is within 2^-9 of an ulp of k / 255,
/// whose binary digits repeat k's eight bits, so they never come that close
/// to a rounding midpoint (the ninth digit past any point equals the first):
/// the sum rounds to the division's result, as the test over every byte
/// checks, without a division or four table reads.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn unorm8x4(t: [u8; 4]) -> Texel {
    use std::arch::x86_64::{
        __m128, _mm_add_ps, _mm_cvtepi32_ps, _mm_cvtsi32_si128, _mm_mul_ps, _mm_set1_ps,
        _mm_setzero_si128, _mm_unpacklo_epi8, _mm_unpacklo_epi16,
    };
    // SAFETY: SSE2, the only extension used, is part of every x86_64 CPU.
    unsafe {
        let zero = _mm_setzero_si128();
        let bytes = _mm_cvtsi32_si128(i32::from_le_bytes(t));
        let ints = _mm_unpacklo_epi16(_mm_unpacklo_epi8(bytes, zero), zero);
        let x = _mm_mul_ps(_mm_cvtepi32_ps(ints), _mm_set1_ps(1.0 / 256.0));
        let q = _mm_add_ps(x, _mm_mul_ps(x, _mm_set1_ps(1.0 / 255.0)));
        std::mem::transmute::<__m128, [f32; 4]>(q)
    }
}

/// Four 16-bit channels as floats, k / 65535 each (see [`unorm16`]).
#[inline(always)]
fn unorm16x4(t: [u16; 4]) -> Texel {
    t.map(unorm16)
}

#[inline(always)]
fn rgb8_texel(t: [u8; 4]) -> Texel {
    let sum = t[0] as usize + t[1] as usize + t[2] as usize;
    let h = f32::from_bits(MEAN_OF_SUM[sum.min(765)] + t[3] as u32);
    let [r, g, b, _] = unorm8x4(t);
    [r, g, b, h]
}

#[inline(always)]
fn grey8_value(code: u16) -> f32 {
    let sum = (code >> 2) as usize;
    f32::from_bits((MEAN_OF_SUM[sum.min(765)] + (code & 3) as u32).wrapping_sub(1))
}

/// Runs `$body` with `$f` bound to the [`Fetch`] view of `$texels`, one
/// compiled copy per storage kind.
#[macro_export]
macro_rules! with_fetch {
    ($texels:expr, $f:ident => $body:expr) => {
        match $texels {
            $crate::sample::texels::Texels::F32(v)
            | $crate::sample::texels::Texels::Widened(_, v) => {
                let $f = $crate::sample::texels::F32s(&v[..]);
                $body
            }
            $crate::sample::texels::Texels::Rgba8(v) => {
                let $f = $crate::sample::texels::Rgba8s(&v[..]);
                $body
            }
            $crate::sample::texels::Texels::Rgb8(v) => {
                let $f = $crate::sample::texels::Rgb8s(&v[..]);
                $body
            }
            $crate::sample::texels::Texels::Rgba16(v) => {
                let $f = $crate::sample::texels::Rgba16s(&v[..]);
                $body
            }
            $crate::sample::texels::Texels::Xyz16(v) => {
                let $f = $crate::sample::texels::Xyz16s(&v[..]);
                $body
            }
            $crate::sample::texels::Texels::Grey8(v) => {
                let $f = $crate::sample::texels::Grey8s(&v[..]);
                $body
            }
            $crate::sample::texels::Texels::Grey16(v) => {
                let $f = $crate::sample::texels::Grey16s(&v[..]);
                $body
            }
        }
    };
}

/// The storage a level's mip chain uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MipKind {
    F32,
    Rgba16,
    Xyz16,
}

/// Texels pushed one at a time into a chosen kind of storage.
pub(crate) enum Builder {
    F32(Vec<[f32; 4]>),
    Rgba16(Vec<[u16; 4]>),
    Xyz16(Vec<[i16; 3]>),
}

impl Builder {
    pub(crate) fn new(kind: MipKind, capacity: usize) -> Builder {
        match kind {
            MipKind::F32 => Builder::F32(Vec::with_capacity(capacity)),
            MipKind::Rgba16 => Builder::Rgba16(Vec::with_capacity(capacity)),
            MipKind::Xyz16 => Builder::Xyz16(Vec::with_capacity(capacity)),
        }
    }

    #[inline]
    pub(crate) fn push(&mut self, t: Texel) {
        match self {
            Builder::F32(v) => v.push(t),
            Builder::Rgba16(v) => v.push(t.map(to_unorm16)),
            Builder::Xyz16(v) => v.push([to_snorm16(t[0]), to_snorm16(t[1]), to_snorm16(t[2])]),
        }
    }

    pub(crate) fn finish(self) -> Texels {
        match self {
            Builder::F32(v) => Texels::F32(v),
            Builder::Rgba16(v) => Texels::Rgba16(v),
            Builder::Xyz16(v) => Texels::Xyz16(v),
        }
    }
}

impl Texels {
    /// Number of texels.
    pub fn len(&self) -> usize {
        with_fetch!(self, f => f.len())
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Texel `i` (storage order) as floats.
    #[inline]
    pub fn at(&self, i: usize) -> Texel {
        with_fetch!(self, f => f.at(i))
    }

    pub fn first(&self) -> Option<Texel> {
        (!self.is_empty()).then(|| self.at(0))
    }

    /// Every texel as floats, in storage order.
    pub fn iter(&self) -> impl Iterator<Item = Texel> + '_ {
        (0..self.len()).map(move |i| self.at(i))
    }

    /// True when the texels are kept as f32.
    pub fn is_f32(&self) -> bool {
        matches!(self, Texels::F32(_))
    }

    /// Compact texels of at most [`WIDE_TEXELS`] with their f32 copy
    /// beside them; anything else as it is.
    pub fn widened_if_small(self) -> Texels {
        if self.is_f32() || self.len() > WIDE_TEXELS || matches!(self, Texels::Widened(..)) {
            return self;
        }
        let wide = self.iter().collect();
        Texels::Widened(Box::new(self), wide)
    }

    /// These texels with every height 0, kept at their precision: an 8-bit
    /// picture without alpha (height from its colours) becomes RGBA with
    /// alpha 0, its colours read as before.
    pub fn without_height(self) -> Texels {
        match self {
            Texels::F32(mut v) => {
                v.iter_mut().for_each(|t| t[3] = 0.0);
                Texels::F32(v)
            }
            Texels::Rgba8(mut v) | Texels::Rgb8(mut v) => {
                v.iter_mut().for_each(|t| t[3] = 0);
                Texels::Rgba8(v)
            }
            Texels::Rgba16(mut v) => {
                v.iter_mut().for_each(|t| t[3] = 0);
                Texels::Rgba16(v)
            }
            Texels::Widened(compact, _) => compact.without_height().widened_if_small(),
            other => Texels::F32(other.iter().map(|[r, g, b, _]| [r, g, b, 0.0]).collect()),
        }
    }

    /// Each texel's fourth channel (an RGBA picture's alpha) in all four,
    /// kept at its precision: every read gives what `at(i)[3]` gives.
    pub fn fourth_everywhere(&self) -> Texels {
        match self.compact() {
            Texels::Rgba8(v) => Texels::Rgba8(v.iter().map(|t| [t[3]; 4]).collect()),
            Texels::Rgba16(v) => Texels::Rgba16(v.iter().map(|t| [t[3]; 4]).collect()),
            other => Texels::F32(other.iter().map(|t| [t[3]; 4]).collect()),
        }
        .widened_if_small()
    }

    /// Each texel's first channel (a picture's red) alone, in 16 bits: an
    /// 8-bit red k is kept as 257·k, which reads back as k / 255 exactly.
    pub fn first_channel_grey(&self) -> Texels {
        self.channel_grey(0)
    }

    /// Each texel's channel `k` (0 red … 3 alpha) alone, in 16 bits (read
    /// back in all four channels): an 8-bit k as 257·k, which
    /// reads back as k / 255 exactly; f32 texels stay f32. An 8-bit picture
    /// without alpha (`Rgb8`, whose fourth byte is not alpha) reads 1 as
    /// its alpha, as an opaque picture's.
    pub fn channel_grey(&self, k: usize) -> Texels {
        match self.compact() {
            Texels::Rgb8(_) if k == 3 => Texels::Grey16(vec![u16::MAX; self.len()]),
            Texels::Rgba8(v) | Texels::Rgb8(v) => {
                Texels::Grey16(v.iter().map(|t| u16::from(t[k]) * 257).collect())
            }
            Texels::Rgba16(v) => Texels::Grey16(v.iter().map(|t| t[k]).collect()),
            other => Texels::F32(other.iter().map(|t| [t[k]; 4]).collect()),
        }
        .widened_if_small()
    }

    /// Bytes [`Texels::channel_grey`] of these texels takes (its f32 copy
    /// when small included), known before it is made.
    pub fn channel_grey_bytes(&self) -> u64 {
        let n = self.len() as u64;
        match self.compact() {
            Texels::Rgba8(_) | Texels::Rgb8(_) | Texels::Rgba16(_) => {
                let copy = if self.len() <= WIDE_TEXELS { 16 } else { 0 };
                n * (2 + copy)
            }
            _ => n * 16,
        }
    }

    /// The storage that decides what the texels are: the compact texels of
    /// a widened level, else these.
    pub fn compact(&self) -> &Texels {
        match self {
            Texels::Widened(compact, _) => compact,
            other => other,
        }
    }

    /// Bytes one texel takes in this storage (a widened level's copy
    /// included).
    pub fn bytes_per_texel(&self) -> usize {
        match self {
            Texels::Widened(compact, _) => compact.bytes_per_texel() + 16,
            Texels::F32(_) => 16,
            Texels::Rgba8(_) | Texels::Rgb8(_) => 4,
            Texels::Rgba16(_) => 8,
            Texels::Xyz16(_) => 6,
            Texels::Grey8(_) | Texels::Grey16(_) => 2,
        }
    }

    /// The storage this level's mip levels use: f32 stays f32 (pictures of
    /// procedural textures unchanged), normals stay signed, the rest 16-bit.
    pub fn mip_kind(&self) -> MipKind {
        match self {
            Texels::Widened(compact, _) => compact.mip_kind(),
            Texels::F32(_) => MipKind::F32,
            Texels::Xyz16(_) => MipKind::Xyz16,
            _ => MipKind::Rgba16,
        }
    }

    /// The texels as f32 for editing, converting the storage first if it
    /// is compact (it then takes 16 bytes a texel).
    pub fn as_mut_slice(&mut self) -> &mut [[f32; 4]] {
        if !self.is_f32() {
            *self = Texels::F32(self.iter().collect());
        }
        match self {
            Texels::F32(v) => v,
            _ => unreachable!("converted to f32 just above"),
        }
    }

    /// [`Texels::as_mut_slice`]'s texels, one at a time.
    pub fn iter_mut(&mut self) -> std::slice::IterMut<'_, [f32; 4]> {
        self.as_mut_slice().iter_mut()
    }
}

impl From<Vec<[f32; 4]>> for Texels {
    fn from(v: Vec<[f32; 4]>) -> Self {
        Texels::F32(v)
    }
}

impl FromIterator<[f32; 4]> for Texels {
    fn from_iter<I: IntoIterator<Item = [f32; 4]>>(iter: I) -> Self {
        Texels::F32(iter.into_iter().collect())
    }
}

impl<'a> IntoIterator for &'a mut Texels {
    type Item = &'a mut [f32; 4];
    type IntoIter = std::slice::IterMut<'a, [f32; 4]>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter_mut()
    }
}

impl<'a> IntoIterator for &'a Texels {
    type Item = Texel;
    type IntoIter = Box<dyn Iterator<Item = Texel> + 'a>;
    fn into_iter(self) -> Self::IntoIter {
        Box::new(self.iter())
    }
}

/// Equal when every texel reads the same, whatever the storage (a picture
/// decoded from an 8-bit PNG equals the f32 texels of the same values).
impl PartialEq for Texels {
    fn eq(&self, other: &Texels) -> bool {
        self.len() == other.len() && self.iter().zip(other.iter()).all(|(a, b)| a == b)
    }
}

/// Equal when every texel reads the same (whatever the storage).
impl PartialEq<Vec<[f32; 4]>> for Texels {
    fn eq(&self, other: &Vec<[f32; 4]>) -> bool {
        self.len() == other.len() && self.iter().zip(other).all(|(a, b)| a == *b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgb8_height_and_grey8_are_bit_exact_for_every_colour() {
        for r in 0..=255u8 {
            for g in 0..=255u8 {
                for b in 0..=255u8 {
                    let t = rgb8_texel(pack_rgb8(r, g, b));
                    assert_eq!(t[3].to_bits(), mean_height8(r, g, b).to_bits());
                    assert_eq!(t[0], r as f32 / 255.0);
                    assert_eq!(unorm8x4([r, g, b, 0]), [r, g, b, 0].map(unorm8));
                    let grey = grey8_value(pack_grey8(r, g, b));
                    assert_eq!(grey.to_bits(), grey8(r, g, b).to_bits(), "{r} {g} {b}");
                }
            }
        }
    }

    #[test]
    fn eight_bit_channels_read_as_their_division_by_255() {
        for k in 0..=255u8 {
            let t = unorm8x4([k, 255 - k, k / 3, k.wrapping_mul(7)]);
            let want = [k, 255 - k, k / 3, k.wrapping_mul(7)].map(|c| c as f32 / 255.0);
            assert_eq!(t.map(f32::to_bits), want.map(f32::to_bits), "byte {k}");
        }
    }

    #[test]
    fn maps_kept_compact_read_as_the_picture_did() {
        let picture: Vec<[u8; 4]> = (0..=255u8).map(|k| [k, 255 - k, k / 3, k ^ 0x5a]).collect();
        let rgba = Texels::Rgba8(picture.clone());
        // The red channel alone in 16 bits: the same floats, bit for bit.
        let red = rgba.first_channel_grey();
        // The alpha in every channel, and the colours with no height.
        let alpha = rgba.fourth_everywhere();
        let flat = Texels::Rgb8(
            picture
                .iter()
                .map(|t| pack_rgb8(t[0], t[1], t[2]))
                .collect(),
        )
        .without_height();
        for (i, t) in picture.iter().enumerate() {
            let want = t.map(|c| c as f32 / 255.0);
            assert_eq!(red.at(i)[0].to_bits(), want[0].to_bits(), "red {t:?}");
            assert_eq!(alpha.at(i), [want[3]; 4], "alpha {t:?}");
            assert_eq!(flat.at(i), [want[0], want[1], want[2], 0.0], "flat {t:?}");
        }
        assert!(matches!(red.compact(), Texels::Grey16(_)));
        assert!(matches!(flat.compact(), Texels::Rgba8(_)));
    }

    #[test]
    fn sixteen_bit_steps_round_trip() {
        for k in 0..=u16::MAX {
            assert_eq!(to_unorm16(unorm16(k)), k);
            assert_eq!(unorm16x4([k; 4])[0], k as f32 / 65535.0);
        }
        for k in [-32767i16, -1, 0, 1, 12345, 32767] {
            assert_eq!(to_snorm16(snorm16(k)), k);
        }
        assert_eq!(to_unorm16(f32::NAN), 0);
        assert_eq!(to_snorm16(-2.0), -32767);
    }

    #[test]
    fn a_widened_level_reads_as_its_compact_texels() {
        let bytes: Vec<[u8; 4]> = (0..=255u8).map(|k| [k, 255 - k, k / 3, k ^ 0x5a]).collect();
        let rgb: Vec<[u8; 4]> = bytes.iter().map(|t| pack_rgb8(t[0], t[1], t[2])).collect();
        for compact in [Texels::Rgba8(bytes), Texels::Rgb8(rgb)] {
            let wide = compact.clone().widened_if_small();
            assert!(matches!(wide, Texels::Widened(..)) && !wide.is_f32());
            for i in 0..compact.len() {
                let (a, b) = (compact.at(i), wide.at(i));
                assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "texel {i}");
            }
            assert_eq!(wide.bytes_per_texel(), 4 + 16);
            assert_eq!(wide.mip_kind(), MipKind::Rgba16);
            assert!(matches!(wide.compact(), Texels::Rgba8(_) | Texels::Rgb8(_)));
        }
        // Past the limit, and f32 texels, stay as they are.
        let large = Texels::Rgba8(vec![[1, 2, 3, 4]; WIDE_TEXELS + 1]).widened_if_small();
        assert!(matches!(large, Texels::Rgba8(_)));
        assert!(Texels::F32(vec![[0.5; 4]]).widened_if_small().is_f32());
    }

    #[test]
    fn editing_converts_to_f32_and_keeps_the_values() {
        let mut t = Texels::Rgba8(vec![[255, 0, 51, 102]]);
        let before = t.at(0);
        t.as_mut_slice()[0][3] = 0.5;
        assert!(t.is_f32());
        assert_eq!(t.at(0), [before[0], before[1], before[2], 0.5]);
    }
}

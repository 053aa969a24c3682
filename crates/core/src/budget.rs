//! One memory budget for everything relief derives from its inputs: decoded
//! pictures with their mip chains and normal maps, resized height maps,
//! frame buffers and the text of `render --ansi`.
//!
//! Each of them reserves its worst case here *before* allocating; a
//! reservation that would take the total past [`BUDGET_BYTES`] is refused
//! with an error naming the limit, so a tiny file that asks for gigabytes
//! costs nothing. A reservation is given back when the value that holds it
//! is dropped. The estimates are upper bounds of what the code allocates (a
//! test measures the peak resident memory of the worst cases against them).

use std::sync::atomic::{AtomicU64, Ordering};

/// The budget: relief's resident memory stays below this, whatever it reads.
pub const BUDGET_BYTES: u64 = 1 << 30;

/// The program itself (code, thread stacks, built-in textures, the
/// terminal's cell buffers), counted as reserved from the start.
pub const BASELINE_BYTES: u64 = 48 << 20;

/// Largest view the interactive mode draws, in terminal cells: a larger
/// terminal shows the picture in its top-left corner (the cell buffers of
/// a 65535×65535 terminal alone would be hundreds of gigabytes).
pub const MAX_VIEW_COLUMNS: u16 = 1024;
pub const MAX_VIEW_ROWS: u16 = 512;

/// Bytes per texel of a texture kept in f32 (float pictures, textures
/// built or edited in memory) at its worst: the base level (RGBA `f32`,
/// 16), its mip chain (16/3), the dot3 normal map (12) and its chain
/// (16/3, built straight from the normals). The decoder's own buffers (at
/// most 16 + 16 per texel, for float pictures) are freed before the mip
/// chains exist, and fit within this.
pub const TEXTURE_BYTES_PER_TEXEL: f64 = 16.0 + 16.0 / 3.0 + 12.0 + 16.0 / 3.0;

/// The precision a picture's texels are kept at (`texture::texels`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    /// 8 bits a channel: base 4 bytes, mip chain in 16 bits (8/3), normal
    /// map in three signed 16-bit channels (6) and its chain (6/3). The
    /// decoder's picture (≤ 4) and its RGBA copy (4) come and go before.
    Unorm8,
    /// 16 bits a channel: base 8, the rest as for 8 bits; the decoder's
    /// picture and its RGBA copy (≤ 8 + 8) are freed before the chains exist.
    Unorm16,
    /// f32: [`TEXTURE_BYTES_PER_TEXEL`].
    Float,
}

impl Precision {
    /// Worst-case bytes per texel of a texture at this precision.
    pub fn bytes_per_texel(self) -> f64 {
        const DERIVED: f64 = 8.0 / 3.0 + 6.0 + 6.0 / 3.0;
        match self {
            Precision::Unorm8 => (4.0 + DERIVED).max(4.0 + 4.0),
            Precision::Unorm16 => (8.0 + DERIVED).max(8.0 + 8.0),
            Precision::Float => TEXTURE_BYTES_PER_TEXEL,
        }
    }
}

/// Bytes per frame pixel: the colour (3), a depth value (4) and the PNG's
/// copy of the colour (3). Supersampling and MSAA add their own samples
/// (see [`frame_bytes_for`]).
pub const FRAME_BYTES_PER_PIXEL: u64 = 3 + 4 + 3;

/// Bytes per sample of a supersampled or multisampled buffer: colour and depth.
pub const SAMPLE_BYTES: u64 = 3 + 4;

static RESERVED: AtomicU64 = AtomicU64::new(BASELINE_BYTES);
/// The most ever reserved at once since [`reset_peak`] (tests and benchmarks
/// compare it with what was allocated).
static PEAK: AtomicU64 = AtomicU64::new(BASELINE_BYTES);

/// A reservation that did not fit.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "{what} would need {need} MiB, beyond relief's memory budget of {budget} MiB ({used} MiB already in use)",
    need = mib(*.need),
    budget = mib(BUDGET_BYTES),
    used = mib(*.used)
)]
pub struct BudgetError {
    /// What asked (already safe to print).
    pub what: String,
    pub need: u64,
    pub used: u64,
}

fn mib(bytes: u64) -> u64 {
    bytes.div_ceil(1 << 20)
}

/// Bytes held against the budget until dropped.
#[derive(Debug)]
pub struct Reservation {
    bytes: u64,
}

impl Reservation {
    pub fn bytes(&self) -> u64 {
        self.bytes
    }

    /// Holds `more` bytes for `what` as well (a computation whose needs are
    /// known step by step reserves each step before allocating it).
    pub fn grow(&mut self, what: &str, more: u64) -> Result<(), BudgetError> {
        let extra = reserve(what, more)?;
        self.bytes += extra.bytes;
        std::mem::forget(extra);
        Ok(())
    }

    /// Gives back `bytes` (at most what is held) once they are freed.
    pub fn shrink(&mut self, bytes: u64) {
        let bytes = bytes.min(self.bytes);
        self.bytes -= bytes;
        RESERVED.fetch_sub(bytes, Ordering::SeqCst);
    }
}

impl Drop for Reservation {
    fn drop(&mut self) {
        RESERVED.fetch_sub(self.bytes, Ordering::SeqCst);
    }
}

/// Reserves `bytes` for `what`, or says why not.
pub fn reserve(what: &str, bytes: u64) -> Result<Reservation, BudgetError> {
    let mut used = RESERVED.load(Ordering::SeqCst);
    loop {
        let total = used.saturating_add(bytes);
        if total > BUDGET_BYTES {
            return Err(BudgetError {
                what: what.to_string(),
                need: bytes,
                used,
            });
        }
        match RESERVED.compare_exchange(used, total, Ordering::SeqCst, Ordering::SeqCst) {
            Ok(_) => {
                PEAK.fetch_max(total, Ordering::SeqCst);
                return Ok(Reservation { bytes });
            }
            Err(now) => used = now,
        }
    }
}

/// Bytes reserved now (the baseline included).
pub fn in_use() -> u64 {
    RESERVED.load(Ordering::SeqCst)
}

/// The most reserved at once (the baseline included) since [`reset_peak`].
pub fn peak() -> u64 {
    PEAK.load(Ordering::SeqCst)
}

/// Starts [`peak`] again from what is reserved now.
pub fn reset_peak() {
    PEAK.store(in_use(), Ordering::SeqCst);
}

/// Worst case of a `width × height` texture kept in f32 (see
/// [`TEXTURE_BYTES_PER_TEXEL`]).
pub fn texture_bytes(width: u64, height: u64) -> u64 {
    texture_bytes_at(width, height, Precision::Float)
}

/// The most texels a compact (8- or 16-bit) base level may have to keep an
/// f32 copy of its reads beside it (`texture::texels`, `Widened`): 64 K,
/// a copy of 1 MiB (a 256×256 picture such as the reference brick).
pub const WIDE_TEXELS: usize = 1 << 16;

/// Worst case of a `width × height` texture kept at `precision`, with the
/// f32 copy a compact base level of at most [`WIDE_TEXELS`] texels keeps
/// beside it (16 bytes a texel).
pub fn texture_bytes_at(width: u64, height: u64, precision: Precision) -> u64 {
    let texels = width.saturating_mul(height);
    let copy = if precision != Precision::Float && texels <= WIDE_TEXELS as u64 {
        16.0
    } else {
        0.0
    };
    (texels as f64 * (precision.bytes_per_texel() + copy))
        .ceil()
        .min(u64::MAX as f64) as u64
}

/// A height map of `from` texels resized to `to`: its heights (4 bytes
/// each), the one-axis intermediate (at most the larger of the two grids)
/// and the result.
pub fn resize_bytes(from: (u64, u64), to: (u64, u64)) -> u64 {
    let a = from.0.saturating_mul(from.1);
    let b = to.0.saturating_mul(to.1);
    a.saturating_add(a.max(b))
        .saturating_add(b)
        .saturating_mul(4)
}

/// The shadow scene's depth and owner maps at their largest (2048², 4 + 4 bytes).
pub const SHADOW_MAP_BYTES: u64 = 2048 * 2048 * 8;

/// A frame of `width × height` pixels with a supersampled buffer of at
/// most `supersamples` samples ([`SAMPLE_BYTES`] each) and a shadow map.
pub fn frame_bytes(width: u64, height: u64, supersamples: u64) -> u64 {
    width
        .saturating_mul(height)
        .saturating_mul(FRAME_BYTES_PER_PIXEL)
        .saturating_add(supersamples.saturating_mul(SAMPLE_BYTES))
        .saturating_add(SHADOW_MAP_BYTES)
}

/// [`frame_bytes`] for a frame rendered with `aa`.
pub fn frame_bytes_for(width: usize, height: usize, aa: crate::settings::AntiAlias) -> u64 {
    let k = crate::settings::ssaa_factor(aa, width, height) as u64;
    let (w, h) = (width as u64, height as u64);
    let samples = if k > 1 {
        w.saturating_mul(h).saturating_mul(k * k)
    } else if aa == crate::settings::AntiAlias::Msaa4 {
        w.saturating_mul(h).saturating_mul(4)
    } else {
        0
    };
    frame_bytes(w, h, samples)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reservations_add_up_and_are_given_back() {
        let before = in_use();
        let a = reserve("a", 10 << 20).unwrap();
        assert!(in_use() >= before + (10 << 20));
        let err = reserve("a huge picture", BUDGET_BYTES).unwrap_err();
        assert!(
            err.to_string().starts_with(
                "a huge picture would need 1024 MiB, beyond relief's memory budget of 1024 MiB"
            ),
            "{err}"
        );
        drop(a);
        assert!(reserve("u64::MAX", u64::MAX).is_err());
        let mut grown = reserve("b", 1 << 20).unwrap();
        grown.grow("b", 2 << 20).unwrap();
        assert_eq!(grown.bytes(), 3 << 20);
        assert!(peak() >= BASELINE_BYTES + (3 << 20));
        grown.shrink(1 << 20);
        assert_eq!(grown.bytes(), 2 << 20);
        assert!(grown.grow("b", BUDGET_BYTES).is_err());
        assert_eq!(grown.bytes(), 2 << 20);
    }

    #[test]
    fn estimates_saturate_instead_of_wrapping() {
        assert_eq!(frame_bytes(u64::MAX, 2, 0), u64::MAX);
        assert!(texture_bytes(u64::MAX, u64::MAX) > BUDGET_BYTES);
        assert_eq!(resize_bytes((1, 16384), (16384, 1)), 4 * 3 * 16384);
    }
}

//! The filters applied after the vertex codec (Appendix B of the
//! specifications), each element rewritten in place: `OCTAHEDRAL` unit
//! vectors, `QUATERNION` rotations, `EXPONENTIAL` floats and `COLOR`
//! (YCoCg, `KHR_meshopt_compression` only). The formulas are the
//! specification's, in the same order of f32 operations.

use super::error::DecodeError;

/// Unit vectors: x and y in octahedral form over a K-bit 1.0 stored as the
/// third component; the fourth passes through. Stride 4 (8-bit
/// components) or 8 (16-bit).
pub(super) fn octahedral(data: &mut [u8], stride: usize) -> Result<(), DecodeError> {
    let bytes = lane_bytes(stride, &[4, 8], "the octahedral filter")?;
    let max = signed_max(bytes);
    for_each_element(data, bytes, |v| {
        let v = v.map(|c| signed(c, bytes));
        let one = v[2] as f32;
        let (mut x, mut y) = (v[0] as f32 / one, v[1] as f32 / one);
        let z = 1.0 - x.abs() - y.abs();
        // The negative hemisphere is folded over the diagonals.
        let t = z.min(0.0);
        x -= t.copysign(x);
        y -= t.copysign(y);
        let length = (x * x + y * y + z * z).sqrt();
        let scaled = |c: f32| ((c / length) * max).round() as i32;
        [scaled(x), scaled(y), scaled(z), v[3]]
    });
    Ok(())
}

/// Unit quaternions as their three smaller components over a K-bit 1.0
/// whose low two bits name the largest one (left out, always positive).
/// Stride 8, 16-bit components.
pub(super) fn quaternion(data: &mut [u8], stride: usize) -> Result<(), DecodeError> {
    let bytes = lane_bytes(stride, &[8], "the quaternion filter")?;
    for_each_element(data, bytes, |v| {
        let v = v.map(|c| signed(c, bytes));
        let one = (v[3] | 3) as f32;
        // The three stored components are at most 1/√2 and kept scaled by √2.
        let range = 1.0 / 2f32.sqrt();
        let [x, y, z] = [v[0], v[1], v[2]].map(|c| c as f32 / one * range);
        let w = (1.0 - x * x - y * y - z * z).max(0.0).sqrt();
        let largest = (v[3] & 3) as usize;
        let mut out = [0; 4];
        for (k, c) in [w, x, y, z].into_iter().enumerate() {
            out[(largest + k) % 4] = (c * 32767.0).round() as i32;
        }
        out
    });
    Ok(())
}

/// Floats as 2^e × m: an 8-bit signed exponent above a 24-bit signed
/// mantissa, decoded exactly. Any stride of whole 32-bit words.
pub(super) fn exponential(data: &mut [u8], stride: usize) -> Result<(), DecodeError> {
    if stride == 0 || !stride.is_multiple_of(4) {
        return Err(DecodeError::Stride {
            stride,
            what: "the exponential filter",
        });
    }
    for word in data.chunks_exact_mut(4) {
        let v = i32::from_le_bytes([word[0], word[1], word[2], word[3]]);
        let (exponent, mantissa) = (v >> 24, (v << 8) >> 8);
        let value = mantissa as f32 * power_of_two(exponent);
        word.copy_from_slice(&value.to_le_bytes());
    }
    Ok(())
}

/// 2^e for e in −128..=127, built from its bits (exact, unlike a `powi`
/// whose rounding is not promised): normal down to 2^−126, subnormal below.
fn power_of_two(e: i32) -> f32 {
    match e {
        -126.. => f32::from_bits(((e + 127) as u32) << 23),
        _ => f32::from_bits(1 << (e + 149)),
    }
}

/// Colours as Y, Co, Cg and an alpha of K−1 bits under a set bit K−1 that
/// tells K. Stride 4 (8-bit components) or 8 (16-bit).
pub(super) fn color(data: &mut [u8], stride: usize) -> Result<(), DecodeError> {
    let bytes = lane_bytes(stride, &[4, 8], "the color filter")?;
    let max = (1u32 << (8 * bytes)) - 1;
    for_each_element(data, bytes, |v| {
        // K from the alpha's highest set bit: its scale is 2^K − 1.
        let scale = (1i32 << (32 - v[3].leading_zeros())) - 1;
        let (y, co, cg) = (v[0] as i32, signed(v[1], bytes), signed(v[2], bytes));
        let (r, g, b) = (y + co - cg, y + cg, y - co - cg);
        // The alpha gains a bit, a copy of its lowest, to match the others.
        let a = v[3] as i32 & (scale >> 1);
        let a = (a << 1) | (a & 1);
        let factor = max as f32 / scale as f32;
        [r, g, b, a].map(|c| ((c as f32 * factor).round() as i32).clamp(0, max as i32))
    });
    Ok(())
}

/// The bytes of one of an element's four components, for a stride the
/// filter allows.
fn lane_bytes(stride: usize, allowed: &[usize], what: &'static str) -> Result<usize, DecodeError> {
    match allowed.contains(&stride) {
        true => Ok(stride / 4),
        false => Err(DecodeError::Stride { stride, what }),
    }
}

/// The largest signed value of `bytes` bytes: 127 or 32767.
fn signed_max(bytes: usize) -> f32 {
    ((1u32 << (8 * bytes - 1)) - 1) as f32
}

/// A component's bits read as signed.
fn signed(raw: u32, bytes: usize) -> i32 {
    match bytes {
        1 => i32::from(raw as u8 as i8),
        _ => i32::from(raw as u16 as i16),
    }
}

/// Rewrites each element of four components of `bytes` bytes
/// (little-endian, read unsigned, written back truncated).
fn for_each_element(data: &mut [u8], bytes: usize, f: impl Fn([u32; 4]) -> [i32; 4]) {
    for element in data.chunks_exact_mut(4 * bytes) {
        let read = |k: usize| match bytes {
            1 => u32::from(element[k]),
            _ => u32::from(u16::from_le_bytes([element[2 * k], element[2 * k + 1]])),
        };
        let out = f([read(0), read(1), read(2), read(3)]);
        for (k, value) in out.into_iter().enumerate() {
            match bytes {
                1 => element[k] = value as u8,
                _ => element[2 * k..2 * k + 2].copy_from_slice(&(value as u16).to_le_bytes()),
            }
        }
    }
}

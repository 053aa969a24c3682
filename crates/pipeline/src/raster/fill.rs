//! Filling a run of pixels (or samples) with one value.

/// `slice.fill(value)` by doubling copies: a 3-byte pixel filled one at a
/// time costs more than its pixels' shading on a small frame (a band's
/// clear, a flat span), a copy of a few hundred bytes at once does not.
pub fn fill<T: Copy>(slice: &mut [T], value: T) {
    let seed = slice.len().min(64);
    slice[..seed].fill(value);
    let mut done = seed;
    while done < slice.len() {
        let n = done.min(slice.len() - done);
        slice.copy_within(..n, done);
        done += n;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_length_is_filled_as_slice_fill_fills_it() {
        for len in 0..700 {
            let mut ours = vec![[1u8, 2, 3]; len + 2];
            let mut std = ours.clone();
            fill(&mut ours[1..len + 1], [7, 8, 9]);
            std[1..len + 1].fill([7, 8, 9]);
            assert_eq!(ours, std, "length {len}");
        }
    }
}

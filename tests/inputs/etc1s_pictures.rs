//! The pictures of tests/data/ktx2/, drawn here for the tool that encodes
//! them as ETC1S (`tools/etc1s-ktx2`) and for the tests that compare the
//! decoded texels with them.
//!
//! They are made of what ETC1S codes: one colour a 4×4 block, and inside
//! it a brightness that varies texel by texel (the same for R, G and B).
//! From block to block red rises to the right and green falls downward, so
//! a flip or a swap of the two shows; blue is one value per mip level, so
//! a wrong level shows; alpha, coded as a picture of its own, rises along
//! the diagonal, unlike both the mean of RGB and 255.

/// One file: its name, its level 0's size, whether it has alpha, its levels.
pub struct Picture {
    pub file: &'static str,
    pub width: usize,
    pub height: usize,
    pub alpha: bool,
    pub levels: u32,
}

/// Opaque and not square; with alpha and a size that is not a multiple of
/// the 4×4 blocks; and a whole mip chain, 32×32 down to 1×1.
pub const PICTURES: [Picture; 3] = [
    Picture {
        file: "rgb.ktx2",
        width: 32,
        height: 24,
        alpha: false,
        levels: 1,
    },
    Picture {
        file: "rgba.ktx2",
        width: 30,
        height: 22,
        alpha: true,
        levels: 1,
    },
    Picture {
        file: "mips.ktx2",
        width: 32,
        height: 32,
        alpha: false,
        levels: 6,
    },
];

/// Each level's blue, 40 apart from any other level's.
pub const LEVEL_BLUE: [u8; 6] = [30, 190, 110, 230, 70, 150];
/// The brightness added inside a block, by the texel's place in it.
const SHADE: [i32; 4] = [-24, -8, 8, 24];

/// Level `k`'s size (each level halves, rounding down, to 1).
pub fn level_size(picture: &Picture, k: u32) -> (usize, usize) {
    ((picture.width >> k).max(1), (picture.height >> k).max(1))
}

/// `from` + `span` × where the middle of block `i` of `n` lies.
fn ramp(from: usize, span: usize, i: usize, n: usize) -> i32 {
    (from + span * (2 * i + 1) / (2 * n)) as i32
}

/// Texel (x, y) of level `k`, RGBA (alpha 255 for an opaque picture).
pub fn texel(picture: &Picture, k: u32, x: usize, y: usize) -> [u8; 4] {
    let (w, h) = level_size(picture, k);
    let (bx, by, nx, ny) = (x / 4, y / 4, w.div_ceil(4), h.div_ceil(4));
    // Along the diagonals in colour, along the rows in alpha.
    let (shade, alpha_shade) = (SHADE[(x + y) % 4], SHADE[y % 4]);
    let r = ramp(40, 160, bx, nx) + shade;
    let g = 220 - ramp(0, 160, by, ny) + shade;
    let b = i32::from(LEVEL_BLUE[k as usize]) + shade;
    let a = match picture.alpha {
        true => ramp(60, 140, bx + by, nx + ny - 1) + alpha_shade,
        false => 255,
    };
    [r, g, b, a].map(|c| c as u8)
}

/// Level `k`'s texels, row by row from the top.
pub fn level(picture: &Picture, k: u32) -> Vec<[u8; 4]> {
    let (w, h) = level_size(picture, k);
    (0..w * h)
        .map(|i| texel(picture, k, i % w, i / w))
        .collect()
}

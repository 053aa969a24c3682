//! Writes into the folder it is given (tests/data/ktx2) the ETC1S KTX2
//! files the tests read: each picture of tests/inputs/etc1s_pictures.rs
//! encoded by the Basis Universal encoder (C++, built by the
//! basis-universal crate).
//!
//! The crate's wrapper hands back a .basis file only (the encoder's own
//! KTX2 writer is not reachable through it), so the .basis file's parts
//! are moved here into a KTX2 container as that writer lays them out (KTX
//! 2.0 §3, §3.12.2 "BasisLZ Global Data"): the endpoint and selector
//! codebooks and the Huffman tables become the global data, each level's
//! RGB slice (then its alpha slice) its data. The ETC1S bits are the
//! encoder's, untouched.

use std::path::PathBuf;

use basis_universal::{BasisTextureFormat, ColorSpace, Compressor, CompressorParams};

#[path = "../../../tests/inputs/etc1s_pictures.rs"]
mod etc1s_pictures;
use etc1s_pictures::{PICTURES, Picture, level, level_size};

mod basis;
mod ktx2;

fn main() {
    let dir = PathBuf::from(std::env::args().nth(1).expect("usage: etc1s-ktx2 DIR"));
    std::fs::create_dir_all(&dir).unwrap();
    for picture in &PICTURES {
        let basis_file = encode(picture);
        let parts = basis::parse(&basis_file);
        assert_eq!(parts.levels(), picture.levels, "{}", picture.file);
        assert_eq!(parts.has_alpha(), picture.alpha, "{}", picture.file);
        let file = ktx2::write(picture, &parts);
        std::fs::write(dir.join(picture.file), &file).unwrap();
        println!(
            "{}: {} bytes (.basis {} bytes)",
            picture.file,
            file.len(),
            basis_file.len()
        );
    }
}

/// The picture's levels as RGBA8 bytes.
fn bytes(picture: &Picture, k: u32) -> Vec<u8> {
    level(picture, k).into_iter().flatten().collect()
}

/// The .basis file of `picture`: ETC1S at the highest quality, one thread
/// (the same file each run), its own levels given rather than filtered.
fn encode(picture: &Picture) -> Vec<u8> {
    let mut params = CompressorParams::new();
    params.set_basis_format(BasisTextureFormat::ETC1S);
    params.set_etc1s_quality_level(basis_universal::ETC1S_QUALITY_MAX);
    params.set_color_space(ColorSpace::Srgb);
    let (w, h) = (picture.width as u32, picture.height as u32);
    params.source_image_mut(0).init(&bytes(picture, 0), w, h, 4);
    for k in 1..picture.levels {
        let (w, h) = level_size(picture, k);
        let mut image = params.source_mipmap_image_mut(0, k - 1);
        image.init(&bytes(picture, k), w as u32, h as u32, 4);
    }
    let mut compressor = Compressor::new(1);
    // SAFETY: the parameters live until the compressor has run.
    unsafe {
        assert!(compressor.init(&params), "{}: init", picture.file);
        compressor
            .process()
            .expect("the encoder refused the picture");
    }
    compressor.basis_file().to_vec()
}

//! `relief_texture::picture`: the plain entry points to the `image` crate's
//! codecs (tested here, not in the crate: a unit test there would compile
//! every codec once more into the crate's test binary).

use image::{DynamicImage, ImageFormat};
use relief_texture::picture::{decode, decode_as, encode, has_alpha, open, save};

/// A 3×2 picture with distinct texels, alpha included.
fn picture() -> DynamicImage {
    let raw: Vec<u8> = (0..24).map(|i| (i * 10) as u8).collect();
    DynamicImage::ImageRgba8(image::RgbaImage::from_raw(3, 2, raw).unwrap())
}

#[test]
fn a_png_comes_back_texel_for_texel() {
    let bytes = encode(&picture(), ImageFormat::Png).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    assert_eq!(decode(&bytes).unwrap().to_rgba8(), picture().to_rgba8());
    assert_eq!(
        decode_as(&bytes, ImageFormat::Png).unwrap().to_rgba8(),
        picture().to_rgba8()
    );
    assert!(has_alpha(&bytes));
    let rgb = encode(
        &DynamicImage::ImageRgb8(picture().to_rgb8()),
        ImageFormat::Png,
    )
    .unwrap();
    assert!(!has_alpha(&rgb));
}

#[test]
fn a_file_is_written_and_read_in_the_format_its_name_says() {
    let dir = std::env::temp_dir().join(format!("relief-picture-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("p.tga");
    save(&picture(), &path).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert!(
        image::guess_format(&bytes).is_err(),
        "TGA has no magic number"
    );
    assert_eq!(open(&path).unwrap().to_rgba8(), picture().to_rgba8());
    assert!(decode(b"not a picture").is_err());
    assert!(!has_alpha(b"not a picture"));
    std::fs::remove_dir_all(&dir).unwrap();
}

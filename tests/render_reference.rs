//! The reference cube scene checked against numbers derived by hand.

mod common;

use common::*;
use relief::settings::Settings;

#[test]
fn reference_view_covers_the_documented_pixel_count() {
    // DESIGN.md: at 320×240 the cube covers 11,741 pixels in the reference view.
    let scene = reference_scene(true);
    let (fb, stats) = render(&scene, &Settings::default(), 320, 240);
    assert_eq!(covered(&scene, &fb), 11_741);
    assert_eq!(stats.counters.pixels_shaded, 11_741);
}

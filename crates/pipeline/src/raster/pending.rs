//! Pixels left over by small triangles, shaded together: a triangle of a
//! pixel or two fills one lane or two of a packet, and on a dense mesh most
//! triangles are that small, so the eight lanes mostly shade nothing. A
//! kernel that can shade eight pixels of different triangles at once
//! (`PixelShader::defers`) leaves its triangle's last, partial packet here;
//! the band's loop shades them eight at a time (`render::dispatch`), with
//! each lane's own triangle, as each would have been shaded alone.
//!
//! Deferring must not change which colour a pixel ends with. A pixel is
//! deferred only after it passed its coverage and depth tests, and:
//! - without a depth buffer (one convex mesh, back faces culled) no later
//!   triangle covers it;
//! - after a depth pre-pass only its owner shades it;
//! - with a depth buffer, a later, nearer triangle lowers the buffer's
//!   depth there, so a deferred pixel is written only where the buffer
//!   still holds its own depth (the buffer only decreases: once below the
//!   pixel's depth it stays below).

use relief_core::framebuffer::Rgb;
use relief_texture::sample::mip::Footprint;

use crate::shade::packet::LANES;
use crate::shade::shader::PendingKey;

/// A deferred pixel: its triangle's shader, its perspective-correct
/// barycentrics and texture footprint, where it goes in the band, and the
/// depth it wrote to the band's buffer (NaN when the band has none to
/// check).
#[derive(Clone, Copy, Debug, Default)]
pub struct PendingPixel {
    pub shader: u32,
    pub b: [f32; 3],
    pub fp: Footprint,
    pub at: usize,
    pub z: f32,
}

/// Room for a full packet and a triangle's leftover (at most 7) beyond it.
const ROOM: usize = 2 * LANES;

/// The band's deferred pixels, in the order their triangles were drawn.
pub struct Pending {
    /// Whether the band defers at all (a band drawn outside the band loop,
    /// as the tests draw one, shades every pixel at once).
    on: bool,
    key: Option<PendingKey>,
    pixels: [PendingPixel; ROOM],
    count: usize,
}

impl Pending {
    /// A queue the band loop empties.
    pub fn on() -> Pending {
        Pending {
            on: true,
            ..Pending::off()
        }
    }

    /// No queue: every pixel is shaded with its triangle.
    pub fn off() -> Pending {
        Pending {
            on: false,
            key: None,
            pixels: [PendingPixel::default(); ROOM],
            count: 0,
        }
    }

    /// Whether pixels of kernel `key` may join the queue now: it is on and
    /// holds no pixel of another kind, and has room for a leftover.
    #[inline]
    pub fn takes(&self, key: PendingKey) -> bool {
        self.on && (self.count == 0 || self.key == Some(key)) && self.count < LANES
    }

    /// Adds a pixel of kernel `key` (after `takes` said yes).
    #[inline]
    pub fn push(&mut self, key: PendingKey, pixel: PendingPixel) {
        self.key = Some(key);
        self.pixels[self.count] = pixel;
        self.count += 1;
    }

    pub fn len(&self) -> usize {
        self.count
    }

    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The first packet's pixels (up to eight).
    pub fn packet(&self) -> &[PendingPixel] {
        &self.pixels[..self.count.min(LANES)]
    }

    /// Drops the first packet's pixels (after they were shaded).
    pub fn drop_packet(&mut self) {
        let n = self.count.min(LANES);
        self.pixels.copy_within(n..self.count, 0);
        self.count -= n;
    }
}

/// Writes a shaded packet of deferred pixels into the band's colours,
/// each where the band's depth (when checked) is still its own.
pub fn write_packet(
    pixels: &[PendingPixel],
    colours: &[Rgb; LANES],
    color: &mut [Rgb],
    depth: Option<&[f32]>,
) {
    for (p, c) in pixels.iter().zip(colours) {
        let own = match depth {
            Some(d) if !p.z.is_nan() => d[p.at] == p.z,
            _ => true,
        };
        if own {
            color[p.at] = *c;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pixel(at: usize, z: f32) -> PendingPixel {
        PendingPixel {
            at,
            z,
            ..PendingPixel::default()
        }
    }

    #[test]
    fn a_queue_takes_one_kind_and_hands_out_packets_in_order() {
        let mut q = Pending::on();
        assert!(q.takes((1, 0)));
        for at in 0..7 {
            q.push((1, 0), pixel(at, f32::NAN));
        }
        assert!(!q.takes((2, 0)), "another kernel's pixels wait for a flush");
        assert!(q.takes((1, 0)));
        for at in 7..12 {
            q.push((1, 0), pixel(at, f32::NAN));
        }
        assert!(!q.takes((1, 0)), "a full packet is shaded before more come");
        assert_eq!(
            q.packet().iter().map(|p| p.at).collect::<Vec<_>>(),
            (0..8).collect::<Vec<_>>()
        );
        q.drop_packet();
        assert_eq!(
            q.packet().iter().map(|p| p.at).collect::<Vec<_>>(),
            (8..12).collect::<Vec<_>>()
        );
        q.drop_packet();
        assert!(q.is_empty());
        assert!(!Pending::off().takes((1, 0)));
    }

    #[test]
    fn a_pixel_a_nearer_triangle_took_keeps_that_colour() {
        let mut color = vec![[0u8; 3]; 4];
        // Pixel 1's buffer depth went below its own (0.5): a later, nearer
        // triangle drew there. Pixel 2 has no depth to check.
        let depth = [0.5, 0.25, 0.5, 1.0];
        let pixels = [pixel(0, 0.5), pixel(1, 0.5), pixel(2, f32::NAN)];
        let mut colours = [[9u8; 3]; LANES];
        colours[1] = [7; 3];
        write_packet(&pixels, &colours, &mut color, Some(&depth));
        assert_eq!(color, vec![[9; 3], [0; 3], [9; 3], [0; 3]]);
    }
}

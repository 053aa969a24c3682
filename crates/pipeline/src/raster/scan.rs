//! The pixel loop: coverage by incremental edge functions, perspective-correct
//! barycentrics, depth, footprint, and the shader, for the rows of one band.

use glam::Vec2;

use super::alpha::AlphaRule;
use super::fill::fill;
use super::pending::{Pending, PendingPixel};
use super::setup::{ONE, ScreenTri};
use crate::shade::interpolate::perspective;
use crate::shade::packet::LANES;
use crate::shade::{PixelShader, ShadeCtx};
use relief_core::framebuffer::Rgb;
use relief_core::stats::Counters;
use relief_texture::sample::mip::Footprint;
use wide::f32x8;

/// A horizontal band of the framebuffer (and depth buffer) owned by one task.
pub struct Band<'a> {
    /// First row of the band in the framebuffer.
    pub y0: usize,
    pub width: usize,
    pub color: &'a mut [Rgb],
    pub depth: Option<&'a mut [f32]>,
    /// Small triangles' last pixels, shaded together by the band loop
    /// (`Pending::off()`: each with its triangle).
    pub pending: Pending,
}

impl Band<'_> {
    pub fn rows(&self) -> usize {
        self.color.len().checked_div(self.width).unwrap_or(0)
    }
}

/// Per-triangle constants for the screen-space UV derivatives.
pub(crate) struct FootprintSetup {
    uv: [Vec2; 3],
    dq_dx: f32,
    dq_dy: f32,
    duvq_dx: Vec2,
    duvq_dy: Vec2,
}

impl FootprintSetup {
    pub(crate) fn new(tri: &ScreenTri, source_uv: &[Vec2; 3]) -> Self {
        let uv = tri.vertex_uvs(source_uv);
        let uvq = [uv[0] * tri.q[0], uv[1] * tri.q[1], uv[2] * tri.q[2]];
        let (lx, ly) = tri.lambda_steps();
        let dot = |l: [f32; 3], v: [f32; 3]| l[0] * v[0] + l[1] * v[1] + l[2] * v[2];
        let dotv = |l: [f32; 3], v: [Vec2; 3]| v[0] * l[0] + v[1] * l[1] + v[2] * l[2];
        FootprintSetup {
            uv,
            dq_dx: dot(lx, tri.q),
            dq_dy: dot(ly, tri.q),
            duvq_dx: dotv(lx, uvq),
            duvq_dy: dotv(ly, uvq),
        }
    }

    /// d(uv)/dx and d(uv)/dy at a pixel, from u = U/Q (quotient rule).
    /// `w` are the perspective weights l·q already, so u = Σ uvₖ·wₖ / Σ wₖ:
    /// the vertex uv, not uv·q (which would weigh q twice).
    #[inline]
    pub(crate) fn at(&self, w: [f32; 3], q_sum: f32) -> Footprint {
        let inv = 1.0 / q_sum;
        let uv = (self.uv[0] * w[0] + self.uv[1] * w[1] + self.uv[2] * w[2]) * inv;
        Footprint {
            dx: (self.duvq_dx - uv * self.dq_dx) * inv,
            dy: (self.duvq_dy - uv * self.dq_dy) * inv,
        }
    }
}

/// A band whose depth was drawn first (a depth pre-pass): each pixel
/// holds its nearest depth, and `owner` the shader index of the first
/// triangle at that depth, the one a single pass with the depth test
/// keeps. Only that triangle shades the pixel, so overdraw costs a depth
/// test per layer, not a shading.
pub struct OwnedBand<'a> {
    pub band: Band<'a>,
    /// One per pixel of the band; `u32::MAX` where no triangle is.
    pub owner: &'a mut [u32],
}

/// How a covered pixel's depth decides whether it is drawn.
enum DepthRule<'a> {
    /// No depth buffer: every covered pixel.
    Off,
    /// Nearer than the buffer holds (which then takes the pixel's depth).
    Less(&'a mut [f32]),
    /// After a depth pre-pass: the pixel's owner only.
    Owner(&'a [u32]),
}

impl DepthRule<'_> {
    /// Whether the pixel at index `at` of the band, at screen-space
    /// barycentrics `l` of `tri`, is drawn (and the buffer updated, unless
    /// the pixel is blended: a translucent surface hides nothing).
    #[inline(always)]
    fn passes(
        &mut self,
        at: usize,
        l: [f32; 3],
        tri: &ScreenTri,
        blends: bool,
        counters: &mut Counters,
    ) -> bool {
        match self {
            DepthRule::Off => true,
            DepthRule::Less(depth) => {
                counters.depth_tests += 1;
                let z = l[0] * tri.z[0] + l[1] * tri.z[1] + l[2] * tri.z[2];
                let slot = &mut depth[at];
                if z < *slot {
                    if !blends {
                        *slot = z;
                    }
                    true
                } else {
                    false
                }
            }
            // No pre-pass runs on a frame with a translucent material.
            DepthRule::Owner(owner) => owner[at] == tri.shader,
        }
    }
}

/// The pixels of one band and how their depth is tested.
struct Rows<'a> {
    y0: usize,
    width: usize,
    color: &'a mut [Rgb],
    depth: DepthRule<'a>,
    pending: &'a mut Pending,
}

/// Rasterizes the part of `tri` inside `band` with shader `S`.
pub fn raster_triangle<S: PixelShader>(
    tri: &ScreenTri,
    shader: &S,
    ctx: &ShadeCtx,
    band: &mut Band,
    counters: &mut Counters,
) {
    let rows = band.rows();
    let target = Rows {
        y0: band.y0,
        width: band.width,
        color: band.color,
        depth: match band.depth.as_deref_mut() {
            Some(depth) => DepthRule::Less(depth),
            None => DepthRule::Off,
        },
        pending: &mut band.pending,
    };
    raster_rows(tri, shader, ctx, target, rows, counters)
}

/// Rasterizes the part of `tri` inside a band whose depth was drawn first
/// ([`depth_prepass`]): only the pixels `tri` owns are shaded.
pub fn raster_owned<S: PixelShader>(
    tri: &ScreenTri,
    shader: &S,
    ctx: &ShadeCtx,
    band: &mut OwnedBand,
    counters: &mut Counters,
) {
    let rows = band.band.rows();
    let target = Rows {
        y0: band.band.y0,
        width: band.band.width,
        color: band.band.color,
        depth: DepthRule::Owner(band.owner),
        pending: &mut band.band.pending,
    };
    raster_rows(tri, shader, ctx, target, rows, counters)
}

/// The depth pre-pass of one triangle over `band`: each covered pixel
/// nearer than the buffer takes the triangle's depth (computed exactly as
/// the shading pass computes it) and its shader as owner. Never for an
/// alpha-masked plan: its depth depends on the texture.
pub fn depth_prepass(tri: &ScreenTri, band: &mut OwnedBand, counters: &mut Counters) {
    let Some(depth) = band.band.depth.as_deref_mut() else {
        return;
    };
    let (y0, width) = (band.band.y0, band.band.width);
    let band_last = y0 + depth.len().checked_div(width).unwrap_or(0);
    let ya = (tri.y0 as usize).max(y0);
    let yb = (tri.y1 as usize + 1).min(band_last);
    if ya >= yb {
        return;
    }
    let inv_area = (1.0 / tri.area as f64) as f32;
    let steps = [tri.edge_steps(0), tri.edge_steps(1), tri.edge_steps(2)];
    let span_steps = steps.map(|s| s.0);
    let (x0, x1) = (tri.x0 as usize, tri.x1 as usize);
    let cx = tri.x0 as i64 * ONE + ONE / 2;
    for py in ya..yb {
        let cy = py as i64 * ONE + ONE / 2;
        let e_row = tri.edges(cx, cy);
        let Some((first, last)) = covered_span(&e_row, &tri.bias, &span_steps, x1 - x0) else {
            continue;
        };
        let row = (py - y0) * width + x0;
        for k in first..=last {
            let e = [0, 1, 2].map(|i| e_row[i] + steps[i].0 * k as i64);
            let l = e.map(|e| e as f32 * inv_area);
            counters.depth_tests += 1;
            let z = l[0] * tri.z[0] + l[1] * tri.z[1] + l[2] * tri.z[2];
            let at = row + k;
            if z < depth[at] {
                depth[at] = z;
                band.owner[at] = tri.shader;
            }
        }
    }
}

/// The pixel loops over the rows of `target` (`rows` of them).
fn raster_rows<S: PixelShader>(
    tri: &ScreenTri,
    shader: &S,
    ctx: &ShadeCtx,
    mut band: Rows,
    rows: usize,
    counters: &mut Counters,
) {
    let band_last = band.y0 + rows;
    let ya = (tri.y0 as usize).max(band.y0);
    let yb = (tri.y1 as usize + 1).min(band_last);
    if ya >= yb {
        return;
    }
    let alpha = AlphaRule::of(shader, ctx);
    if tri.unclipped && ctx.packets && shader.packets(ctx) && !alpha.blends() {
        return raster_packets(tri, shader, ctx, band, counters, ya..yb);
    }
    let (footprint, inv_area, steps) = pixel_setup(tri, shader, ctx);
    // An alpha mask drops a pixel before its depth test.
    let blends = alpha.blends();
    let x0 = tri.x0 as usize;
    let cx = tri.x0 as i64 * ONE + ONE / 2;
    let width = band.width;
    for py in ya..yb {
        let cy = py as i64 * ONE + ONE / 2;
        let mut e = tri.edges(cx, cy);
        let row = (py - band.y0) * width;
        for px in x0..=tri.x1 as usize {
            if (e[0] + tri.bias[0]) | (e[1] + tri.bias[1]) | (e[2] + tri.bias[2]) >= 0 {
                let l = [
                    e[0] as f32 * inv_area,
                    e[1] as f32 * inv_area,
                    e[2] as f32 * inv_area,
                ];
                let covered = alpha
                    .coverage(tri, shader, ctx, l)
                    .filter(|_| band.depth.passes(row + px, l, tri, blends, counters));
                if let Some(a) = covered {
                    let c = shade_at(tri, shader, ctx, footprint.as_ref(), l, counters);
                    let slot = &mut band.color[row + px];
                    *slot = alpha.composite(*slot, c, a);
                }
            }
            e[0] += steps[0].0;
            e[1] += steps[1].0;
            e[2] += steps[2].0;
        }
    }
}

/// What every pixel loop over a triangle needs first: the UV footprint
/// setup when the shader reads a mip-filtered texture, 1 / area for the
/// barycentrics, and each edge function's step along x and y.
pub(super) fn pixel_setup<S: PixelShader>(
    tri: &ScreenTri,
    shader: &S,
    ctx: &ShadeCtx,
) -> (Option<FootprintSetup>, f32, [(i64, i64); 3]) {
    let footprint = if S::SAMPLES_TEXTURE && ctx.plan.footprint {
        shader.uvs().map(|uv| FootprintSetup::new(tri, uv))
    } else {
        None
    };
    let inv_area = (1.0 / tri.area as f64) as f32;
    let steps = [tri.edge_steps(0), tri.edge_steps(1), tri.edge_steps(2)];
    (footprint, inv_area, steps)
}

/// The packet loop: per row, the covered span (found with the edge
/// functions, one integer test per pixel), shaded eight pixels at a time.
/// Coverage, depth and every lane's value are exactly those of the
/// one-pixel loop.
fn raster_packets<S: PixelShader>(
    tri: &ScreenTri,
    shader: &S,
    ctx: &ShadeCtx,
    mut band: Rows,
    counters: &mut Counters,
    rows: std::ops::Range<usize>,
) {
    let (footprint, inv_area, steps) = pixel_setup(tri, shader, ctx);
    // An alpha mask drops a lane before its depth test, as it drops a pixel.
    let alpha = AlphaRule::of(shader, ctx);
    let cut = alpha != AlphaRule::Opaque;
    let (x0, x1) = (tri.x0 as usize, tri.x1 as usize);
    let cx = tri.x0 as i64 * ONE + ONE / 2;
    let width = band.width;
    let at = |e: &[i64; 3], k: i64| {
        [
            e[0] + steps[0].0 * k,
            e[1] + steps[1].0 * k,
            e[2] + steps[2].0 * k,
        ]
    };
    let span_steps = [steps[0].0, steps[1].0, steps[2].0];
    let mut tails = Tails::default();
    for py in rows {
        let cy = py as i64 * ONE + ONE / 2;
        let e_row = tri.edges(cx, cy);
        // The edge weights of the row's pixel `px`, as the one-pixel loop has them.
        let weights_at = |px: usize| {
            let e = at(&e_row, (px - x0) as i64);
            [
                e[0] as f32 * inv_area,
                e[1] as f32 * inv_area,
                e[2] as f32 * inv_area,
            ]
        };
        // The covered pixels of a row are contiguous (the triangle is convex).
        let Some((first, last)) = covered_span(&e_row, &tri.bias, &span_steps, x1 - x0) else {
            continue;
        };
        let (first, last) = (x0 + first, x0 + last);
        let row = (py - band.y0) * width;
        let no_depth = matches!(band.depth, DepthRule::Off);
        if let (Some(color), true) = (shader.solid(), no_depth) {
            fill(&mut band.color[row + first..=row + last], color);
            counters.pixels_shaded += (last + 1 - first) as u64;
            counters.packet_pixels += (last + 1 - first) as u64;
            continue;
        }
        let mut px = first;
        while px <= last {
            let lanes = LANES.min(last + 1 - px);
            if lanes < LANES {
                // A span's last few pixels wait for the next rows' to fill
                // a packet (a small triangle's rows are all short).
                for p in px..=last {
                    let lf = weights_at(p);
                    if (!cut || alpha.coverage(tri, shader, ctx, lf).is_some())
                        && band.depth.passes(row + p, lf, tri, false, counters)
                        && tails.push(lf, row + p)
                    {
                        tails.flush(tri, shader, ctx, footprint.as_ref(), &mut band, counters);
                    }
                }
                break;
            }
            let mut live = (1u32 << lanes) - 1;
            let mut l = [[0.0f32; LANES]; 3];
            if no_depth && !cut {
                // Every pixel of the span is inside.
                l = inside_weights(at(&e_row, (px - x0) as i64), &steps, inv_area);
            } else {
                for lane in 0..lanes {
                    let lf = weights_at(px + lane);
                    if alpha.coverage(tri, shader, ctx, lf).is_none() {
                        live &= !(1 << lane);
                        continue;
                    }
                    if !band.depth.passes(row + px + lane, lf, tri, false, counters) {
                        live &= !(1 << lane);
                        continue;
                    }
                    for (lk, v) in l.iter_mut().zip(lf) {
                        lk[lane] = v;
                    }
                }
            }
            if live != 0 {
                let b = perspective(l.map(f32x8::from), tri.q).b;
                let fp = packet_footprints(footprint.as_ref(), &l, tri.q, live);
                let colors = shader.shade8(ctx, b, &fp, live, counters);
                counters.packet_pixels += u64::from(live.count_ones());
                store_packet(&mut band.color[row + px..row + px + lanes], colors, live);
            }
            px += LANES;
        }
    }
    let defers = |key| tails.count <= S::MOST_DEFERRED && band.pending.takes(key);
    match shader.defers(ctx).filter(|&key| defers(key)) {
        Some(key) => tails.defer(tri, footprint.as_ref(), &mut band, key),
        None => tails.flush(tri, shader, ctx, footprint.as_ref(), &mut band, counters),
    }
}

/// Covered pixels of a triangle, from the ends of its rows, gathered into
/// one packet: a triangle a few pixels wide shades its rows together
/// instead of a packet per row, each lane as the one-pixel loop shades it.
#[derive(Default)]
struct Tails {
    /// Each gathered pixel's edge weights, lane by lane.
    l: [[f32; LANES]; 3],
    /// Each gathered pixel's place in the band's colour rows.
    at: [usize; LANES],
    count: usize,
}

impl Tails {
    /// Adds a covered pixel; true when the packet is full.
    #[inline(always)]
    fn push(&mut self, l: [f32; 3], at: usize) -> bool {
        let lane = self.count;
        for (k, v) in l.into_iter().enumerate() {
            self.l[k][lane] = v;
        }
        self.at[lane] = at;
        self.count += 1;
        self.count == LANES
    }

    /// Shades the gathered pixels, writes them, and empties the packet.
    #[inline(always)]
    fn flush<S: PixelShader>(
        &mut self,
        tri: &ScreenTri,
        shader: &S,
        ctx: &ShadeCtx,
        footprint: Option<&FootprintSetup>,
        band: &mut Rows,
        counters: &mut Counters,
    ) {
        if self.count == 0 {
            return;
        }
        if self.count == 1 {
            // One pixel (a triangle that covers one): the one-pixel
            // kernel, the same bits without the packet's eight-lane setup.
            let l = [self.l[0][0], self.l[1][0], self.l[2][0]];
            band.color[self.at[0]] = shade_at(tri, shader, ctx, footprint, l, counters);
            counters.packet_pixels += 1;
            self.count = 0;
            return;
        }
        let live = (1u32 << self.count) - 1;
        // Lanes beyond the count hold a pixel shaded before: never written.
        let b = perspective(self.l.map(f32x8::from), tri.q).b;
        let fp = packet_footprints(footprint, &self.l, tri.q, live);
        let colors = shader.shade8(ctx, b, &fp, live, counters);
        counters.packet_pixels += u64::from(live.count_ones());
        for (&at, colour) in self.at.iter().zip(colors).take(self.count) {
            band.color[at] = colour;
        }
        self.count = 0;
    }

    /// Leaves the gathered pixels to the band's queue of kernel `key`,
    /// each with what `shade_at` would shade it from, and empties the
    /// packet.
    #[inline(always)]
    fn defer(
        &mut self,
        tri: &ScreenTri,
        footprint: Option<&FootprintSetup>,
        band: &mut Rows,
        key: crate::shade::shader::PendingKey,
    ) {
        for lane in 0..self.count {
            let l = [self.l[0][lane], self.l[1][lane], self.l[2][lane]];
            let p = perspective(l, tri.q);
            let z = match band.depth {
                DepthRule::Less(_) => l[0] * tri.z[0] + l[1] * tri.z[1] + l[2] * tri.z[2],
                DepthRule::Off | DepthRule::Owner(_) => f32::NAN,
            };
            let pixel = PendingPixel {
                shader: tri.shader,
                b: tri.source_barycentrics(p.b).to_array(),
                fp: footprint.map_or_else(Footprint::default, |f| f.at(p.w, p.sum)),
                at: self.at[lane],
                z,
            };
            band.pending.push(key, pixel);
        }
        self.count = 0;
    }
}

/// The edge weights of eight pixels from the first one's edge values `e`:
/// the edge values are integers below 2^53, exact in f64, so
/// e + step·lane there rounds to f32 exactly as the integer does.
// Loops, not `array::from_fn`: in one codegen unit the compiler kept
// `from_fn`'s helper out of line here (9 % of the reference frame).
#[inline(always)]
fn inside_weights(e: [i64; 3], steps: &[(i64, i64); 3], inv_area: f32) -> [[f32; LANES]; 3] {
    let mut weights = [[0.0; LANES]; 3];
    for ((weights, e), step) in weights.iter_mut().zip(e).zip(steps) {
        let (e, s) = (e as f64, step.0 as f64);
        for (lane, w) in weights.iter_mut().enumerate() {
            *w = (e + s * lane as f64) as f32 * inv_area;
        }
    }
    weights
}

/// Each live lane's footprint as `shade_at` computes it, from the lanes'
/// edge weights `l` (none without a footprint setup).
#[inline(always)]
fn packet_footprints(
    footprint: Option<&FootprintSetup>,
    l: &[[f32; LANES]; 3],
    q: [f32; 3],
    live: u32,
) -> [Footprint; LANES] {
    let mut fp = [Footprint::default(); LANES];
    if let Some(f) = footprint {
        for lane in (0..LANES).filter(|k| live & (1 << k) != 0) {
            let p = perspective([l[0][lane], l[1][lane], l[2][lane]], q);
            fp[lane] = f.at(p.w, p.sum);
        }
    }
    fp
}

/// Writes the live lanes of a shaded packet to `out` (its pixels).
#[inline(always)]
fn store_packet(out: &mut [Rgb], colors: [Rgb; LANES], live: u32) {
    if live == (1 << LANES) - 1 {
        // A whole packet: a store of known size (a slice copy of unknown
        // length was a call to `memcpy` per packet).
        if let Ok(whole) = <&mut [Rgb; LANES]>::try_from(out) {
            *whole = colors;
        }
    } else {
        for (lane, (o, c)) in out.iter_mut().zip(colors).enumerate() {
            if live & (1 << lane) != 0 {
                *o = c;
            }
        }
    }
}

/// The first and last pixel offsets k in 0..=len of a row whose edge values
/// `e + step·k` (plus the fill-rule bias) are all ≥ 0, solved per edge in
/// exact integers: the very pixels the one-pixel test accepts.
#[inline]
fn covered_span(
    e: &[i64; 3],
    bias: &[i64; 3],
    step: &[i64; 3],
    len: usize,
) -> Option<(usize, usize)> {
    let (mut lo, mut hi) = (0i64, len as i64);
    for i in 0..3 {
        let a = e[i] + bias[i];
        let s = step[i];
        if s > 0 {
            // a + s·k ≥ 0 ⇔ k ≥ ⌈−a / s⌉.
            let n = -a;
            let q = n.div_euclid(s) + (n.rem_euclid(s) != 0) as i64;
            lo = lo.max(q);
        } else if s < 0 {
            // a + s·k ≥ 0 ⇔ k ≤ ⌊a / −s⌋.
            hi = hi.min(a.div_euclid(-s));
        } else if a < 0 {
            return None;
        }
    }
    (lo <= hi).then_some((lo as usize, hi as usize))
}

/// Shades the point with screen-space barycentrics `l` (summing to 1):
/// perspective-correct weights, mapped back to the source triangle when the
/// triangle was clipped, and the texture footprint there when one is wanted.
#[inline(always)]
pub(crate) fn shade_at<S: PixelShader>(
    tri: &ScreenTri,
    shader: &S,
    ctx: &ShadeCtx,
    footprint: Option<&FootprintSetup>,
    l: [f32; 3],
    counters: &mut Counters,
) -> Rgb {
    let p = perspective(l, tri.q);
    let b = tri.source_barycentrics(p.b);
    let fp = match footprint {
        Some(f) => f.at(p.w, p.sum),
        None => Footprint::default(),
    };
    shader.shade(ctx, b, fp, counters)
}

#[cfg(test)]
mod tests {
    use super::{FootprintSetup, covered_span};
    use crate::raster::ClipVertex;
    use crate::raster::setup::setup;
    use glam::{Vec2, Vec3, Vec4};

    /// The footprint against derivatives worked out apart in f64: for a
    /// screen point, the 3D barycentrics b whose clip-space point Σ bₖPₖ
    /// projects there (a 3×3 linear solve), u = Σ bₖuvₖ, differentiated by
    /// central differences. Receding planes (depth 1:6 across the
    /// triangle) with texture coordinates far from 0, where weighing q
    /// twice once underestimated the level of detail by up to half a level.
    #[test]
    fn footprint_matches_f64_derivatives_on_receding_planes() {
        let (width, height) = (320usize, 240usize);
        let screen = [(20.0f64, 220.0f64), (300.0, 220.0), (160.0, 20.0)];
        for (ws, uv) in [
            ([2.0f64, 2.0, 12.0], [(0.0, 3.0), (1.0, 3.0), (0.5, 4.0)]),
            ([2.0, 9.0, 4.0], [(5.0, 0.0), (6.5, 0.5), (5.0, 2.0)]),
            ([7.0, 1.5, 1.5], [(-4.0, -4.0), (-2.0, -4.0), (-3.0, -1.0)]),
        ] {
            // Clip positions whose projections are `screen` exactly.
            let clip: [Vec4; 3] = std::array::from_fn(|k| {
                let (sx, sy) = screen[k];
                let nx = sx / width as f64 * 2.0 - 1.0;
                let ny = 1.0 - sy / height as f64 * 2.0;
                Vec4::new((nx * ws[k]) as f32, (ny * ws[k]) as f32, 0.0, ws[k] as f32)
            });
            let bary = [Vec3::X, Vec3::Y, Vec3::Z];
            let v = std::array::from_fn(|k| ClipVertex {
                pos: clip[k],
                bary: bary[k],
            });
            let tri = setup(v, width, height, 0).unwrap();
            let uv32 = uv.map(|(u, v)| Vec2::new(u as f32, v as f32));
            let fp = FootprintSetup::new(&tri, &uv32);
            // u, v at screen point (x, y), from the 3D barycentrics.
            let uv_at = |x: f64, y: f64| -> (f64, f64) {
                let nx = x / width as f64 * 2.0 - 1.0;
                let ny = 1.0 - y / height as f64 * 2.0;
                let p = clip.map(|c| c.as_dvec4());
                let rows = [
                    p.map(|c| c.x - nx * c.w),
                    p.map(|c| c.y - ny * c.w),
                    [1.0; 3],
                ];
                let m = glam::DMat3::from_cols_array_2d(&rows).transpose();
                let b = m.inverse() * glam::DVec3::new(0.0, 0.0, 1.0);
                (
                    b.x * uv[0].0 + b.y * uv[1].0 + b.z * uv[2].0,
                    b.x * uv[0].1 + b.y * uv[1].1 + b.z * uv[2].1,
                )
            };
            let mut checked = 0;
            for py in (30..215).step_by(7) {
                for px in (30..290).step_by(7) {
                    let (x, y) = (px as f64 + 0.5, py as f64 + 0.5);
                    let fixed = |c: f64| (c * super::ONE as f64) as i64;
                    let e = tri.edges(fixed(x), fixed(y));
                    if e.iter().any(|&e| e <= 0) {
                        continue;
                    }
                    let l = e.map(|e| e as f32 / tri.area as f32);
                    let w = [0, 1, 2].map(|k| l[k] * tri.q[k]);
                    let got = fp.at(w, w[0] + w[1] + w[2]);
                    let h = 1e-3;
                    let d = |a: (f64, f64), b: (f64, f64)| {
                        Vec2::new(
                            ((b.0 - a.0) / (2.0 * h)) as f32,
                            ((b.1 - a.1) / (2.0 * h)) as f32,
                        )
                    };
                    let want_dx = d(uv_at(x - h, y), uv_at(x + h, y));
                    let want_dy = d(uv_at(x, y - h), uv_at(x, y + h));
                    // f32 arithmetic on values near 5 with per-pixel steps
                    // near 0.01: a few parts in 10⁴ of the longer side.
                    let scale = want_dx.length().max(want_dy.length());
                    let err = (got.dx - want_dx).length().max((got.dy - want_dy).length());
                    assert!(
                        err <= 1e-3 * scale,
                        "{px},{py} {ws:?}: got {:?} want {want_dx} {want_dy}",
                        got
                    );
                    checked += 1;
                }
            }
            assert!(checked > 300, "{checked}");
        }
    }

    /// The span solved per edge is the run of pixels the one-pixel test
    /// accepts, for edges rising, falling and flat, with and without bias.
    #[test]
    fn covered_span_is_the_run_the_pixel_test_accepts() {
        let mut seed = 0x2545_f491_u64;
        let mut next = |range: i64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % (2 * range as u64 + 1)) as i64 - range
        };
        for _ in 0..20_000 {
            let len = next(40).unsigned_abs() as usize;
            let step = [next(3) * 256, next(600), next(2)];
            let e = [next(9000), next(9000), next(600)];
            let bias = [0, -next(1).abs(), -1];
            let inside = |k: i64| (0..3).all(|i| e[i] + bias[i] + step[i] * k >= 0);
            let accepted: Vec<usize> = (0..=len).filter(|&k| inside(k as i64)).collect();
            let want = accepted.first().map(|&a| (a, *accepted.last().unwrap()));
            // Convex: the accepted pixels are contiguous.
            if let Some((a, b)) = want {
                assert_eq!(accepted.len(), b - a + 1);
            }
            assert_eq!(
                covered_span(&e, &bias, &step, len),
                want,
                "{e:?} {step:?} {bias:?}"
            );
        }
    }
}

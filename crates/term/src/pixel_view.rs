//! Pixel frames in the interactive view: the picture sent as a kitty, sixel
//! or iTerm2 image over the picture area, the rest of the screen (status
//! line, panels, help) text drawn by ratatui.
//!
//! ratatui's diff must not write over the image: the picture area's cells
//! are marked `skip` in its buffer, so the diff leaves them alone (and a
//! frame whose picture did not change sends nothing there). Cells something
//! is drawn over (a panel, the help, a message) are not skipped: the text
//! goes there and the image stays around it. kitty shows the uncovered
//! cells as placements of the image already sent (a source rectangle each,
//! no pixels sent again), replaced when the panel moves or closes. Sixel
//! and iTerm2 images are cells the text overwrites; when a panel closes,
//! only the cells it covered are sent again.
//!
//! Over a link too slow for the exact frame (it would take longer than
//! [`LINK_SECONDS`]), the exact frame goes first scaled down to what the
//! link carries in that time, then in strips of whole cell rows, one per
//! paced write ([`PixelView::next_strip`]), until a new picture drops the
//! rest. A strip, like the cells a panel leaves, is a cell rectangle of
//! the picture sent again ([`super::cell_rects`]).
//!
//! The image goes to the picture area's top-left cell with an absolute
//! cursor move. It never scrolls the screen: the picture area ends two
//! rows above the bottom, and a screen too small for that gets text.
//! Inside tmux the sequences go through tmux's passthrough (`DCS tmux;`
//! with every `ESC` doubled). The image is deleted (kitty `a=d,d=I`, sixel
//! and iTerm2 cells cleared) on exit, on Ctrl-Z and when leaving pixels; the
//! terminal guard calls [`take_cleanup`] for the first two.

use std::collections::VecDeque;
use std::io::{self, Write};
use std::sync::Mutex;

use ratatui::Terminal;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::widgets::Widget;

use super::backend::SgrBackend;
use super::cell_rects::{Kept, Layer, crop, rectangles, source_rect, within};
use super::cells::SymbolCells;
use super::color::ColorDepth;
use super::format::{Format, FormatChoice, TmuxPixels};
use super::symbols::Symbols;
use super::{iterm, kitty, median_cut, sixel};
use relief_core::framebuffer::{Framebuffer, Rgb};

/// Cell size in pixels when neither the kernel (`TIOCGWINSZ`) nor the
/// terminal (`CSI 16 t`) says: a common 8×16 font.
pub const DEFAULT_CELL: (u16, u16) = (8, 16);

/// Most pixels of one frame: the frame buffer, its depth and the encoder's
/// copies take about 10 bytes a pixel (see [`relief_core::budget`]); 8 Mpx keep a
/// huge cell size (or a huge window) within a tenth of the budget.
pub const MAX_PIXELS: usize = (relief_core::budget::BUDGET_BYTES
    / 10
    / (relief_core::budget::FRAME_BYTES_PER_PIXEL + 3)) as usize;

/// Smallest preview scale while input keeps coming: one pixel in sixteen
/// each way. A kitty preview of a 1280×736 frame at an eighth took about
/// 25 kB, three times what 1 Mbit/s carries in a frame interval at
/// [`PREVIEW_RATE`]: the one in flight when input stopped held the final
/// picture back by 0.2 s.
pub const MIN_PREVIEW_SCALE: f64 = 0.0625;

/// Smallest scale of the picture sized to the link once input stops
/// ([`link_size`]): one pixel in eight each way.
pub const MIN_LINK_SCALE: f64 = 0.125;

/// What the view sends, chosen at start and changed by the format key.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Output {
    /// The format asked for (`--format`, `RELIEF_FORMAT`, detection or the key).
    pub wanted: Format,
    /// The format in use (the wanted one, or symbols inside tmux without
    /// passthrough), why, and whether it goes through tmux's passthrough.
    pub choice: FormatChoice,
    /// What tmux said (inside tmux).
    pub tmux: Option<TmuxPixels>,
    /// tmux draws sixel itself.
    pub tmux_sixel: bool,
    /// The cell size the terminal replied to `CSI 16 t`.
    pub cell_reply: Option<(u16, u16)>,
    /// The largest sixel image the terminal takes (width, height in
    /// pixels; its XTSMGRAPHICS reply): see [`picture_area`].
    pub sixel_max: Option<(u32, u32)>,
}

impl Default for Output {
    fn default() -> Self {
        Output {
            wanted: Format::Symbols,
            choice: FormatChoice {
                format: Format::Symbols,
                source: "default".into(),
                passthrough: false,
                note: None,
            },
            tmux: None,
            tmux_sixel: false,
            cell_reply: None,
            sixel_max: None,
        }
    }
}

impl Output {
    /// The output the clues decide (see [`super::format::choose`]), with
    /// the cell size the terminal replied.
    pub fn from_clues(c: &super::format::Clues, cell_reply: Option<(u16, u16)>) -> Self {
        let (wanted, _) = super::format::wanted(c);
        Output {
            wanted,
            choice: super::format::choose(c),
            tmux: c.tmux.clone(),
            tmux_sixel: c.tmux_draws_sixel(),
            cell_reply,
            sixel_max: None,
        }
    }

    /// The format in use.
    pub fn format(&self) -> Format {
        self.choice.format
    }

    /// The next format (the key): tmux's fallback applies to it too.
    pub fn cycle(&mut self) {
        self.wanted = self.wanted.next();
        self.choice = super::format::in_tmux(
            self.wanted,
            "key".into(),
            self.tmux.as_ref(),
            self.tmux_sixel,
        );
    }
}

/// The cell size in pixels and where it came from: the kernel's window
/// size (`ws_xpixel`/`ws_ypixel` over the cells), else the terminal's
/// reply, else [`DEFAULT_CELL`].
pub fn cell_pixels(
    window: Option<(u16, u16, u16, u16)>,
    reply: Option<(u16, u16)>,
) -> ((u16, u16), &'static str) {
    if let Some((cols, rows, w, h)) = window
        && cols > 0
        && rows > 0
        && w >= cols
        && h >= rows
    {
        return ((w / cols, h / rows), "window size");
    }
    match reply {
        Some((w, h)) if w > 0 && h > 0 => ((w, h), "CSI 16 t"),
        _ => (DEFAULT_CELL, "default"),
    }
}

/// The cells of `viewport` the picture takes, with cells of `cell` pixels:
/// all of them, except for sixel in a terminal that answered its largest
/// image ([`Output::sixel_max`]): then the most whole columns and rows
/// whose image fits it, centred (empty when not one cell fits). xterm
/// drops a larger image without a trace (`maxGraphicSize`, 1000×1000 by
/// default): a full-screen window showed nothing.
pub fn picture_area(output: &Output, viewport: Rect, cell: (u16, u16)) -> Rect {
    let Some((max_w, max_h)) = output.sixel_max else {
        return viewport;
    };
    if output.format() != Format::Sixels {
        return viewport;
    }
    let (cw, ch) = (u32::from(cell.0.max(1)), u32::from(cell.1.max(1)));
    let cols = (max_w / cw).min(u32::from(viewport.width)) as u16;
    // Sixel draws bands six pixels tall: the last one counts whole.
    let fits = |rows: u16| (u32::from(rows) * ch).next_multiple_of(6) <= max_h;
    let rows = (0..=viewport.height).rev().find(|&r| fits(r)).unwrap_or(0);
    Rect::new(
        viewport.x + (viewport.width - cols) / 2,
        viewport.y + (viewport.height - rows) / 2,
        cols,
        rows,
    )
}

/// What the cost panel says of the sixel limit, when the terminal
/// answered one: the limit and, when it shrinks the picture, the cells the
/// picture takes of the area's (cells of `cell` pixels).
pub fn sixel_limit_line(output: &Output, viewport: Rect, cell: (u16, u16)) -> Option<String> {
    let (w, h) = output.sixel_max?;
    if output.format() != Format::Sixels {
        return None;
    }
    let area = picture_area(output, viewport, cell);
    Some(if area == viewport {
        format!("max {w}×{h} px: the whole area")
    } else {
        format!(
            "max {w}×{h} px: {}×{} of {}×{} cells",
            area.width, area.height, viewport.width, viewport.height
        )
    })
}

/// The kernel's window size of standard output: columns, rows, width and
/// height in pixels (none when it is not a terminal).
pub fn window_size() -> Option<(u16, u16, u16, u16)> {
    let w = crossterm::terminal::window_size().ok()?;
    Some((w.columns, w.rows, w.width, w.height))
}

/// The frame's pixel size for `cols × rows` cells of `cell` pixels,
/// scaled down evenly (pixels stay square) to at most [`MAX_PIXELS`].
pub fn frame_size(cols: u16, rows: u16, cell: (u16, u16)) -> (usize, usize) {
    let w = usize::from(cols) * usize::from(cell.0.max(1));
    let h = usize::from(rows) * usize::from(cell.1.max(1));
    scaled_within(w, h, MAX_PIXELS)
}

fn scaled_within(w: usize, h: usize, max: usize) -> (usize, usize) {
    if w * h <= max {
        return (w, h);
    }
    let s = (max as f64 / (w * h) as f64).sqrt();
    let sw = ((w as f64 * s).floor() as usize).max(1);
    let sh = ((h as f64 * s).floor() as usize).max(1);
    (sw, sh)
}

/// The size of a pixel preview of a `w × h` frame while input keeps
/// coming: scaled so its bytes (about proportional to its pixels, from the
/// last exact frame's `exact_bytes`) fit what the link carries in a frame
/// interval (`budget_bytes`), between [`MIN_PREVIEW_SCALE`] and half.
pub fn preview_size(w: usize, h: usize, exact_bytes: u64, budget_bytes: f64) -> (usize, usize) {
    let s = (budget_bytes / exact_bytes.max(1) as f64)
        .sqrt()
        .clamp(MIN_PREVIEW_SCALE, 0.5);
    (
        ((w as f64 * s).round() as usize).max(1),
        ((h as f64 * s).round() as usize).max(1),
    )
}

/// Frames per second a pixel preview is sized for.
pub const PREVIEW_RATE: f64 = 15.0;

/// Seconds of the link the first picture may take once input stops, when
/// the exact frame takes longer: the exact frame scaled down to what the
/// link carries in that time (the final orientation at the link's
/// resolution), so that with the round trip, the render and the quiet
/// time before it, it shows within half a second of the last input. The
/// exact frame follows in strips ([`PixelView::next_strip`]).
pub const LINK_SECONDS: f64 = 0.2;

/// The link an exact frame is sized for while the terminal answers but no
/// reply has timed a frame yet (right after start): 1 Mbit/s, the slowest
/// link relief is made for. Sent whole, the first kitty frame of a
/// 160×48-cell window (1.2 MB) held input behind it for 10 s at that rate;
/// now it goes link-sized and in strips, re-cut once the first reply has
/// measured the link ([`PixelView::next_strip`]).
pub const UNMEASURED_RATE: f64 = 125_000.0;

/// How many strips the `bytes` of an exact image take over a link of
/// `throughput` bytes a second: each about what the link carries in a
/// preview's frame interval.
fn strip_count(bytes: f64, throughput: f64) -> usize {
    (bytes / (throughput / PREVIEW_RATE).max(1.0)).ceil() as usize
}

/// The size of the link-sized picture of a `w × h` frame whose exact image
/// takes `exact_bytes`, for `budget_bytes`: scaled by the square root of
/// their ratio (bytes taken as proportional to pixels), at least
/// [`MIN_LINK_SCALE`], below full size.
pub fn link_size(w: usize, h: usize, exact_bytes: f64, budget_bytes: f64) -> (usize, usize) {
    let s = (budget_bytes / exact_bytes.max(1.0))
        .sqrt()
        .clamp(MIN_LINK_SCALE, 1.0);
    (
        ((w as f64 * s).round() as usize).clamp(1, w.max(1)),
        ((h as f64 * s).round() as usize).clamp(1, h.max(1)),
    )
}

/// The size of a kitty or iTerm2 preview of a `w × h` frame that fits
/// `share` bytes, when the last preview took `density` bytes per pixel of
/// its own: a small image compresses worse than the exact frame (at
/// 1 Mbit/s kitty previews sized by the exact frame's bytes took 12–15 kB
/// for an 8 kB share), so the previews' own bytes size the next. Between
/// [`MIN_PREVIEW_SCALE`] and half each way.
pub fn preview_size_measured(w: usize, h: usize, density: f64, share: f64) -> (usize, usize) {
    let pixels = (w * h).max(1) as f64;
    let s = (share / (density.max(1e-6) * pixels))
        .sqrt()
        .clamp(MIN_PREVIEW_SCALE, 0.5);
    (
        ((w as f64 * s).floor() as usize).max(1),
        ((h as f64 * s).floor() as usize).max(1),
    )
}

/// The size of a preview of a `size` frame in `format`: half each way for
/// text; for pixels what the link's `throughput` (bytes per second)
/// carries at [`PREVIEW_RATE`], judged by the last exact frame's bytes.
pub fn preview_for(
    format: Format,
    size: (usize, usize),
    exact_bytes: Option<u64>,
    throughput: Option<f64>,
) -> (usize, usize) {
    let (w, h) = size;
    match (format.is_pixels(), exact_bytes, throughput) {
        (true, Some(bytes), Some(t)) => preview_size(w, h, bytes, t / PREVIEW_RATE),
        _ => (w.div_ceil(2), h.div_ceil(2)),
    }
}

/// `seq` wrapped in tmux's passthrough: `ESC P tmux;`, the sequence with
/// each `ESC` doubled, `ESC \`.
pub fn wrap_tmux(seq: &[u8], out: &mut Vec<u8>) {
    out.extend_from_slice(b"\x1bPtmux;");
    for &b in seq {
        if b == 0x1b {
            out.push(0x1b);
        }
        out.push(b);
    }
    out.extend_from_slice(b"\x1b\\");
}

/// Moves the cursor to `area`'s top-left cell (1-based, absolute).
pub fn place(area: Rect, out: &mut Vec<u8>) {
    let _ = write!(out, "\x1b[{};{}H", area.y + 1, area.x + 1);
}

/// The bytes that delete relief's kitty image (wrapped for tmux when
/// `passthrough`).
pub fn kitty_delete(passthrough: bool) -> Vec<u8> {
    if passthrough {
        let mut out = Vec::new();
        wrap_tmux(kitty::DELETE, &mut out);
        out
    } else {
        kitty::DELETE.to_vec()
    }
}

/// What the terminal guard writes before putting the screen back: the
/// delete of a kitty image still shown (the cleared screen takes sixel
/// and iTerm2 pixels with it).
static CLEANUP: Mutex<Vec<u8>> = Mutex::new(Vec::new());

fn set_cleanup(bytes: &[u8]) {
    if let Ok(mut c) = CLEANUP.lock() {
        c.clear();
        c.extend_from_slice(bytes);
    }
}

/// The bytes that remove an image still on screen (empty when none), once.
pub fn take_cleanup() -> Vec<u8> {
    CLEANUP
        .lock()
        .map(|mut c| std::mem::take(&mut *c))
        .unwrap_or_default()
}

/// One image of `fb` in `format` over `area` (the image fills its cells:
/// kitty and iTerm2 scale it, sixel has it at its own size), placed at
/// `area`'s top-left, wrapped for tmux when `passthrough`.
pub fn image_bytes(
    fb: &Framebuffer,
    format: Format,
    area: Rect,
    dither: bool,
    passthrough: bool,
) -> io::Result<Vec<u8>> {
    let mut seq = Vec::new();
    let cells = Some((area.width, area.height));
    match format {
        Format::Kitty => kitty::write_image(fb, cells, &mut seq)?,
        Format::Sixels => sixel::write_image(fb, dither, &mut seq)?,
        Format::Iterm => iterm::write_image(fb, cells, &mut seq)?,
        Format::Auto | Format::Symbols => return Ok(Vec::new()),
    }
    Ok(placed(&seq, format, area, passthrough))
}

/// `seq` (an image in `format`) placed at `area`'s top-left, wrapped for
/// tmux when `passthrough`.
pub fn placed(seq: &[u8], format: Format, area: Rect, passthrough: bool) -> Vec<u8> {
    let mut out = Vec::with_capacity(seq.len() + 16);
    place(area, &mut out);
    if !passthrough {
        out.extend_from_slice(seq);
    } else if format == Format::Kitty {
        push_kitty(seq, true, &mut out);
    } else {
        wrap_tmux(seq, &mut out);
    }
    out
}

/// The image of `pic` (kept for `format`) over all of `area`, placed and
/// wrapped as [`image_bytes`] does (sixel from its palette mapping, made
/// once).
fn whole_bytes(
    pic: &mut Kept,
    format: Format,
    area: Rect,
    passthrough: bool,
) -> io::Result<Vec<u8>> {
    pic.map();
    let mut seq = Vec::new();
    let cells = Some((area.width, area.height));
    match (&*pic, format) {
        (Kept::Indexed(q), _) => sixel::write_quantized(q, &mut seq)?,
        (Kept::Rgb(fb), Format::Kitty) => kitty::write_image(fb, cells, &mut seq)?,
        (Kept::Rgb(fb), _) => iterm::write_image(fb, cells, &mut seq)?,
        (Kept::None | Kept::Unmapped(..), _) => return Ok(Vec::new()),
    }
    Ok(placed(&seq, format, area, passthrough))
}

/// The exact frame `fb` over a link that carries `budget` bytes in
/// [`LINK_SECONDS`], when its image (`exact_bytes` bytes) takes longer:
/// the frame scaled down to fit, filling the same cells, and its image
/// over the whole area. kitty and iTerm2 scale it; sixel has no scaling,
/// so it goes enlarged (nearest neighbour, mapped to its palette before),
/// where its bytes follow its colour runs more than its pixels. Should it not fit, it is tried again
/// smaller (sixel: with fewer colours), at most twice.
fn link_picture(
    fb: &Framebuffer,
    format: Format,
    area: Rect,
    exact_bytes: usize,
    budget: f64,
    dither: bool,
    passthrough: bool,
) -> io::Result<(Kept, Vec<u8>)> {
    let (w, h) = (fb.width(), fb.height());
    let mut from = exact_bytes as f64;
    let (mut sw, mut sh) = (w, h);
    let mut pic = Kept::None;
    let mut bytes = Vec::new();
    for colours in SIXEL_LINK_COLOURS {
        (sw, sh) = link_size(sw, sh, from, budget);
        // Never below an eighth of the frame each way.
        let least = |n: usize| ((n as f64 * MIN_LINK_SCALE).round() as usize).max(1);
        (sw, sh) = (sw.max(least(w)), sh.max(least(h)));
        let mut small = Framebuffer::new(sw, sh);
        downscale(fb, &mut small);
        if format == Format::Sixels {
            fewer_colours(&mut small, colours);
            pic = Kept::Indexed(sixel::Quantized::enlarged(&small, dither, (w, h)));
        } else {
            pic = Kept::Rgb(small);
        }
        bytes = whole_bytes(&mut pic, format, area, passthrough)?;
        if bytes.len() as f64 <= budget {
            break;
        }
        // A fifth more than it took: bytes fall slower than pixels.
        from = bytes.len() as f64 * 1.2;
    }
    Ok((pic, bytes))
}

/// The colours of a link-sized sixel picture, try by try (256: the
/// frame's own palette).
const SIXEL_LINK_COLOURS: [usize; 3] = [256, 32, 8];

/// The most colours of a sixel preview while input keeps coming: an
/// enlarged picture's bytes follow its colours' runs in each band more than
/// its pixels, and at 256 colours a preview sized for 1 Mbit/s at
/// [`PREVIEW_RATE`] took several times its share.
pub const SIXEL_PREVIEW_COLOURS: usize = 32;

/// The fewest: below, a preview no longer shows the shapes.
pub const SIXEL_PREVIEW_FEWEST: usize = 4;

/// The colours of the next sixel preview after one of `bytes` for a
/// preview's share of the link, `share` bytes: halved while a preview takes
/// over twice its share (at the smallest size, shrinking no further, a
/// 1 Mbit/s link still took 35 kB previews at 32 colours, and the one sent
/// after the last input delayed the final picture past half a second),
/// doubled back when one takes under half.
pub fn next_preview_colours(colours: usize, bytes: usize, share: f64) -> usize {
    let bytes = bytes as f64;
    if bytes > 2.0 * share {
        (colours / 2).max(SIXEL_PREVIEW_FEWEST)
    } else if bytes < 0.5 * share {
        (colours * 2).min(SIXEL_PREVIEW_COLOURS)
    } else {
        colours
    }
}

/// `fb` reduced to at most `colours` colours (median cut; 256: as it is).
fn fewer_colours(fb: &mut Framebuffer, colours: usize) {
    if colours < 256 {
        let q = median_cut::quantize(fb.pixels(), colours, |_| 0);
        for (p, &i) in fb.pixels_mut().iter_mut().zip(&q.index) {
            *p = q.palette[usize::from(i)];
        }
    }
}

/// Nearest-neighbour enlargement of `small` to fill `big` (a preview: each
/// pixel of the half-resolution picture becomes a 2×2 block, so a cell is
/// one colour and its neighbour the same: fewer bytes to send).
pub fn enlarge(small: &Framebuffer, big: &mut Framebuffer) {
    let (sw, sh) = (small.width(), small.height());
    if sw == 0 || sh == 0 {
        big.fill([0, 0, 0]);
        return;
    }
    let (bw, bh) = (big.width(), big.height());
    for y in 0..bh {
        let sy = (y * sh / bh).min(sh - 1);
        let src = small.row(sy);
        for x in 0..bw {
            let sx = (x * sw / bw).min(sw - 1);
            big.set(x, y, src[sx]);
        }
    }
}

/// kitty sequences `seq` onto `out`, through tmux when `passthrough`: one
/// passthrough per sequence (per chunk), as tmux bounds the size of one.
fn push_kitty(seq: &[u8], passthrough: bool, out: &mut Vec<u8>) {
    if !passthrough {
        out.extend_from_slice(seq);
        return;
    }
    let mut start = 0;
    for end in 1..seq.len() {
        if &seq[end - 1..=end] == b"\x1b\\" {
            wrap_tmux(&seq[start..=end], out);
            start = end + 1;
        }
    }
}

/// Average of `src` over each pixel of `dst` (box filter): the picture at
/// the text's resolution while something covers the image.
pub fn downscale(src: &Framebuffer, dst: &mut Framebuffer) {
    let (sw, sh, dw, dh) = (src.width(), src.height(), dst.width(), dst.height());
    if sw == 0 || sh == 0 {
        dst.fill([0, 0, 0]);
        return;
    }
    for y in 0..dh {
        let (y0, y1) = (
            y * sh / dh,
            ((y + 1) * sh / dh).max(y * sh / dh + 1).min(sh),
        );
        for x in 0..dw {
            let (x0, x1) = (
                x * sw / dw,
                ((x + 1) * sw / dw).max(x * sw / dw + 1).min(sw),
            );
            let mut sum = [0u32; 3];
            for yy in y0..y1 {
                for p in &src.row(yy)[x0..x1] {
                    for c in 0..3 {
                        sum[c] += u32::from(p[c]);
                    }
                }
            }
            let n = ((y1 - y0) * (x1 - x0)) as u32;
            dst.set(x, y, sum.map(|s| ((s + n / 2) / n) as u8));
        }
    }
}

/// How the picture looks as text (under a panel, or in symbols).
#[derive(Clone, Copy, Debug)]
pub struct TextLook {
    pub symbols: Symbols,
    pub depth: ColorDepth,
    pub dither: bool,
    pub pad: Rgb,
}

/// The image on screen.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Shown {
    /// The picture area it fills.
    area: Rect,
    format: Format,
    /// The pixel size of the image the terminal holds (kitty: what the
    /// placements cut from; a preview or a link-sized picture is smaller
    /// than the frame).
    image: (usize, usize),
    /// The pixels of one cell of the kept picture shown at its own size
    /// (sixel).
    cell: (usize, usize),
    /// The area's cells drawn as text over the image (a panel), row by row.
    covered: Vec<bool>,
    /// The strips of the exact frame still to send, top first.
    pending: VecDeque<Rect>,
    /// kitty: the strips sent, images of their own over relief's.
    strips: Vec<Layer>,
    /// Bytes of the strips sent.
    strip_bytes: usize,
    /// The exact image's bytes when its strips were cut for
    /// [`UNMEASURED_RATE`]: they are cut again once the link is measured.
    recut: Option<usize>,
    /// Its sequences go through tmux's passthrough.
    passthrough: bool,
}

impl Shown {
    /// kitty's images on screen: relief's picture, then the strips over it.
    fn layers(&self) -> impl Iterator<Item = Layer> + '_ {
        let picture = Layer {
            id: kitty::IMAGE_ID,
            z: 0,
            cells: self.area,
            image: self.image,
        };
        std::iter::once(picture).chain(self.strips.iter().copied())
    }

    /// The bytes that delete the kitty strips sent (and free their data).
    fn strip_deletes(&self) -> Vec<u8> {
        let mut out = Vec::new();
        for s in &self.strips {
            push_kitty(&kitty::delete(s.id), self.passthrough, &mut out);
        }
        out
    }

    /// What removes its kitty images from the screen (nothing for sixel
    /// and iTerm2: their cells are cleared or drawn over).
    fn kitty_cleanup(&self) -> Vec<u8> {
        if self.format != Format::Kitty {
            return Vec::new();
        }
        let mut out = kitty_delete(self.passthrough);
        out.extend(self.strip_deletes());
        out
    }
}

/// The pixel side of the view between frames: what is on screen.
pub struct PixelView {
    /// The picture at the text's resolution.
    small: Framebuffer,
    /// The image on screen, if any.
    shown: Option<Shown>,
    /// The picture its cells show, kept to send a cell rectangle of it
    /// again (a strip, the cells a panel leaves).
    kept: Kept,
    /// The format of the last frame.
    last_format: Option<Format>,
    /// Bytes of the whole exact image of the last frame sent in strips.
    split_bytes: Option<u64>,
    /// The last exact image's bytes (encoded, or its strips' all sent) and
    /// where it went: an exact frame that clearly takes more than the link
    /// carries in [`LINK_SECONDS`] is then not encoded whole only to be
    /// weighed.
    last_whole: Option<(Rect, Format, usize)>,
    /// The colours of the next sixel preview ([`next_preview_colours`]).
    preview_colours: usize,
    /// Bytes per pixel of the last kitty or iTerm2 preview's image, and its
    /// format ([`preview_size_measured`]).
    preview_density: Option<(Format, f64)>,
}

/// What a frame is: the format in use and its pictures.
pub struct PixelFrame<'a> {
    pub output: &'a Output,
    /// The exact (or enlarged preview) picture.
    pub fb: &'a Framebuffer,
    /// A smaller preview the terminal scales up (kitty, iTerm2).
    pub preview: Option<&'a Framebuffer>,
    /// The picture changed since the last frame.
    pub new_picture: bool,
    pub look: TextLook,
    /// The link's measured (or stated) throughput, bytes a second: an
    /// exact frame it cannot carry in [`LINK_SECONDS`] goes link-sized,
    /// then in strips.
    pub throughput: Option<f64>,
    /// No throughput yet, but the terminal's replies will measure it: the
    /// exact frame is sized for [`UNMEASURED_RATE`] meanwhile.
    pub unmeasured: bool,
}

impl Default for PixelView {
    fn default() -> Self {
        Self::new()
    }
}

impl PixelView {
    pub fn new() -> Self {
        PixelView {
            small: Framebuffer::new(0, 0),
            shown: None,
            kept: Kept::None,
            last_format: None,
            split_bytes: None,
            last_whole: None,
            preview_colours: SIXEL_PREVIEW_COLOURS,
            preview_density: None,
        }
    }

    /// The size of the next preview of a `size` frame in `format` over a
    /// link of `throughput` bytes a second: kitty and iTerm2 by the bytes
    /// per pixel of the last preview once one was sent
    /// ([`preview_size_measured`]), else as [`preview_for`] says.
    pub fn preview_size(
        &self,
        format: Format,
        size: (usize, usize),
        exact_bytes: Option<u64>,
        throughput: Option<f64>,
    ) -> (usize, usize) {
        match (self.preview_density, throughput) {
            (Some((f, density)), Some(t)) if f == format => {
                preview_size_measured(size.0, size.1, density, t / PREVIEW_RATE)
            }
            _ => preview_for(format, size, exact_bytes, throughput),
        }
    }

    /// True when `format` can show on a screen of `screen` with the picture
    /// in `viewport`: a pixel format, and the picture clear of the last row
    /// (an image reaching it would scroll).
    pub fn usable(format: Format, viewport: Rect, screen_height: u16) -> bool {
        format.is_pixels() && !viewport.is_empty() && viewport.bottom() < screen_height
    }

    /// The cells of `viewport` an image covers ([`picture_area`]), or
    /// none when the picture is text.
    pub fn image_area(output: &Output, viewport: Rect, screen_height: u16) -> Option<Rect> {
        if !Self::usable(output.format(), viewport, screen_height) {
            return None;
        }
        let (cell, _) = cell_pixels(window_size(), output.cell_reply);
        Some(picture_area(output, viewport, cell)).filter(|a| !a.is_empty())
    }

    /// The framebuffer size for the picture in `viewport`: the text's
    /// pixels, or for a pixel format the pixels of the cells its image
    /// covers ([`PixelView::image_area`]).
    pub fn framebuffer_size(
        output: &Output,
        viewport: Rect,
        screen_height: u16,
        symbols: Symbols,
    ) -> (usize, usize) {
        if let Some(area) = Self::image_area(output, viewport, screen_height) {
            let (cell, _) = cell_pixels(window_size(), output.cell_reply);
            frame_size(area.width, area.height, cell)
        } else {
            (
                usize::from(viewport.width) * symbols.columns(),
                usize::from(viewport.height) * symbols.rows(),
            )
        }
    }

    /// Draws one frame: `view` draws the whole screen from a picture at the
    /// text's resolution into ratatui's buffer; in a pixel format the
    /// picture's cells nothing is drawn over are then skipped by the diff,
    /// and the image sent or shown again where it is needed (see
    /// [`PixelView::image_update`]), all inside the open frame.
    pub fn draw<W: Write>(
        &mut self,
        terminal: &mut Terminal<SgrBackend<W>>,
        frame: PixelFrame,
        viewport: Rect,
        mut view: impl FnMut(&mut ratatui::Frame, &Framebuffer),
    ) -> io::Result<()> {
        let format = frame.output.format();
        let screen = terminal.size()?;
        let area = Self::image_area(frame.output, viewport, screen.height);
        let fb = frame.fb;
        let text_size = (
            usize::from(viewport.width) * frame.look.symbols.columns(),
            usize::from(viewport.height) * frame.look.symbols.rows(),
        );
        let text_fb = match area {
            Some(a) if a != viewport => {
                self.text_around(fb, viewport, a, frame.look);
                &self.small
            }
            Some(_) if (fb.width(), fb.height()) != text_size => {
                self.small.resize(text_size.0, text_size.1);
                downscale(fb, &mut self.small);
                &self.small
            }
            _ => fb,
        };
        if self.last_format.is_some_and(|f| f != format) {
            // A new format: the whole screen is drawn again, so nothing a
            // terminal made of the last one's sequences (a format it
            // ignores may print its bytes, even scroll) stays.
            if let Some(s) = self.shown.take() {
                terminal.backend_mut().write_raw(&s.kitty_cleanup())?;
                set_cleanup(&[]);
            }
            terminal.clear()?;
        }
        self.last_format = Some(format);
        let mut covered = None;
        terminal.draw(|f| {
            view(f, text_fb);
            if let Some(area) = area {
                let buf = f.buffer_mut();
                covered = Some(skip_picture(buf, viewport, area, text_fb, frame.look));
            }
        })?;
        let bytes = match (covered, area) {
            (Some(covered), Some(area)) => self.image_update(&frame, area, covered)?,
            _ => {
                // Text only: kitty's images are deleted; sixel and iTerm2
                // pixels are covered by the text cells drawn meanwhile.
                set_cleanup(&[]);
                self.shown
                    .take()
                    .map_or_else(Vec::new, |s| s.kitty_cleanup())
            }
        };
        if !bytes.is_empty() {
            terminal.backend_mut().write_raw(&bytes)?;
        }
        Ok(())
    }

    /// The image bytes of a pixel frame whose picture area has `covered`
    /// cells under text (a panel, the help, a message):
    ///
    /// - a new picture, area or format: the image is sent (strips of the
    ///   last one still to come are dropped, kitty's sent deleted); kitty
    ///   shows the uncovered cells as placements of it, sixel and iTerm2
    ///   are sent only over the uncovered cells (the panel's text stays).
    ///   An exact frame the link cannot carry in [`LINK_SECONDS`] goes
    ///   link-sized, its strips to follow ([`PixelView::next_strip`]);
    /// - the same picture under other cells: kitty's placements are
    ///   replaced (no pixels sent); sixel and iTerm2 send the cells a panel
    ///   left, the cells a panel now covers being text drawn over the image;
    /// - nothing changed: nothing.
    fn image_update(
        &mut self,
        frame: &PixelFrame,
        area: Rect,
        covered: Vec<bool>,
    ) -> io::Result<Vec<u8>> {
        let format = frame.output.format();
        let same_place = self
            .shown
            .as_ref()
            .is_some_and(|s| s.area == area && s.format == format);
        if frame.new_picture || !same_place {
            return self.send_picture(frame, area, covered);
        }
        self.uncover_cells(frame, area, covered)
    }

    /// A new picture, area or format: the image kept and sent whole, over
    /// the uncovered cells, or link-sized with its strips to follow.
    fn send_picture(
        &mut self,
        frame: &PixelFrame,
        area: Rect,
        covered: Vec<bool>,
    ) -> io::Result<Vec<u8>> {
        let format = frame.output.format();
        let passthrough = frame.output.choice.passthrough;
        let mut out = Vec::new();
        let open = rectangles(&covered, area, false);
        let any_covered = covered.contains(&true);
        self.keep_picture(frame, format);
        self.drop_last_picture(format, any_covered, passthrough, &mut out);
        let cell = self.image_cell(frame, area, self.kept.size());
        let rate = frame
            .throughput
            .or(frame.unmeasured.then_some(UNMEASURED_RATE));
        let budget = rate
            .filter(|_| frame.preview.is_none())
            .map(|t| t * LINK_SECONDS);
        let mut shown = Shown {
            area,
            format,
            image: self.kept.size(),
            cell,
            covered,
            pending: VecDeque::new(),
            strips: Vec::new(),
            strip_bytes: 0,
            recut: None,
            passthrough,
        };
        // The whole image: what goes when nothing covers it, and what
        // an exact frame costs the link; not encoded when the last
        // exact one here took clearly more than the link carries.
        let estimate = self
            .last_whole
            .filter(|&(a, f, _)| a == area && f == format)
            .map(|(_, _, bytes)| bytes);
        let clearly_over = matches!((budget, estimate),
            (Some(b), Some(e)) if e as f64 > 2.0 * b && strips_fit(&shown));
        let whole = if (!any_covered || budget.is_some()) && !clearly_over {
            Some(self.whole_picture(frame, format, area, passthrough)?)
        } else {
            None
        };
        let exact_len = whole.as_ref().map(Vec::len).or(estimate).unwrap_or(0);
        match budget {
            Some(budget) if exact_len as f64 > budget && strips_fit(&shown) => {
                self.send_link_sized(frame, (exact_len, budget), &mut shown, &open, &mut out)?;
            }
            _ => match whole {
                Some(whole) if !any_covered => out.extend(whole),
                _ => out.extend(over_cells(&mut self.kept, &shown, &open)?),
            },
        }
        set_cleanup(&shown.kitty_cleanup());
        self.shown = Some(shown);
        Ok(out)
    }

    /// Keeps the frame's picture as it is sent: kitty's and iTerm2's
    /// preview as it is, sixel's preview in fewer colours, mapped, then
    /// enlarged; else the exact frame.
    fn keep_picture(&mut self, frame: &PixelFrame, format: Format) {
        let send = match (format, frame.preview) {
            (Format::Kitty | Format::Iterm, Some(p)) => p,
            _ => frame.fb,
        };
        let dither = frame.look.dither;
        match (format, frame.preview) {
            // sixel's preview: the small picture in fewer colours,
            // mapped, then enlarged.
            (Format::Sixels, Some(p)) => {
                let size = (frame.fb.width(), frame.fb.height());
                let mut few = p.clone();
                fewer_colours(&mut few, self.preview_colours);
                self.kept = Kept::Indexed(sixel::Quantized::enlarged(&few, dither, size));
            }
            _ => self.kept.keep(send, format, dither),
        }
    }

    /// Forgets the last picture shown, with what of it kitty still holds
    /// (its strips, and its placements when either picture had parts).
    fn drop_last_picture(
        &mut self,
        format: Format,
        any_covered: bool,
        passthrough: bool,
        out: &mut Vec<u8>,
    ) {
        let last = self.shown.take();
        if let Some(last) = &last
            && last.format == Format::Kitty
        {
            // The strips of the last picture go with it.
            out.extend(last.strip_deletes());
        }
        let had_parts = last
            .as_ref()
            .is_some_and(|s| s.format == Format::Kitty && s.covered.contains(&true));
        if format == Format::Kitty && (had_parts || any_covered) {
            // The placements of the last image go first (kitty drops
            // them with the image it replaces; said for any terminal).
            push_kitty(kitty::DELETE_PLACEMENTS, passthrough, out);
        }
    }

    /// The kept picture encoded whole, its size noted: for the next exact
    /// frame's estimate, or to size the next preview (sixel's colours,
    /// kitty's and iTerm2's bytes per pixel).
    fn whole_picture(
        &mut self,
        frame: &PixelFrame,
        format: Format,
        area: Rect,
        passthrough: bool,
    ) -> io::Result<Vec<u8>> {
        let whole = whole_bytes(&mut self.kept, format, area, passthrough)?;
        match (frame.preview, frame.throughput) {
            (None, _) => self.last_whole = Some((area, format, whole.len())),
            (Some(_), Some(t)) if format == Format::Sixels => {
                self.preview_colours =
                    next_preview_colours(self.preview_colours, whole.len(), t / PREVIEW_RATE);
            }
            (Some(p), _) if format != Format::Sixels => {
                let pixels = (p.width() * p.height()).max(1) as f64;
                self.preview_density = Some((format, whole.len() as f64 / pixels));
            }
            _ => {}
        }
        Ok(whole)
    }

    /// An exact frame of `exact_len` bytes the link cannot carry in
    /// [`LINK_SECONDS`] (its `budget`): a link-sized picture now, over the
    /// open cells, and the exact one's strips to follow.
    fn send_link_sized(
        &mut self,
        frame: &PixelFrame,
        (exact_len, budget): (usize, f64),
        shown: &mut Shown,
        open: &[Rect],
        out: &mut Vec<u8>,
    ) -> io::Result<()> {
        let (mut first, bytes) = link_picture(
            frame.fb,
            shown.format,
            shown.area,
            exact_len,
            budget,
            frame.look.dither,
            shown.passthrough,
        )?;
        shown.image = first.size();
        if shown.covered.contains(&true) {
            out.extend(over_cells(&mut first, shown, open)?);
        } else {
            out.extend(bytes);
        }
        // Strips of about what the link carries in a
        // preview's frame interval.
        let n = strip_count(exact_len as f64, budget / LINK_SECONDS);
        shown.pending = super::cell_rects::strips(shown.area, n).into();
        if frame.throughput.is_none() {
            shown.recut = Some(exact_len);
        }
        self.split_bytes = Some(exact_len as u64);
        Ok(())
    }

    /// The same picture under other cells: kitty's placements replaced,
    /// sixel and iTerm2 sending the cells a panel left; nothing when the
    /// cells covered are the same.
    fn uncover_cells(
        &mut self,
        frame: &PixelFrame,
        area: Rect,
        covered: Vec<bool>,
    ) -> io::Result<Vec<u8>> {
        let format = frame.output.format();
        let passthrough = frame.output.choice.passthrough;
        let mut out = Vec::new();
        let Some(shown) = self.shown.as_mut() else {
            return Ok(out);
        };
        if shown.covered == covered {
            return Ok(out);
        }
        if format == Format::Kitty {
            let open = rectangles(&covered, area, false);
            for layer in shown.layers() {
                push_kitty(&kitty::delete_placements(layer.id), passthrough, &mut out);
                out.extend(kitty_placements(layer, &open, passthrough)?);
            }
        } else {
            // Cells a panel left: the picture again over them.
            let left: Vec<bool> = shown
                .covered
                .iter()
                .zip(&covered)
                .map(|(&was, &now)| was && !now)
                .collect();
            for r in rectangles(&left, area, true) {
                let seq = self.kept.part(area, shown.cell, r)?;
                if !seq.is_empty() {
                    out.extend(placed(&seq, format, r, passthrough));
                }
            }
        }
        shown.covered = covered;
        Ok(out)
    }

    /// The pixels of one cell of a sixel image over `area`: the image's own
    /// when it fills the area's cells exactly (the usual case), else (a
    /// frame scaled down within [`MAX_PIXELS`]) the terminal's cell size.
    fn image_cell(&self, frame: &PixelFrame, area: Rect, image: (usize, usize)) -> (usize, usize) {
        let (cols, rows) = (usize::from(area.width), usize::from(area.height));
        if image.0.is_multiple_of(cols) && image.1.is_multiple_of(rows) {
            (image.0 / cols, image.1 / rows)
        } else {
            let (c, _) = cell_pixels(window_size(), frame.output.cell_reply);
            (usize::from(c.0.max(1)), usize::from(c.1.max(1)))
        }
    }

    /// The picture as text over all of `viewport` when its image covers
    /// only `area` of it, into `self.small`: `fb` box-filtered to `area`'s
    /// text pixels, the rest of the viewport the background.
    fn text_around(&mut self, fb: &Framebuffer, viewport: Rect, area: Rect, look: TextLook) {
        let (cols, rows) = (look.symbols.columns(), look.symbols.rows());
        let cells = |r: Rect| (usize::from(r.width) * cols, usize::from(r.height) * rows);
        let (w, h) = cells(viewport);
        self.small.resize(w, h);
        self.small.fill(look.pad);
        let (pw, ph) = cells(area);
        let mut part = Framebuffer::new(pw, ph);
        downscale(fb, &mut part);
        let x0 = usize::from(area.x - viewport.x) * cols;
        let y0 = usize::from(area.y - viewport.y) * rows;
        for y in 0..ph {
            for (x, &p) in part.row(y).iter().enumerate() {
                self.small.set(x0 + x, y0 + y, p);
            }
        }
    }

    /// Strips of the exact frame are still to be sent.
    pub fn pending(&self) -> bool {
        self.shown.as_ref().is_some_and(|s| !s.pending.is_empty())
    }

    /// The next strip of the exact frame (one write of its own), over the
    /// cells of it no panel covers: kitty sends it as an image of its own
    /// placed over them, sixel and iTerm2 send their rectangles of it.
    /// Strips cut before the link was measured are cut again for its
    /// `throughput` once there is one.
    pub fn next_strip(&mut self, throughput: Option<f64>) -> io::Result<Option<Vec<u8>>> {
        let Some(shown) = self.shown.as_mut() else {
            return Ok(None);
        };
        if let (Some(exact), Some(t)) = (shown.recut, throughput) {
            shown.recut = None;
            shown.pending = recut(&shown.pending, shown.area, exact, t).into();
        }
        let Some(strip) = shown.pending.pop_front() else {
            return Ok(None);
        };
        let open = within(&rectangles(&shown.covered, shown.area, false), strip);
        let mut out = Vec::new();
        match &mut self.kept {
            Kept::Rgb(fb) if shown.format == Format::Kitty => {
                let size = (fb.width(), fb.height());
                let pixels = crop(fb, source_rect(size, shown.area, strip));
                let layer = Layer {
                    id: kitty::strip_id(shown.strips.len()),
                    z: kitty::STRIP_Z,
                    cells: strip,
                    image: (pixels.width(), pixels.height()),
                };
                let mut seq = Vec::new();
                kitty::write_data(&pixels, layer.id, &mut seq)?;
                push_kitty(&seq, shown.passthrough, &mut out);
                out.extend(kitty_placements(layer, &open, shown.passthrough)?);
                shown.strips.push(layer);
                set_cleanup(&shown.kitty_cleanup());
            }
            kept => {
                for r in open {
                    let seq = kept.part(shown.area, shown.cell, r)?;
                    if !seq.is_empty() {
                        out.extend(placed(&seq, shown.format, r, shown.passthrough));
                    }
                }
            }
        }
        // Once all are sent without a panel, what the exact image took.
        shown.strip_bytes += out.len();
        if shown.pending.is_empty() && !shown.covered.contains(&true) {
            self.last_whole = Some((shown.area, shown.format, shown.strip_bytes));
        }
        Ok(Some(out))
    }

    /// Bytes of the whole exact image just sent in strips, once: what an
    /// exact frame costs the link, though its first write was the
    /// link-sized picture.
    pub fn take_split_bytes(&mut self) -> Option<u64> {
        self.split_bytes.take()
    }

    /// The screen is new (after Ctrl-Z): nothing of ours is on it.
    pub fn forget(&mut self) {
        self.shown = None;
        set_cleanup(&[]);
    }

    /// Where an image is shown, if one is.
    pub fn shown(&self) -> Option<(Rect, Format)> {
        self.shown.as_ref().map(|s| (s.area, s.format))
    }
}

/// The strips `pending` of an exact image of `exact` bytes over `area` cut
/// again for a link of `throughput` bytes a second: the rows they cover,
/// in [`strip_count`] strips of their share of the bytes.
fn recut(pending: &VecDeque<Rect>, area: Rect, exact: usize, throughput: f64) -> Vec<Rect> {
    let (Some(first), Some(last)) = (pending.front(), pending.back()) else {
        return Vec::new();
    };
    let rest = Rect::new(area.x, first.y, area.width, last.bottom() - first.y);
    let share = f64::from(rest.height) / f64::from(area.height.max(1));
    super::cell_rects::strips(rest, strip_count(exact as f64 * share, throughput))
}

/// Whether the exact frame can follow `shown` in strips: kitty and iTerm2
/// stretch a strip over its rows; sixel draws its own pixels, so its cells
/// must be whole pixels of the image (not a frame scaled down within
/// [`MAX_PIXELS`]).
fn strips_fit(shown: &Shown) -> bool {
    let (cols, rows) = (
        usize::from(shown.area.width),
        usize::from(shown.area.height),
    );
    match shown.format {
        Format::Kitty | Format::Iterm => true,
        Format::Sixels => shown.image == (cols * shown.cell.0, rows * shown.cell.1),
        Format::Auto | Format::Symbols => false,
    }
}

/// The bytes that show `pic` (kept for `shown`'s format) over the cells
/// `open` of `shown`'s area only: kitty sends it once, without showing it,
/// and places it over each; sixel and iTerm2 send each rectangle of it.
fn over_cells(pic: &mut Kept, shown: &Shown, open: &[Rect]) -> io::Result<Vec<u8>> {
    let mut out = Vec::new();
    match (&*pic, shown.format) {
        (Kept::Rgb(fb), Format::Kitty) => {
            let mut seq = Vec::new();
            kitty::write_data(fb, kitty::IMAGE_ID, &mut seq)?;
            push_kitty(&seq, shown.passthrough, &mut out);
            let picture = Layer {
                id: kitty::IMAGE_ID,
                z: 0,
                cells: shown.area,
                image: (fb.width(), fb.height()),
            };
            out.extend(kitty_placements(picture, open, shown.passthrough)?);
        }
        _ => {
            for r in open {
                let seq = pic.part(shown.area, shown.cell, *r)?;
                if !seq.is_empty() {
                    out.extend(placed(&seq, shown.format, *r, shown.passthrough));
                }
            }
        }
    }
    Ok(out)
}

/// kitty placements of `layer` over the cells `open` within it, each
/// placed at its top-left cell.
fn kitty_placements(layer: Layer, open: &[Rect], passthrough: bool) -> io::Result<Vec<u8>> {
    let mut out = Vec::new();
    for (r, seq) in super::cell_rects::kitty_layer(layer, open)? {
        place(r, &mut out);
        push_kitty(&seq, passthrough, &mut out);
    }
    Ok(out)
}

/// Marks the cells of the image's `area` in `buf` that still hold the
/// picture's text (`fb` drawn over `viewport`; nothing drawn over them) as
/// skipped by the diff, so the image there stays; returns the others,
/// drawn over (true), row by row.
fn skip_picture(
    buf: &mut Buffer,
    viewport: Rect,
    area: Rect,
    fb: &Framebuffer,
    look: TextLook,
) -> Vec<bool> {
    // Cells outside the frame's buffer count as drawn over.
    let inside = area.intersection(buf.area);
    let mut text = Buffer::empty(viewport);
    SymbolCells {
        fb,
        symbols: look.symbols,
        depth: look.depth,
        dither: look.dither,
        pad: look.pad,
    }
    .render(viewport, &mut text);
    let mut covered = Vec::with_capacity(area.area() as usize);
    for y in area.top()..area.bottom() {
        for x in area.left()..area.right() {
            if !inside.contains((x, y).into()) {
                covered.push(true);
                continue;
            }
            let over = buf[(x, y)] != text[(x, y)];
            if !over {
                buf[(x, y)].set_diff_option(ratatui::buffer::CellDiffOption::Skip);
            }
            covered.push(over);
        }
    }
    covered
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_picture_area_past_the_buffer_counts_as_drawn_over() {
        let mut buf = Buffer::empty(Rect::new(0, 0, 10, 5));
        let look = TextLook {
            symbols: Symbols::Half,
            depth: ColorDepth::Truecolor,
            dither: false,
            pad: [0, 0, 0],
        };
        let mut fb = Framebuffer::new(20, 20);
        fb.fill([90, 120, 30]);
        // The picture as the view draws it: clipped to the buffer.
        SymbolCells {
            fb: &fb,
            symbols: look.symbols,
            depth: look.depth,
            dither: look.dither,
            pad: look.pad,
        }
        .render(Rect::new(0, 0, 20, 10), &mut buf);
        let covered = skip_picture(
            &mut buf,
            Rect::new(0, 0, 20, 10),
            Rect::new(0, 0, 20, 10),
            &fb,
            look,
        );
        assert_eq!(covered.len(), 200);
        for (i, &c) in covered.iter().enumerate() {
            let (x, y) = (i % 20, i / 20);
            assert_eq!(c, x >= 10 || y >= 5, "{x},{y}");
        }
    }

    #[test]
    fn the_cell_size_comes_from_the_window_then_the_reply_then_the_default() {
        assert_eq!(
            cell_pixels(Some((80, 24, 800, 480)), Some((9, 18))),
            ((10, 20), "window size")
        );
        // No pixel fields (many terminals over SSH, tmux): the reply.
        assert_eq!(
            cell_pixels(Some((80, 24, 0, 0)), Some((9, 18))),
            ((9, 18), "CSI 16 t")
        );
        assert_eq!(cell_pixels(None, None), (DEFAULT_CELL, "default"));
    }

    fn sixels(sixel_max: Option<(u32, u32)>) -> Output {
        let clues = super::super::format::Clues {
            forced: Some((Format::Sixels, "--format")),
            ..Default::default()
        };
        Output {
            sixel_max,
            ..Output::from_clues(&clues, None)
        }
    }

    #[test]
    fn a_sixel_picture_takes_the_most_whole_cells_within_the_largest_image() {
        // xterm at font size 8 full screen: 160 × 46 cells of 8 × 13 pixels
        // (1280 × 598) against 1000 × 1000: 125 columns, centred.
        let viewport = Rect::new(0, 0, 160, 46);
        let capped = sixels(Some((1000, 1000)));
        let a = picture_area(&capped, viewport, (8, 13));
        assert_eq!(a, Rect::new(17, 0, 125, 46));
        // Rows: the last band of six counts whole: 10 rows of 13 are 130
        // pixels, drawn in 22 bands (132): 131 takes 9 rows, 132 ten.
        let short = Rect::new(2, 1, 20, 12);
        let rows = |h| picture_area(&sixels(Some((1000, h))), short, (8, 13));
        assert_eq!(rows(131), Rect::new(2, 2, 20, 9));
        assert_eq!(rows(132), Rect::new(2, 2, 20, 10));
        // Not one cell fits: nothing (the view then draws text).
        assert!(picture_area(&sixels(Some((7, 1000))), viewport, (8, 13)).is_empty());
        assert!(PixelView::image_area(&sixels(Some((0, 0))), viewport, 48).is_none());
        // No answer, a limit that does not bind, or another format: all of it.
        assert_eq!(picture_area(&sixels(None), viewport, (8, 13)), viewport);
        assert_eq!(
            picture_area(&sixels(Some((4096, 4096))), viewport, (8, 13)),
            viewport
        );
        let mut kitty = capped.clone();
        kitty.wanted = Format::Kitty;
        kitty.choice.format = Format::Kitty;
        assert_eq!(picture_area(&kitty, viewport, (8, 13)), viewport);
        // What the cost panel says.
        assert_eq!(
            sixel_limit_line(&capped, viewport, (8, 13)).as_deref(),
            Some("max 1000×1000 px: 125×46 of 160×46 cells")
        );
        assert_eq!(
            sixel_limit_line(&capped, Rect::new(0, 0, 100, 40), (8, 13)).as_deref(),
            Some("max 1000×1000 px: the whole area")
        );
        assert_eq!(sixel_limit_line(&sixels(None), viewport, (8, 13)), None);
        assert_eq!(sixel_limit_line(&kitty, viewport, (8, 13)), None);
    }

    #[test]
    fn a_huge_frame_is_scaled_down_evenly_within_the_cap() {
        assert_eq!(frame_size(100, 40, (10, 20)), (1000, 800));
        let (w, h) = frame_size(1024, 512, (200, 400));
        assert!(w * h <= MAX_PIXELS, "{w}×{h}");
        // Square pixels: the aspect of 204800 × 204800 stays 1.
        assert!(w.abs_diff(h) <= 1, "{w}×{h}");
        assert!(w * h > MAX_PIXELS * 99 / 100);
    }

    #[test]
    fn sixel_preview_colours_follow_their_share_of_the_link() {
        // 35 kB previews for an 8.3 kB share: 32 → 16 → 8 → 4, no fewer.
        let share = 125_000.0 / PREVIEW_RATE;
        let mut c = SIXEL_PREVIEW_COLOURS;
        for want in [16, 8, 4, 4] {
            c = next_preview_colours(c, 35_000, share);
            assert_eq!(c, want);
        }
        // Within half to twice the share: kept; well under: doubled back.
        assert_eq!(next_preview_colours(8, 10_000, share), 8);
        assert_eq!(next_preview_colours(8, 3_000, share), 16);
        assert_eq!(next_preview_colours(32, 1_000, share), 32);
    }

    #[test]
    fn previews_shrink_with_the_link() {
        // Four times the bytes the link carries: half each way.
        assert_eq!(preview_size(800, 600, 400_000, 100_000.0), (400, 300));
        // Sixteen times: a quarter.
        assert_eq!(preview_size(800, 600, 1_600_000, 100_000.0), (200, 150));
        // Never below a sixteenth, never above half.
        assert_eq!(preview_size(800, 600, u64::MAX, 1.0), (50, 38));
        assert_eq!(preview_size(800, 600, 10, 1e9), (400, 300));
    }

    #[test]
    fn kitty_previews_are_sized_by_the_last_previews_bytes() {
        // 1 Mbit/s at 15 frames a second: an 8.3 kB share.
        let share = 125_000.0 / PREVIEW_RATE;
        let (w, h) = (1280, 736);
        // The exact frame's 1.27 bytes a pixel (1.2 MB) said 107 × 61;
        // previews that small took 1.8 a pixel: 11.7 kB, over the share.
        assert_eq!(preview_size(w, h, 1_200_000, share), (107, 61));
        let (pw, ph) = preview_size_measured(w, h, 1.8, share);
        // s = √(8333 / (1.8 × 942080)) = 0.0701: 89 × 51.
        assert_eq!((pw, ph), (89, 51));
        assert!((pw * ph) as f64 * 1.8 <= share);
        // Denser still: smaller, never below a sixteenth each way.
        assert_eq!(preview_size_measured(w, h, 2.5, share), (80, 46));
        assert_eq!(preview_size_measured(w, h, 1e9, share), (80, 46));
        // A fast link: at most half each way.
        assert_eq!(preview_size_measured(w, h, 1.8, 1e9), (640, 368));
    }

    #[test]
    fn strips_cut_before_the_link_was_measured_are_cut_again_for_it() {
        let area = Rect::new(0, 2, 60, 12);
        // Cut for the unmeasured 1 Mbit/s: 240 kB in 8.3 kB strips, one a row.
        let pending: VecDeque<Rect> =
            super::super::cell_rects::strips(area, strip_count(240_000.0, UNMEASURED_RATE)).into();
        assert_eq!(pending.len(), 12);
        // Two sent; the link carries 450 kB/s (30 kB a strip): the other
        // ten rows are 200 kB, seven strips; at 3 MB/s one.
        let rest: VecDeque<Rect> = pending.iter().skip(2).copied().collect();
        let cut = recut(&rest, area, 240_000, 450_000.0);
        assert_eq!(cut.len(), 7);
        let one = recut(&rest, area, 240_000, 3_000_000.0);
        assert_eq!(one, vec![Rect::new(0, 4, 60, 10)]);
        // The cut covers the same rows, in order.
        assert_eq!(cut.first().map(|r| r.y), Some(4));
        assert_eq!(cut.iter().map(|r| r.height).sum::<u16>(), 10);
        assert!(recut(&VecDeque::new(), area, 240_000, 1.0).is_empty());
    }

    #[test]
    fn downscale_averages_boxes() {
        let mut src = Framebuffer::new(4, 2);
        src.set(0, 0, [100, 0, 0]);
        src.set(1, 1, [0, 200, 0]);
        let mut dst = Framebuffer::new(2, 1);
        downscale(&src, &mut dst);
        assert_eq!(dst.get(0, 0), [25, 50, 0]);
        assert_eq!(dst.get(1, 0), [0, 0, 0]);
    }
}

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
//! The image goes to the picture area's top-left cell with an absolute
//! cursor move. It never scrolls the screen: the picture area ends two
//! rows above the bottom, and a screen too small for that gets text.
//! Inside tmux the sequences go through tmux's passthrough (`DCS tmux;`
//! with every `ESC` doubled). The image is deleted (kitty `a=d,d=I`, sixel
//! and iTerm2 cells cleared) on exit, on Ctrl-Z and when leaving pixels; the
//! terminal guard calls [`take_cleanup`] for the first two.

use std::io::{self, Write};
use std::sync::Mutex;

use ratatui::Terminal;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::widgets::Widget;

use super::backend::SgrBackend;
use super::cells::SymbolCells;
use super::color::ColorDepth;
use super::format::{Format, FormatChoice, TmuxPixels};
use super::symbols::Symbols;
use super::{iterm, kitty, sixel};
use crate::framebuffer::{Framebuffer, Rgb};

/// Cell size in pixels when neither the kernel (`TIOCGWINSZ`) nor the
/// terminal (`CSI 16 t`) says: a common 8×16 font.
pub const DEFAULT_CELL: (u16, u16) = (8, 16);

/// Most pixels of one frame: the frame buffer, its depth and the encoder's
/// copies take about 10 bytes a pixel (see [`crate::budget`]); 8 Mpx keep a
/// huge cell size (or a huge window) within a tenth of the budget.
pub const MAX_PIXELS: usize =
    (crate::budget::BUDGET_BYTES / 10 / (crate::budget::FRAME_BYTES_PER_PIXEL + 3)) as usize;

/// Smallest preview scale while input keeps coming: one pixel in eight
/// each way.
pub const MIN_PREVIEW_SCALE: f64 = 0.125;

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
    let mut out = Vec::with_capacity(seq.len() + 16);
    place(area, &mut out);
    if !passthrough {
        out.extend_from_slice(&seq);
    } else if format == Format::Kitty {
        push_kitty(&seq, true, &mut out);
    } else {
        wrap_tmux(&seq, &mut out);
    }
    Ok(out)
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
    /// placements cut from; a preview is smaller than the frame).
    image: (usize, usize),
    /// The area's cells drawn as text over the image (a panel), row by row.
    covered: Vec<bool>,
}

/// The pixel side of the view between frames: what is on screen.
pub struct PixelView {
    /// The picture at the text's resolution.
    small: Framebuffer,
    /// The image on screen, if any.
    shown: Option<Shown>,
    /// The format of the last frame.
    last_format: Option<Format>,
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
            last_format: None,
        }
    }

    /// True when `format` can show on a screen of `screen` with the picture
    /// in `viewport`: a pixel format, and the picture clear of the last row
    /// (an image reaching it would scroll).
    pub fn usable(format: Format, viewport: Rect, screen_height: u16) -> bool {
        format.is_pixels() && !viewport.is_empty() && viewport.bottom() < screen_height
    }

    /// The framebuffer size for the picture in `viewport`: the text's
    /// pixels, or for a pixel format the cells' pixels.
    pub fn framebuffer_size(
        output: &Output,
        viewport: Rect,
        screen_height: u16,
        symbols: Symbols,
    ) -> (usize, usize) {
        if Self::usable(output.format(), viewport, screen_height) {
            let (cell, _) = cell_pixels(window_size(), output.cell_reply);
            frame_size(viewport.width, viewport.height, cell)
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
        let pixels = Self::usable(format, viewport, screen.height);
        let fb = frame.fb;
        let text_size = (
            usize::from(viewport.width) * frame.look.symbols.columns(),
            usize::from(viewport.height) * frame.look.symbols.rows(),
        );
        let text_fb = if pixels && (fb.width(), fb.height()) != text_size {
            self.small.resize(text_size.0, text_size.1);
            downscale(fb, &mut self.small);
            &self.small
        } else {
            fb
        };
        let passthrough = frame.output.choice.passthrough;
        if self.last_format.is_some_and(|f| f != format) {
            // A new format: the whole screen is drawn again, so nothing a
            // terminal made of the last one's sequences (a format it
            // ignores may print its bytes, even scroll) stays.
            if self.shown.take().is_some_and(|s| s.format == Format::Kitty) {
                terminal
                    .backend_mut()
                    .write_raw(&kitty_delete(passthrough))?;
                set_cleanup(&[]);
            }
            terminal.clear()?;
        }
        self.last_format = Some(format);
        let mut covered = None;
        terminal.draw(|f| {
            view(f, text_fb);
            if pixels {
                covered = Some(skip_picture(f.buffer_mut(), viewport, text_fb, frame.look));
            }
        })?;
        let bytes = match covered {
            Some(covered) => self.image_update(&frame, viewport, covered)?,
            None => {
                // Text only: kitty's image is deleted; sixel and iTerm2
                // pixels are covered by the text cells drawn meanwhile.
                match self.shown.take() {
                    Some(s) => {
                        set_cleanup(&[]);
                        if s.format == Format::Kitty {
                            kitty_delete(passthrough)
                        } else {
                            Vec::new()
                        }
                    }
                    None => Vec::new(),
                }
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
    /// - a new picture, area or format: the image is sent; kitty shows the
    ///   uncovered cells as placements of it, sixel and iTerm2 are sent
    ///   only over the uncovered cells (the panel's text stays);
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
        let passthrough = frame.output.choice.passthrough;
        let same_place = self
            .shown
            .as_ref()
            .is_some_and(|s| s.area == area && s.format == format);
        let mut out = Vec::new();
        let open = rectangles(&covered, area, false);
        if frame.new_picture || !same_place {
            let send = match (format, frame.preview) {
                (Format::Kitty | Format::Iterm, Some(p)) => p,
                _ => frame.fb,
            };
            let image = (send.width(), send.height());
            let had_parts = self
                .shown
                .as_ref()
                .is_some_and(|s| s.format == Format::Kitty && s.covered.contains(&true));
            if format == Format::Kitty && (had_parts || covered.contains(&true)) {
                // The placements of the last image go first (kitty drops
                // them with the image it replaces; said for any terminal).
                push_kitty(kitty::DELETE_PLACEMENTS, passthrough, &mut out);
            }
            if !covered.contains(&true) {
                out.extend(image_bytes(
                    send,
                    format,
                    area,
                    frame.look.dither,
                    passthrough,
                )?);
            } else if format == Format::Kitty {
                let mut seq = Vec::new();
                kitty::write_data(send, &mut seq)?;
                push_kitty(&seq, passthrough, &mut out);
                kitty_placements(&open, area, image, passthrough, &mut out)?;
            } else {
                let cell = self.image_cell(frame, area, image);
                for r in &open {
                    part_bytes(
                        send,
                        format,
                        area,
                        cell,
                        *r,
                        frame.look.dither,
                        passthrough,
                        &mut out,
                    )?;
                }
            }
            set_cleanup(&if format == Format::Kitty {
                kitty_delete(passthrough)
            } else {
                Vec::new()
            });
            self.shown = Some(Shown {
                area,
                format,
                image,
                covered,
            });
            return Ok(out);
        }
        let Some(shown) = self.shown.as_mut() else {
            return Ok(out);
        };
        if shown.covered == covered {
            return Ok(out);
        }
        if format == Format::Kitty {
            push_kitty(kitty::DELETE_PLACEMENTS, passthrough, &mut out);
            kitty_placements(&open, area, shown.image, passthrough, &mut out)?;
        } else {
            // Cells a panel left: the picture again over them.
            let left: Vec<bool> = shown
                .covered
                .iter()
                .zip(&covered)
                .map(|(&was, &now)| was && !now)
                .collect();
            let image = shown.image;
            let cell = self.image_cell(frame, area, image);
            for r in rectangles(&left, area, true) {
                part_bytes(
                    frame.fb,
                    format,
                    area,
                    cell,
                    r,
                    frame.look.dither,
                    passthrough,
                    &mut out,
                )?;
            }
        }
        if let Some(shown) = self.shown.as_mut() {
            shown.covered = covered;
        }
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

/// Exact tiling of the cells of `area` whose flag in `cells` (row by row)
/// is `which`, by rectangles: each row's runs, a run extending the
/// rectangle above it when it spans the same columns. A panel over the
/// picture leaves at most four.
pub fn rectangles(cells: &[bool], area: Rect, which: bool) -> Vec<Rect> {
    let (w, h) = (usize::from(area.width), usize::from(area.height));
    let mut done = Vec::new();
    // Rectangles reaching the row above.
    let mut open: Vec<Rect> = Vec::new();
    for y in 0..h {
        let row = &cells[y * w..(y + 1) * w];
        let mut next = Vec::new();
        let mut x = 0;
        while x < w {
            if row[x] != which {
                x += 1;
                continue;
            }
            let start = x;
            while x < w && row[x] == which {
                x += 1;
            }
            let (left, width) = (area.x + start as u16, (x - start) as u16);
            match open.iter().position(|r| r.x == left && r.width == width) {
                Some(i) => {
                    let mut r = open.swap_remove(i);
                    r.height += 1;
                    next.push(r);
                }
                None => next.push(Rect::new(left, area.y + y as u16, width, 1)),
            }
        }
        done.append(&mut open);
        open = next;
    }
    done.append(&mut open);
    done.sort_by_key(|r| (r.y, r.x));
    done
}

/// The pixels of an `image` stretched over `area` under the cells `r`:
/// left, top, width, height (at least one pixel each way, within the
/// image; neighbouring cells share their edges, so a tiling of cells is a
/// tiling of pixels).
pub fn source_rect(image: (usize, usize), area: Rect, r: Rect) -> kitty::Source {
    let (w, h) = (image.0.max(1), image.1.max(1));
    let (cols, rows) = (
        usize::from(area.width.max(1)),
        usize::from(area.height.max(1)),
    );
    let edge = |cell: u16, origin: u16, cells: usize, size: usize| {
        (usize::from(cell - origin) * size / cells).min(size - 1)
    };
    let x0 = edge(r.x, area.x, cols, w);
    let y0 = edge(r.y, area.y, rows, h);
    let x1 = (usize::from(r.right() - area.x) * w / cols).max(x0 + 1);
    let y1 = (usize::from(r.bottom() - area.y) * h / rows).max(y0 + 1);
    [x0, y0, x1 - x0, y1 - y0]
}

/// kitty placements of the image (of `image` pixels, stretched over
/// `area`) over the cells `open`, numbered from 1: the whole image as one
/// placement when nothing is covered.
fn kitty_placements(
    open: &[Rect],
    area: Rect,
    image: (usize, usize),
    passthrough: bool,
    out: &mut Vec<u8>,
) -> io::Result<()> {
    for (i, r) in open.iter().enumerate() {
        let mut seq = Vec::new();
        kitty::write_placement(
            i as u32 + 1,
            source_rect(image, area, *r),
            (r.width, r.height),
            &mut seq,
        )?;
        place(*r, out);
        push_kitty(&seq, passthrough, out);
    }
    Ok(())
}

/// The part of `fb` under the cells `r` as its own sixel or iTerm2 image
/// placed at `r`'s top-left cell: sixel at its own pixels (`cell` pixels a
/// cell, clipped to the image), iTerm2 stretched over `r`'s cells.
#[allow(clippy::too_many_arguments)]
fn part_bytes(
    fb: &Framebuffer,
    format: Format,
    area: Rect,
    cell: (usize, usize),
    r: Rect,
    dither: bool,
    passthrough: bool,
    out: &mut Vec<u8>,
) -> io::Result<()> {
    let [x, y, w, h] = match format {
        Format::Sixels => {
            let x0 = (usize::from(r.x - area.x) * cell.0).min(fb.width());
            let y0 = (usize::from(r.y - area.y) * cell.1).min(fb.height());
            let x1 = (usize::from(r.right() - area.x) * cell.0).min(fb.width());
            let y1 = (usize::from(r.bottom() - area.y) * cell.1).min(fb.height());
            [x0, y0, x1 - x0, y1 - y0]
        }
        _ => source_rect((fb.width(), fb.height()), area, r),
    };
    if w == 0 || h == 0 {
        return Ok(());
    }
    let mut part = Framebuffer::new(w, h);
    for row in 0..h {
        part.pixels_mut()[row * w..(row + 1) * w].copy_from_slice(&fb.row(y + row)[x..x + w]);
    }
    out.extend(image_bytes(&part, format, r, dither, passthrough)?);
    Ok(())
}

/// Marks the picture's cells in `buf` that still hold the picture's text
/// (nothing drawn over them) as skipped by the diff, so the image there
/// stays; returns the others, drawn over (true), row by row.
fn skip_picture(buf: &mut Buffer, viewport: Rect, fb: &Framebuffer, look: TextLook) -> Vec<bool> {
    let mut text = Buffer::empty(viewport);
    SymbolCells {
        fb,
        symbols: look.symbols,
        depth: look.depth,
        dither: look.dither,
        pad: look.pad,
    }
    .render(viewport, &mut text);
    let mut covered = Vec::with_capacity(viewport.area() as usize);
    for y in viewport.top()..viewport.bottom() {
        for x in viewport.left()..viewport.right() {
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
    fn previews_shrink_with_the_link() {
        // Four times the bytes the link carries: half each way.
        assert_eq!(preview_size(800, 600, 400_000, 100_000.0), (400, 300));
        // Sixteen times: a quarter.
        assert_eq!(preview_size(800, 600, 1_600_000, 100_000.0), (200, 150));
        // Never below an eighth, never above half.
        assert_eq!(preview_size(800, 600, u64::MAX, 1.0), (100, 75));
        assert_eq!(preview_size(800, 600, 10, 1e9), (400, 300));
    }

    /// The cells of `area` (row by row) inside any of `panels`.
    fn mask(area: Rect, panels: &[Rect]) -> Vec<bool> {
        let mut m = Vec::new();
        for y in area.top()..area.bottom() {
            for x in area.left()..area.right() {
                m.push(panels.iter().any(|p| p.contains((x, y).into())));
            }
        }
        m
    }

    #[test]
    fn rectangles_tile_exactly_the_cells_asked_for() {
        let area = Rect::new(2, 1, 20, 10);
        // A centred panel: the band above, left, right and the band below.
        let help = Rect::new(7, 4, 8, 3);
        let m = mask(area, &[help]);
        let open = rectangles(&m, area, false);
        assert_eq!(
            open,
            vec![
                Rect::new(2, 1, 20, 3),
                Rect::new(2, 4, 5, 3),
                Rect::new(15, 4, 7, 3),
                Rect::new(2, 7, 20, 4),
            ]
        );
        assert_eq!(rectangles(&m, area, true), vec![help]);
        // Two panels, one at a corner and one overlapping it: every cell
        // of the area once, in a rectangle of its own kind.
        let panels = [Rect::new(10, 1, 12, 5), Rect::new(4, 3, 9, 6)];
        let m = mask(area, &panels);
        let mut seen = vec![0; m.len()];
        for which in [false, true] {
            for r in rectangles(&m, area, which) {
                for y in r.top()..r.bottom() {
                    for x in r.left()..r.right() {
                        let i = usize::from(y - area.y) * 20 + usize::from(x - area.x);
                        assert_eq!(m[i], which, "{r:?}");
                        seen[i] += 1;
                    }
                }
            }
        }
        assert!(seen.iter().all(|&n| n == 1));
        assert!(rectangles(&[false; 200], area, true).is_empty());
        assert_eq!(rectangles(&[false; 200], area, false), vec![area]);
    }

    #[test]
    fn source_rectangles_follow_the_cells_and_share_their_edges() {
        let area = Rect::new(0, 0, 60, 12);
        // 8×16 pixels a cell: whole cells of pixels.
        assert_eq!(
            source_rect((480, 192), area, Rect::new(16, 2, 44, 10)),
            [128, 32, 352, 160]
        );
        // A preview of 100 × 30 pixels stretched over the cells: edges at
        // ⌊cell · 100 / 60⌋ and ⌊cell · 30 / 12⌋; neighbours meet.
        let left = source_rect((100, 30), area, Rect::new(0, 0, 16, 12));
        let right = source_rect((100, 30), area, Rect::new(16, 0, 44, 5));
        let below = source_rect((100, 30), area, Rect::new(16, 5, 44, 7));
        assert_eq!(left, [0, 0, 26, 30]);
        assert_eq!(right, [26, 0, 74, 12]);
        assert_eq!(below, [26, 12, 74, 18]);
        // Never empty (kitty reads a width of 0 as the whole image).
        assert_eq!(
            source_rect((30, 6), area, Rect::new(1, 1, 1, 1)),
            [0, 0, 1, 1]
        );
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

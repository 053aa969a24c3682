//! When the event loop draws, and what: the scheduling decisions apart from
//! the terminal, so they are tested with a clock the tests drive.
//!
//! Between frames the loop asks [`Schedule::wait`] how long it may block
//! for input; after applying what came, [`Schedule::next`] says whether a
//! frame goes now and what kind (an auto-rotation step first, a status-only
//! refresh, a preview or the exact picture). Frames in flight and the hold
//! on a slow link live in the [`Pacer`]; input that arrives meanwhile only
//! marks the picture dirty, so when the next frame may go it shows the
//! newest state and the frames in between are dropped.

use std::time::{Duration, Instant};

use relief_term::pacing::{Activity, Pacer};

/// Auto-rotation frame pacing.
pub const FRAME_INTERVAL: Duration = Duration::from_millis(33);

/// While a model loads, its progress is shown this often (a status line
/// of a few hundred bytes: four a second cost nothing over SSH).
pub const PROGRESS_INTERVAL: Duration = Duration::from_millis(250);

/// What the loop waits for before it looks again.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wait {
    /// The status line's refresh follows its picture at once (a few hundred
    /// bytes, not waiting for the picture to be shown).
    Refresh,
    /// A frame is in flight: its reply, or the time-out (`None`: no
    /// time-out applies).
    Reply(Option<Instant>),
    /// The reply is in but the link is not free yet (the SSH connection's
    /// send queue, or a stated rate): look again then.
    Held(Instant),
    /// A new picture is due now.
    Due,
    /// A preview is on screen: the exact picture once input stops.
    Refine(Instant),
    /// The next auto-rotation step.
    Rotate(Instant),
    /// The next refresh of a load's progress on the status line.
    Progress(Instant),
    /// Nothing to draw until input comes.
    Idle,
}

impl Wait {
    /// Until when the loop may block for input (`None`: for good).
    pub fn until(self, now: Instant) -> Option<Instant> {
        match self {
            Wait::Refresh | Wait::Due => Some(now),
            Wait::Reply(at) => at,
            Wait::Held(at) | Wait::Refine(at) | Wait::Rotate(at) | Wait::Progress(at) => Some(at),
            Wait::Idle => None,
        }
    }
}

/// A frame to draw now.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Auto-rotation advances by this many seconds first.
    pub tick: Option<f32>,
    /// Only the text changes (the status line's refresh after a picture).
    pub status_only: bool,
    /// A half-resolution preview instead of the exact picture (input keeps
    /// coming over a link too slow for the exact one).
    pub preview: bool,
    /// The next strip of the exact picture (nothing is rendered or drawn
    /// again: the strip is the write).
    pub strip: bool,
}

/// The scheduling state (see the module notes).
#[derive(Clone, Debug)]
pub struct Schedule {
    /// The state changed since the last picture.
    dirty: bool,
    /// After a new exact picture, one more (text-only) write lets the status
    /// line show that picture's own time and bytes; skipped while
    /// auto-rotation draws anyway.
    refresh_status: bool,
    last_tick: Instant,
    /// Whether input keeps coming (previews) or has stopped (refine).
    activity: Activity,
    /// How long without input counts as stopped (the pacer's, as of the
    /// last wait).
    quiet: Duration,
    /// The picture on screen is a preview: the exact one is due once input
    /// stops.
    previewing: bool,
    /// Bytes of the last exact picture: what the link must carry.
    exact_bytes: Option<u64>,
    /// The first query (the probe) went out.
    probed: bool,
    /// While a model loads: when the status line next shows its progress.
    progress_at: Option<Instant>,
    /// Strips of the exact picture wait to be sent, one per frame while
    /// nothing newer is due.
    strips: bool,
}

impl Schedule {
    /// A schedule whose first picture is due at once.
    pub fn new(now: Instant) -> Self {
        Schedule {
            dirty: true,
            refresh_status: false,
            last_tick: now,
            activity: Activity::default(),
            quiet: Duration::ZERO,
            previewing: false,
            exact_bytes: None,
            probed: false,
            progress_at: None,
            strips: false,
        }
    }

    /// Whether a model is loading at `now`: its progress is then shown
    /// every [`PROGRESS_INTERVAL`] while nothing else is drawn.
    pub fn loading(&mut self, under_way: bool, now: Instant) {
        match (under_way, self.progress_at) {
            (true, None) => self.progress_at = Some(now + PROGRESS_INTERVAL),
            (false, Some(_)) => self.progress_at = None,
            _ => {}
        }
    }

    /// What to wait for at `now` (the pacer applies its time-outs).
    pub fn wait(&mut self, pacer: &mut Pacer, continuous: bool, now: Instant) -> Wait {
        let wait = self.wait_for_frames(pacer, continuous, now);
        // A load's progress comes before a later frame, or instead of none.
        match (wait, self.progress_at) {
            (Wait::Idle, Some(at)) => Wait::Progress(at),
            (Wait::Refine(then) | Wait::Rotate(then), Some(at)) if at < then => Wait::Progress(at),
            _ => wait,
        }
    }

    /// [`Schedule::wait`] for the pictures and their figures alone.
    fn wait_for_frames(&mut self, pacer: &mut Pacer, continuous: bool, now: Instant) -> Wait {
        let ready = pacer.ready(now);
        self.quiet = pacer.quiet();
        if self.refresh_status && !self.dirty {
            Wait::Refresh
        } else if !ready {
            match (pacer.held(), pacer.deadline()) {
                (true, Some(at)) => Wait::Held(at),
                (_, at) => Wait::Reply(at),
            }
        } else if self.dirty || self.strips {
            Wait::Due
        } else if self.previewing && !continuous {
            Wait::Refine(self.activity.settled_at(self.quiet).unwrap_or(now))
        } else if continuous {
            Wait::Rotate(self.last_tick + FRAME_INTERVAL)
        } else {
            Wait::Idle
        }
    }

    /// Input changed the state at `at`.
    pub fn input(&mut self, at: Instant) {
        self.dirty = true;
        self.activity.input(at, self.quiet);
    }

    /// The picture must be drawn again (the screen was resized or cleared).
    pub fn redraw(&mut self) {
        self.dirty = true;
    }

    /// The frame to draw at `now`, if one is due and may go.
    pub fn next(&mut self, pacer: &mut Pacer, continuous: bool, now: Instant) -> Option<Frame> {
        let refresh_due = self.refresh_status && !self.dirty;
        if !refresh_due && !pacer.ready(now) {
            // A frame in flight: what came meanwhile waits for the next.
            return None;
        }
        let mut tick = None;
        if continuous {
            if now >= self.last_tick + FRAME_INTERVAL {
                tick = Some(now.duration_since(self.last_tick).as_secs_f32());
                self.last_tick = now;
                self.dirty = true;
            }
        } else {
            self.last_tick = now;
        }
        if self.previewing && !continuous && !self.activity.moving(now, self.quiet) {
            // Input stopped: the exact picture replaces the preview.
            self.dirty = true;
        }
        let progress_due = self.progress_at.is_some_and(|at| now >= at);
        if progress_due {
            self.progress_at = Some(now + PROGRESS_INTERVAL);
        }
        let status_only = (self.refresh_status || progress_due) && !self.dirty;
        self.refresh_status = false;
        if !self.dirty && !status_only {
            // Nothing newer: the exact picture's next strip, if any.
            return self.strips.then_some(Frame {
                tick: None,
                status_only: false,
                preview: false,
                strip: true,
            });
        }
        self.dirty = false;
        // While input keeps coming over a link too slow for the exact
        // picture at the frame rate, a cheaper one.
        let moving = continuous || self.activity.moving(now, self.quiet);
        let preview = pacer.preview(moving, self.exact_bytes, FRAME_INTERVAL);
        Some(Frame {
            tick,
            status_only,
            preview,
            strip: false,
        })
    }

    /// Whether strips of the exact picture wait to be sent (after each
    /// write: a new picture drops those of the last).
    pub fn set_strips(&mut self, pending: bool) {
        self.strips = pending;
    }

    /// Whether `frame` makes a new picture: what it shows changed (`!same`),
    /// or a preview is replaced by the exact picture. A new picture is then
    /// what is on screen.
    pub fn new_picture(&mut self, frame: &Frame, same: bool) -> bool {
        let new = !same || (self.previewing && !frame.preview);
        if new {
            self.previewing = frame.preview;
        }
        new
    }

    /// Bytes of the last exact picture, once one was written.
    pub fn exact_bytes(&self) -> Option<u64> {
        self.exact_bytes
    }

    /// The picture on screen is a preview.
    pub fn previewing(&self) -> bool {
        self.previewing
    }

    /// Whether this write starts with the probe (the first query, whose
    /// reply comes one round trip later whatever the frame's size).
    pub fn probe(&mut self, asks: bool) -> bool {
        let probe = asks && !self.probed;
        self.probed |= probe;
        probe
    }

    /// `frame` was written: `bytes`, a new picture or not.
    pub fn written(&mut self, frame: &Frame, new_picture: bool, bytes: u64, continuous: bool) {
        if frame.status_only || frame.strip {
            return;
        }
        if new_picture && !self.previewing {
            self.exact_bytes = Some(bytes);
        }
        self.refresh_status = new_picture && !self.previewing && !continuous;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_term::hold::{Hold, HoldBy};

    struct Clock(Instant);

    impl Clock {
        fn at(&self, ms: u64) -> Instant {
            self.0 + Duration::from_millis(ms)
        }
    }

    fn clock() -> Clock {
        Clock(Instant::now())
    }

    /// Draws `frame` as the loop does: a new picture unless `same`, written
    /// with `bytes` at `at` and its query.
    fn draw(s: &mut Schedule, p: &mut Pacer, f: Frame, same: bool, bytes: u64, at: Instant) {
        let new = s.new_picture(&f, same);
        let asks = p.asks();
        if s.probe(asks) {
            p.sent(at, 0, true);
        }
        p.sent(at, bytes, asks);
        s.written(&f, new, bytes, false);
    }

    const EXACT: Frame = Frame {
        tick: None,
        status_only: false,
        preview: false,
        strip: false,
    };

    #[test]
    fn first_picture_then_its_status_refresh_then_idle() {
        let c = clock();
        let mut p = Pacer::default();
        let mut s = Schedule::new(c.at(0));
        assert_eq!(s.wait(&mut p, false, c.at(0)), Wait::Due);
        assert_eq!(Wait::Due.until(c.at(0)), Some(c.at(0)));
        let f = s.next(&mut p, false, c.at(0)).unwrap();
        assert_eq!(f, EXACT);
        draw(&mut s, &mut p, f, false, 25_000, c.at(1));
        assert!(!s.probe(true), "one probe only");
        // The refresh goes at once, without waiting for the reply.
        assert_eq!(s.wait(&mut p, false, c.at(2)), Wait::Refresh);
        let r = s.next(&mut p, false, c.at(2)).unwrap();
        assert!(r.status_only && !r.preview);
        draw(&mut s, &mut p, r, true, 300, c.at(2));
        // Then the replies: the probe's, the frame's and the refresh's.
        assert_eq!(
            s.wait(&mut p, false, c.at(3)),
            Wait::Reply(Some(c.at(1001)))
        );
        assert_eq!(s.next(&mut p, false, c.at(3)), None);
        for t in [40, 240, 250] {
            p.reply(c.at(t));
        }
        assert_eq!(s.wait(&mut p, false, c.at(250)), Wait::Idle);
        assert_eq!(Wait::Idle.until(c.at(250)), None);
        assert_eq!(s.next(&mut p, false, c.at(250)), None);
    }

    #[test]
    fn input_during_a_frame_in_flight_is_folded_into_the_next() {
        let c = clock();
        let mut p = Pacer::default();
        let mut s = Schedule::new(c.at(0));
        s.wait(&mut p, false, c.at(0));
        let f = s.next(&mut p, false, c.at(0)).unwrap();
        draw(&mut s, &mut p, f, false, 25_000, c.at(0));
        p.reply(c.at(40));
        let r = s.next(&mut p, false, c.at(1)).unwrap();
        draw(&mut s, &mut p, r, true, 300, c.at(1));
        // Five keys while the frame is in flight: no frame until its reply.
        for t in 2..7 {
            s.wait(&mut p, false, c.at(t));
            s.input(c.at(t));
            assert_eq!(s.next(&mut p, false, c.at(t)), None);
        }
        assert!(matches!(
            s.wait(&mut p, false, c.at(7)),
            Wait::Reply(Some(_))
        ));
        p.reply(c.at(200));
        p.reply(c.at(201));
        assert_eq!(s.wait(&mut p, false, c.at(201)), Wait::Due);
        // One frame for all five; the link is not known to be slow yet.
        assert_eq!(s.next(&mut p, false, c.at(201)), Some(EXACT));
        assert_eq!(s.next(&mut p, false, c.at(202)), None);
    }

    /// A pacer that has seen a slow link: 40 ms round trip, 125 kB/s.
    fn slow(c: &Clock) -> Pacer {
        let mut p = Pacer::default();
        p.sent(c.at(0), 0, true);
        p.reply(c.at(40));
        p.sent(c.at(50), 25_000, true);
        p.reply(c.at(290));
        p
    }

    #[test]
    fn previews_while_input_keeps_coming_then_the_exact_picture() {
        let c = clock();
        let mut p = slow(&c);
        let mut s = Schedule::new(c.at(300));
        s.probe(true);
        s.wait(&mut p, false, c.at(300));
        let f = s.next(&mut p, false, c.at(300)).unwrap();
        assert!(!f.preview, "no exact picture measured yet");
        draw(&mut s, &mut p, f, false, 25_000, c.at(300));
        p.reply(c.at(540));
        let r = s.next(&mut p, false, c.at(541)).unwrap();
        draw(&mut s, &mut p, r, true, 300, c.at(541));
        p.reply(c.at(580));
        // A drag: events 20 ms apart.
        s.wait(&mut p, false, c.at(600));
        s.input(c.at(600));
        s.input(c.at(620));
        let f = s.next(&mut p, false, c.at(620)).unwrap();
        assert!(f.preview, "25 kB take 200 ms at 125 kB/s: a preview");
        assert!(s.new_picture(&f, false) && s.previewing());
        p.sent(c.at(620), 8_000, true);
        s.written(&f, true, 8_000, false);
        // No status refresh after a preview.
        assert!(matches!(s.wait(&mut p, false, c.at(621)), Wait::Reply(_)));
        p.reply(c.at(700));
        // Input stopped at 620: the exact picture is due a quiet time (60 ms) later.
        assert_eq!(s.wait(&mut p, false, c.at(700)), Wait::Refine(c.at(680)));
        let f = s.next(&mut p, false, c.at(700)).unwrap();
        assert_eq!(f, EXACT);
        // The same state, but the preview is replaced.
        assert!(s.new_picture(&f, true) && !s.previewing());
    }

    #[test]
    fn a_held_frame_waits_for_the_link_and_shows_the_newest_state() {
        let c = clock();
        // 1 Mbit/s stated: 25 kB occupy the link 220 ms.
        let mut p = Pacer::default().with_hold(Hold::new(HoldBy::Rate(125_000.0)), None);
        let mut s = Schedule::new(c.at(0));
        s.wait(&mut p, false, c.at(0));
        let f = s.next(&mut p, false, c.at(0)).unwrap();
        draw(&mut s, &mut p, f, false, 25_000, c.at(0));
        // The refresh goes (a few hundred bytes, queued behind the frame).
        let r = s.next(&mut p, false, c.at(0)).unwrap();
        draw(&mut s, &mut p, r, true, 250, c.at(0));
        for t in [2, 3, 4] {
            p.reply(c.at(t));
        }
        // The replies came at once (a multiplexer), but the link is busy
        // until 220 ms (the frame) + 2.2 ms (the refresh).
        s.input(c.at(10));
        let free = c.at(222) + Duration::from_micros(200);
        assert_eq!(s.wait(&mut p, false, c.at(10)), Wait::Held(free));
        // Input keeps coming meanwhile: no frame.
        for t in [100, 180, 200, 220] {
            s.input(c.at(t));
            assert_eq!(s.next(&mut p, false, c.at(t)), None);
        }
        // Free: one frame for all of it, the preview the stated rate calls for.
        let f = s.next(&mut p, false, c.at(223)).unwrap();
        assert!(f.preview && !f.status_only);
        assert_eq!(s.next(&mut p, false, c.at(224)), None);
    }

    #[test]
    fn strips_go_one_per_reply_while_nothing_newer_is_due_and_input_preempts_them() {
        let c = clock();
        let mut p = slow(&c);
        let mut s = Schedule::new(c.at(300));
        s.probe(true);
        s.wait(&mut p, false, c.at(300));
        let f = s.next(&mut p, false, c.at(300)).unwrap();
        // The exact picture went link-sized; its strips wait.
        draw(&mut s, &mut p, f, false, 25_000, c.at(300));
        s.set_strips(true);
        // The status refresh first, at once.
        let r = s.next(&mut p, false, c.at(301)).unwrap();
        assert!(r.status_only && !r.strip);
        draw(&mut s, &mut p, r, true, 300, c.at(301));
        // A strip once the link is free again, not before.
        assert!(matches!(s.wait(&mut p, false, c.at(302)), Wait::Reply(_)));
        assert_eq!(s.next(&mut p, false, c.at(302)), None);
        p.reply(c.at(500));
        p.reply(c.at(501));
        assert_eq!(s.wait(&mut p, false, c.at(501)), Wait::Due);
        let strip = s.next(&mut p, false, c.at(501)).unwrap();
        assert!(strip.strip && !strip.preview && !strip.status_only);
        // A strip is no new picture: no status refresh, the exact bytes kept.
        draw(&mut s, &mut p, strip, true, 2_000, c.at(501));
        assert_eq!(s.exact_bytes(), Some(25_000));
        p.reply(c.at(560));
        // A key: the next frame is its picture, not a strip.
        s.input(c.at(570));
        let f = s.next(&mut p, false, c.at(570)).unwrap();
        assert!(!f.strip);
        // The new picture dropped the strips: then nothing.
        s.set_strips(false);
        let new = s.new_picture(&f, false);
        p.sent(c.at(570), 8_000, true);
        s.written(&f, new, 8_000, false);
        p.reply(c.at(700));
        s.wait(&mut p, false, c.at(700));
        let r = s.next(&mut p, false, c.at(700));
        assert!(r.is_none_or(|r| !r.strip), "{r:?}");
    }

    #[test]
    fn auto_rotation_ticks_at_the_frame_interval() {
        let c = clock();
        let mut p = Pacer::by_writes();
        let mut s = Schedule::new(c.at(0));
        s.wait(&mut p, true, c.at(0));
        let f = s.next(&mut p, true, c.at(0)).unwrap();
        assert_eq!(f.tick, None);
        let new = s.new_picture(&f, false);
        s.written(&f, new, 25_000, true);
        assert_eq!(s.wait(&mut p, true, c.at(5)), Wait::Rotate(c.at(33)));
        assert_eq!(s.next(&mut p, true, c.at(20)), None);
        let f = s.next(&mut p, true, c.at(40)).unwrap();
        assert!((f.tick.unwrap() - 0.040).abs() < 1e-6);
        assert_eq!(s.wait(&mut p, true, c.at(41)), Wait::Rotate(c.at(73)));
    }

    #[test]
    fn a_load_shows_its_progress_every_interval_until_it_ends() {
        let c = clock();
        let mut p = Pacer::by_writes();
        let mut s = Schedule::new(c.at(0));
        s.loading(true, c.at(0));
        assert_eq!(s.wait(&mut p, false, c.at(0)), Wait::Due);
        let f = s.next(&mut p, false, c.at(0)).unwrap();
        draw(&mut s, &mut p, f, false, 25_000, c.at(0));
        assert_eq!(s.wait(&mut p, false, c.at(1)), Wait::Refresh);
        let r = s.next(&mut p, false, c.at(1)).unwrap();
        draw(&mut s, &mut p, r, true, 300, c.at(1));
        // Nothing else to draw: the progress, every interval.
        let first = c.at(0) + PROGRESS_INTERVAL;
        assert_eq!(s.wait(&mut p, false, c.at(2)), Wait::Progress(first));
        assert_eq!(Wait::Progress(first).until(c.at(2)), Some(first));
        assert_eq!(s.next(&mut p, false, c.at(100)), None);
        let at = c.at(260);
        let f = s.next(&mut p, false, at).unwrap();
        assert!(f.status_only && !f.preview && f.tick.is_none());
        draw(&mut s, &mut p, f, true, 300, at);
        assert_eq!(
            s.wait(&mut p, false, at),
            Wait::Progress(at + PROGRESS_INTERVAL)
        );
        // Auto-rotation's frames, sooner, come first (each shows the
        // progress too).
        assert_eq!(s.wait(&mut p, true, at), Wait::Rotate(at + FRAME_INTERVAL));
        // The load ended: nothing more to draw.
        s.loading(false, c.at(300));
        assert_eq!(s.wait(&mut p, false, c.at(300)), Wait::Idle);
        assert_eq!(s.next(&mut p, false, c.at(900)), None);
    }
}

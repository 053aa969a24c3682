//! Holding frames for a link the pacing replies do not see.
//!
//! Inside tmux or GNU screen the multiplexer answers the pacing query at
//! once, so a reply no longer means "on screen". Two other signals stand in:
//!
//! - **The send queue** of the SSH connection ([`crate::backlog`]):
//!   after a frame, the next waits until the queue is down to what the link
//!   delivers within [`ACK_DELAY`] (at least [`QUEUE_THRESHOLD`], at most
//!   one frame as the queue holds it), i.e. until the client has about
//!   acknowledged the frame before, which is what the reply means over
//!   plain SSH. The falls of the queue bound the link's rate from below
//!   (acknowledgements arrive no faster than the link delivers); the
//!   fastest recent one decides previews and that allowance, in relief's
//!   bytes (the multiplexer may send fewer: see [`Hold::wire`]).
//!   Why the allowance: inside a multiplexer the client sends nothing back
//!   (over plain SSH the terminal's reply carries the acknowledgement), so
//!   its TCP delays the acknowledgement of a frame's last segments; waiting
//!   for it cost 40–80 ms a frame on a fast link.
//! - **A rate the user states** (`--link RATE`): each frame occupies the link
//!   for its bytes (plus the framing of SSH, TCP and IP) over that rate, and
//!   the next waits for the link to be free.
//!
//! Input keeps being applied while a frame is held, so the frame that goes
//! is the newest state; when input stops, the exact picture goes as soon as
//! the link is free. The clock and the queue readings are passed in, so
//! tests drive both.

use std::time::{Duration, Instant};

/// Bytes still queued that let the next frame go. The queue reads 0 on an
/// idle link; a frame is 20–50 kB at 160×48 (a half-resolution preview a
/// third of that), so what remains below this is a few segments at most:
/// the next frame waits behind next to nothing, as over plain SSH.
pub const QUEUE_THRESHOLD: u64 = 2048;

/// The multiplexer needs a moment to take the frame and write it to the
/// SSH connection: a reading taken earlier could find the queue still
/// empty. Measured at a few milliseconds; this leaves room for a busy
/// machine.
pub const GRACE: Duration = Duration::from_millis(15);

/// How often the queue is read while a frame is held.
pub const POLL: Duration = Duration::from_millis(10);

/// How long a receiver may delay an acknowledgement (Linux's shortest
/// delayed-acknowledgement time-out): bytes the link delivers within it are
/// as good as shown.
pub const ACK_DELAY: Duration = Duration::from_millis(40);

/// Bytes on the wire per byte written: SSH packets (length, padding, MAC)
/// and TCP/IP segments (about 66 bytes of headers per 1448) add 5–8 %;
/// rounded up so a stated rate is not overrun.
pub const FRAMING: f64 = 1.1;

/// Writes smaller than this say little about what the multiplexer makes
/// of a frame (a status line's refresh).
const WIRE_MIN_BYTES: u64 = 4096;

/// Weight of a new sample of the wire factor.
const WIRE_SMOOTHING: f64 = 0.25;

/// Drain samples kept: the rate is the fastest of them.
const RATE_WINDOW: usize = 8;

/// Drain intervals shorter than this say little (timer noise).
const MIN_INTERVAL: Duration = Duration::from_millis(5);

/// What holds frames, besides the replies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HoldBy {
    /// Nothing: the replies alone pace (plain SSH, a local terminal or a
    /// local tmux).
    Nothing,
    /// The SSH connection's send queue.
    Queue,
    /// A stated link rate, in bytes per second.
    Rate(f64),
}

/// The hold's state (see the module notes).
#[derive(Clone, Debug)]
pub struct Hold {
    by: HoldBy,
    /// When the last frame was written.
    wrote: Option<Instant>,
    /// Stated rate: when the link is done with what was written.
    busy_until: Option<Instant>,
    /// The last queue reading, taken after the grace.
    last: Option<(Instant, Option<u64>)>,
    /// The largest write since the queue was last seen drained.
    frame: u64,
    /// The last reading ever (writes do not clear it): the queue a new
    /// frame joins.
    seen: Option<(Instant, u64)>,
    /// The queue when the first write since the last reading went, and
    /// the bytes written since (`None`: that queue is not known).
    joined: Option<(u64, u64)>,
    /// Smoothed bytes queued per byte written: what the multiplexer sends
    /// for relief's frame (GNU screen turns 24-bit colours into its
    /// palette: a third), in SSH packets.
    wire: Option<f64>,
    /// The latest drain samples, bytes per second (see [`Hold::reading`]).
    drained: std::collections::VecDeque<f64>,
}

impl Hold {
    pub fn new(by: HoldBy) -> Self {
        Hold {
            by,
            wrote: None,
            busy_until: None,
            last: None,
            frame: 0,
            drained: std::collections::VecDeque::new(),
            seen: None,
            joined: None,
            wire: None,
        }
    }

    pub fn by(&self) -> HoldBy {
        self.by
    }

    /// A frame of `bytes` was written at `at`.
    pub fn wrote(&mut self, at: Instant, bytes: u64) {
        if self.last.is_some() || self.wrote.is_none() {
            // The first write since a reading: the queue it joins is that
            // reading if it is near empty, nothing before any write. A queue
            // still holding the frame before may be acknowledged during the
            // grace, and the reading after it would then call this frame
            // nearly free (measured inside tmux at 50 Mbit/s: the factor
            // sank, the allowance with it, and every frame waited for the
            // whole of the one before): no sample then.
            self.joined = match self.seen {
                None => Some(0),
                Some((_, q)) if q <= QUEUE_THRESHOLD => Some(q),
                Some(_) => None,
            }
            .map(|q| (q, 0));
        }
        if let Some((_, written)) = &mut self.joined {
            *written += bytes;
        }
        self.wrote = Some(at);
        self.last = None;
        self.frame = self.frame.max(bytes);
        if let HoldBy::Rate(rate) = self.by {
            let start = self.busy_until.map_or(at, |b| b.max(at));
            let busy = Duration::from_secs_f64(bytes as f64 * FRAMING / rate);
            self.busy_until = Some(start + busy);
        }
    }

    /// Whether the queue should be read at `now`: a frame was written more
    /// than the grace ago and the last reading is older than the poll.
    pub fn wants_reading(&self, now: Instant) -> bool {
        self.by == HoldBy::Queue
            && self.wrote.is_some_and(|w| now >= w + GRACE)
            && self.last.is_none_or(|(t, _)| now >= t + POLL)
    }

    /// A reading of the queue at `at` (`None`: the socket was not found).
    pub fn reading(&mut self, at: Instant, queued: Option<u64>) {
        if let (Some((t, Some(before))), Some(now)) = (self.last, queued) {
            let dt = at.saturating_duration_since(t);
            // Acknowledgements arrive no faster than the link delivers, so
            // a fall of the queue between two readings is at most the
            // link's rate: the whole of it on a slow link, which drains a
            // frame over many readings; far less on a fast one, where a
            // frame's acknowledgements come in one burst a round trip after
            // it (or in a few, one per congestion window) and the readings
            // around the burst see a flat queue for most of their interval.
            // So each fall is a lower bound of the rate, and the rate is the
            // fastest recent one; a flat or rising queue says nothing.
            if now < before && dt >= MIN_INTERVAL {
                let sample = (before - now) as f64 / dt.as_secs_f64();
                if self.drained.len() == RATE_WINDOW {
                    self.drained.pop_front();
                }
                self.drained.push_back(sample);
            }
        }
        if let (None, Some(q), Some((base, written))) = (self.last, queued, self.joined)
            && written >= WIRE_MIN_BYTES
        {
            // The first reading after the grace: the frame is in the queue,
            // none of it acknowledged yet on a fast link (a round trip is
            // longer than the grace) and little on a slow one.
            let sample = (q.saturating_sub(base) as f64 / written as f64).clamp(0.05, 2.0);
            self.wire = Some(match self.wire {
                Some(w) => w + WIRE_SMOOTHING * (sample - w),
                None => sample,
            });
        }
        self.joined = None;
        self.last = Some((at, queued));
        self.seen = queued.map(|q| (at, q));
        if queued.is_none_or(|q| q <= QUEUE_THRESHOLD) {
            self.frame = 0;
        }
    }

    /// The queue at or below which the next frame may go: what the link
    /// delivers within [`ACK_DELAY`] at the measured rate, at least
    /// [`QUEUE_THRESHOLD`] and at most the frame as it sits in the queue
    /// (the wire factor, or [`FRAMING`] before it is known, with a tenth
    /// to spare), so one frame may stay unacknowledged (an unknown rate:
    /// the frame).
    pub fn release_at(&self) -> u64 {
        let within = self
            .measured()
            .map_or(u64::MAX, |r| (r * ACK_DELAY.as_secs_f64()) as u64);
        let frame = (self.frame as f64 * self.wire.unwrap_or(1.0) * FRAMING) as u64;
        within.min(frame).max(QUEUE_THRESHOLD)
    }

    /// Bytes queued per byte written, as measured (`None`: not yet).
    pub fn wire(&self) -> Option<f64> {
        self.wire
    }

    /// The fastest recent drain (`None`: none seen).
    fn measured(&self) -> Option<f64> {
        self.drained.iter().copied().reduce(f64::max)
    }

    /// Whether the next frame may go at `now` (the readings so far).
    pub fn clear(&self, now: Instant) -> bool {
        self.until(now).is_none()
    }

    /// While held: when to look again (`None`: not held).
    pub fn until(&self, now: Instant) -> Option<Instant> {
        match self.by {
            HoldBy::Nothing => None,
            HoldBy::Rate(_) => self.busy_until.filter(|&b| b > now),
            HoldBy::Queue => {
                let wrote = self.wrote?;
                if now < wrote + GRACE {
                    return Some(wrote + GRACE);
                }
                match self.last {
                    // Not read since the grace: read now.
                    None => Some(now),
                    Some((t, Some(q))) if q > self.release_at() => Some((t + POLL).max(now)),
                    // Drained, or the socket is gone: nothing to wait for.
                    Some(_) => None,
                }
            }
        }
    }

    /// The link's rate in bytes per second, as stated or as measured from
    /// the queue's drain (`None`: not known here).
    pub fn rate(&self) -> Option<f64> {
        match self.by {
            HoldBy::Nothing => None,
            // In relief's bytes: the queue holds what the multiplexer sent.
            HoldBy::Queue => Some(self.measured()? / self.wire.unwrap_or(1.0)),
            HoldBy::Rate(r) => Some(r),
        }
    }
}

/// `--link`: measured, or as the user states it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LinkRate {
    /// By the replies, and by the send queue inside a multiplexer over SSH.
    Auto,
    /// Bytes per second.
    Stated(f64),
}

/// `--link`: `auto`, or a rate in bits per second with an optional `k`, `M`
/// or `G` (powers of 1000): `1M`, `50M`, `500k`, `2.5M`.
pub fn parse_link(text: &str) -> Result<LinkRate, String> {
    let t = text.trim();
    if t.eq_ignore_ascii_case("auto") {
        return Ok(LinkRate::Auto);
    }
    let (number, scale) = match t.char_indices().last() {
        Some((i, 'k' | 'K')) => (&t[..i], 1e3),
        Some((i, 'm' | 'M')) => (&t[..i], 1e6),
        Some((i, 'g' | 'G')) => (&t[..i], 1e9),
        _ => (t, 1.0),
    };
    let bits: f64 = number.parse().map_err(|_| {
        format!("expected auto or a rate in bits/s such as 1M or 50M, got '{text}'")
    })?;
    let bits = bits * scale;
    // Below 1 kbit/s a single frame would take minutes.
    if !bits.is_finite() || bits < 1e3 {
        return Err(format!(
            "the link rate must be at least 1k (bits/s), got '{text}'"
        ));
    }
    Ok(LinkRate::Stated(bits / 8.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Clock(Instant);

    impl Clock {
        fn at(&self, ms: u64) -> Instant {
            self.0 + Duration::from_millis(ms)
        }
    }

    fn clock() -> Clock {
        Clock(Instant::now())
    }

    /// Reads the queue whenever the hold asks, as the loop does.
    fn poll(h: &mut Hold, now: Instant, queued: Option<u64>) -> bool {
        if h.wants_reading(now) {
            h.reading(now, queued);
        }
        h.clear(now)
    }

    #[test]
    fn nothing_never_holds() {
        let c = clock();
        let mut h = Hold::new(HoldBy::Nothing);
        h.wrote(c.at(0), 1 << 20);
        assert!(h.clear(c.at(0)) && !h.wants_reading(c.at(100)));
        assert_eq!(h.rate(), None);
    }

    #[test]
    fn a_frame_is_held_until_the_queue_has_drained() {
        let c = clock();
        let mut h = Hold::new(HoldBy::Queue);
        assert!(h.clear(c.at(0)), "nothing written yet");
        h.wrote(c.at(0), 27_000);
        // Within the grace the queue is not trusted (the frame may not be in it yet).
        assert!(!h.wants_reading(c.at(14)));
        assert!(!poll(&mut h, c.at(14), Some(0)));
        assert_eq!(h.until(c.at(14)), Some(c.at(15)));
        // The rate unknown, the frame may stay in flight: it is 27 540 bytes
        // in the queue (1.02 per byte written, in SSH packets), and one
        // frame (with a tenth to spare) is 30 294.
        assert!(poll(&mut h, c.at(15), Some(27_540)));
        assert!((h.wire().unwrap() - 1.02).abs() < 1e-9);
        assert!((30_293..=30_294).contains(&h.release_at()));
        // Not two: held, and read again a poll later.
        h.wrote(c.at(16), 27_000);
        assert!(!poll(&mut h, c.at(31), Some(55_080)));
        assert!((h.wire().unwrap() - 1.02).abs() < 1e-9);
        assert_eq!(h.until(c.at(32)), Some(c.at(41)));
        assert!(!h.wants_reading(c.at(40)));
        // Flat for a round trip (no acknowledgement yet): no rate from it.
        assert!(!poll(&mut h, c.at(41), Some(55_080)));
        assert!(!poll(&mut h, c.at(71), Some(55_080)));
        assert_eq!(h.rate(), None);
        // Then it falls 1250 bytes every 10 ms: 125 kB/s (1 Mbit/s) in the
        // queue, which delivers 5000 bytes within the acknowledgement
        // delay: held until then (3830 bytes left after 41 readings).
        // In relief's bytes the rate is 125 000 / 1.02.
        let (mut t, mut q) = (71, 55_080);
        while q > 5_000 {
            (t, q) = (t + 10, q - 1250);
            assert_eq!(poll(&mut h, c.at(t), Some(q)), q <= 5_000, "{t} ms: {q}");
            assert!((h.rate().unwrap() - 125_000.0 / 1.02).abs() < 1e-6);
        }
        assert_eq!((t, q), (481, 3_830));
        assert_eq!(h.release_at(), 5_000);
        assert_eq!(h.until(c.at(481)), None);
        // The next frame: one of 3 kB (too small to say what the multiplexer
        // makes of frames), queued behind what is left.
        h.wrote(c.at(490), 3_000);
        assert!(!h.clear(c.at(490)));
        assert_eq!(h.release_at(), 5_000, "the largest since the queue drained");
        assert!(!poll(&mut h, c.at(505), Some(7_000)));
        assert!(!poll(&mut h, c.at(515), Some(5_750)));
        assert!(poll(&mut h, c.at(525), Some(4_500)));
        assert!(poll(&mut h, c.at(535), Some(3_250)));
        assert!(poll(&mut h, c.at(545), Some(2_000)));
        assert!((h.wire().unwrap() - 1.02).abs() < 1e-9);
        // Drained: the allowance starts over from the next frame, never
        // below the threshold.
        h.wrote(c.at(550), 1_000);
        assert_eq!(h.release_at(), QUEUE_THRESHOLD);
        assert!(!poll(&mut h, c.at(565), Some(QUEUE_THRESHOLD + 1)));
        assert!(poll(&mut h, c.at(575), Some(QUEUE_THRESHOLD)));
    }

    #[test]
    fn on_a_fast_link_one_frame_may_stay_unacknowledged() {
        let c = clock();
        let mut h = Hold::new(HoldBy::Queue);
        // 25 kB written; the next reading finds them all still queued (the
        // acknowledgement delayed): one frame in flight.
        h.wrote(c.at(0), 25_000);
        assert!(poll(&mut h, c.at(15), Some(25_400)), "one frame in flight");
        h.wrote(c.at(16), 25_000);
        assert!(!poll(&mut h, c.at(31), Some(50_800)), "not two");
        // All of it acknowledged within 10 ms: the link carries at least
        // 5.08 MB/s of the queue's bytes, 5 MB/s of relief's (when within
        // them is not known).
        assert!(poll(&mut h, c.at(41), Some(0)));
        assert!((h.rate().unwrap() - 5e6).abs() < 1e-3);
    }

    #[test]
    fn a_frame_acknowledged_during_the_next_ones_grace_leaves_the_factor_alone() {
        // As traced inside tmux at 50 Mbit/s: a frame goes while the one
        // before is still queued, and that one's acknowledgement arrives
        // before the next reading. The queue then holds this frame alone,
        // which says nothing of how many bytes it became: the factor keeps
        // its value, and so does the one frame allowed in flight.
        let c = clock();
        let mut h = Hold::new(HoldBy::Queue);
        h.wrote(c.at(0), 25_000);
        assert!(poll(&mut h, c.at(15), Some(25_750)));
        assert!((h.wire().unwrap() - 1.03).abs() < 1e-9);
        for i in 0..20 {
            let t = 16 + 20 * i;
            h.wrote(c.at(t), 25_000);
            assert!(
                poll(&mut h, c.at(t + 15), Some(25_750)),
                "frame {i}: one frame in flight"
            );
        }
        assert!((h.wire().unwrap() - 1.03).abs() < 1e-9);
        assert!(h.release_at() >= 25_750);
    }

    #[test]
    fn what_the_multiplexer_sends_is_measured_against_what_was_written() {
        // GNU screen sends a 24-bit frame of 27 000 bytes as 8 100 (its
        // 256-colour palette): the queue's rate is a third of relief's,
        // and one frame in flight is 8 100 bytes of it.
        let c = clock();
        let mut h = Hold::new(HoldBy::Queue);
        h.wrote(c.at(0), 27_000);
        assert!(poll(&mut h, c.at(15), Some(8_100)));
        assert!((h.wire().unwrap() - 0.3).abs() < 1e-9);
        assert!((8_909..=8_910).contains(&h.release_at()));
        h.wrote(c.at(16), 27_000);
        assert!(!poll(&mut h, c.at(31), Some(16_200)));
        assert!(poll(&mut h, c.at(41), Some(0)));
        // 16 200 bytes of the queue in 10 ms: 5.4 MB/s of relief's.
        assert!((h.rate().unwrap() - 5.4e6).abs() < 1e-3);
        // A write long after a reading that was not near empty joins a
        // queue of unknown size (it may have drained since): no sample.
        h.reading(c.at(50), Some(20_000));
        h.wrote(c.at(1000), 27_000);
        h.reading(c.at(1015), Some(60_000));
        assert!((h.wire().unwrap() - 0.3).abs() < 1e-9);
    }

    #[test]
    fn on_a_fast_link_small_frames_do_not_hide_its_rate() {
        // As measured inside tmux at 50 Mbit/s, 20 ms each way: an exact
        // frame (26 kB) is acknowledged in one burst a round trip after
        // it; then 8 kB previews, each flat for 60-80 ms (the client delays
        // its acknowledgement) and gone at the next reading.
        let c = clock();
        let mut h = Hold::new(HoldBy::Queue);
        h.wrote(c.at(0), 25_128);
        assert!(poll(&mut h, c.at(15), Some(26_712)));
        assert!(poll(&mut h, c.at(26), Some(26_712)));
        assert!(poll(&mut h, c.at(52), Some(648)));
        let fast = 26_064.0 / 0.026;
        let queued = |h: &Hold| h.rate().unwrap() * h.wire().unwrap();
        assert!((queued(&h) - fast).abs() < 1e-3);
        for i in 0..(RATE_WINDOW as u64 - 1) {
            let t = 1000 + 100 * i;
            h.wrote(c.at(t), 8_374);
            // The preview in SSH packets is a little more than its bytes:
            // it may stay in flight.
            assert!(poll(&mut h, c.at(t + 20), Some(8_476)));
            assert!(poll(&mut h, c.at(t + 65), Some(8_476)));
            assert!(poll(&mut h, c.at(t + 81), Some(0)));
        }
        // Their falls (8476 bytes in 16 ms: 530 kB/s) would call the exact
        // frame slow (47 ms); the exact frame's own says it is not.
        assert!((queued(&h) - fast).abs() < 1e-3);
        assert!(25_128.0 / h.rate().unwrap() < 0.033);
        // Once the link is slower for a whole window, so is the rate.
        h.wrote(c.at(2000), 8_374);
        assert!(poll(&mut h, c.at(2020), Some(8_476)));
        assert!(poll(&mut h, c.at(2036), Some(0)));
        assert!((queued(&h) - 8_476.0 / 0.016).abs() < 1e-3);
        assert!(25_128.0 / h.rate().unwrap() > 0.033);
    }

    #[test]
    fn the_drain_rate_is_the_fastest_recent_fall() {
        let c = clock();
        let mut h = Hold::new(HoldBy::Queue);
        h.wrote(c.at(0), 60_000);
        h.reading(c.at(20), Some(60_000));
        h.reading(c.at(30), Some(50_000)); // 1 MB/s
        assert!((h.rate().unwrap() - 1e6).abs() < 1e-3);
        h.reading(c.at(40), Some(55_000)); // rose: more came in, no sample
        h.reading(c.at(41), Some(54_000)); // 1 ms: too short to say
        assert!((h.rate().unwrap() - 1e6).abs() < 1e-3);
        h.reading(c.at(51), Some(52_000)); // 200 kB/s: a slower fall
        assert!((h.rate().unwrap() - 1e6).abs() < 1e-3);
        // Emptied between two readings: at least that fast.
        h.reading(c.at(61), Some(0));
        assert!((h.rate().unwrap() - 5.2e6).abs() < 1e-3);
        // The link slows down: the fast fall leaves after eight slower ones.
        h.reading(c.at(100), Some(80_000));
        for i in 1..=RATE_WINDOW as u64 {
            assert!((h.rate().unwrap() - 5.2e6).abs() < 1e-3, "{i}");
            h.reading(c.at(100 + 10 * i), Some(80_000 - 1000 * i));
        }
        assert!((h.rate().unwrap() - 1e5).abs() < 1e-3);
    }

    #[test]
    fn a_lost_socket_does_not_hold() {
        let c = clock();
        let mut h = Hold::new(HoldBy::Queue);
        h.wrote(c.at(0), 27_000);
        assert!(poll(&mut h, c.at(20), None));
    }

    #[test]
    fn a_stated_rate_spaces_the_frames() {
        let c = clock();
        // 1 Mbit/s: 125 kB/s; 25 kB with the framing take 220 ms.
        let mut h = Hold::new(HoldBy::Rate(125_000.0));
        assert_eq!(h.rate(), Some(125_000.0));
        h.wrote(c.at(0), 25_000);
        assert!(!h.clear(c.at(219)));
        assert!(h.clear(c.at(220)));
        // Written before the link is free (a status refresh): it queues behind.
        h.wrote(c.at(100), 1_000);
        assert_eq!(
            h.until(c.at(100)),
            Some(c.at(228) + Duration::from_micros(800))
        );
        // Written after: from then on.
        h.wrote(c.at(1000), 12_500);
        assert!(!h.clear(c.at(1109)) && h.clear(c.at(1110)));
        assert!(!h.wants_reading(c.at(2000)), "no queue to read");
    }

    #[test]
    fn link_rates_parse_in_bits_per_second() {
        use LinkRate::{Auto, Stated};
        assert_eq!(parse_link("auto"), Ok(Auto));
        assert_eq!(parse_link("AUTO"), Ok(Auto));
        assert_eq!(parse_link("1M"), Ok(Stated(125_000.0)));
        assert_eq!(parse_link("50M"), Ok(Stated(6_250_000.0)));
        assert_eq!(parse_link("500k"), Ok(Stated(62_500.0)));
        assert_eq!(parse_link("2.5m"), Ok(Stated(312_500.0)));
        assert_eq!(parse_link("1G"), Ok(Stated(125_000_000.0)));
        assert_eq!(parse_link("64000"), Ok(Stated(8_000.0)));
        for bad in ["", "M", "fast", "-1M", "0", "999", "NaNM", "infM", "1T"] {
            assert!(parse_link(bad).is_err(), "{bad}");
        }
    }
}

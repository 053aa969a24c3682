//! End-to-end pacing: knowing when the terminal has shown a frame.
//!
//! A `write` returning says nothing over SSH: sshd and TCP take hundreds of
//! kilobytes at once and deliver them seconds later. So each frame is
//! followed by a primary device attributes query (`ESC [ c`), which every
//! terminal (tmux included) answers after it has processed everything
//! written before it. A reply means "the frame is on screen". The loop
//! keeps at most one frame in flight: input arriving meanwhile is folded
//! into the next frame, and whatever is queued when the user quits is at
//! most one frame and a query.
//!
//! One frame rather than a byte budget of throughput × round trip: the
//! budget would let a fast, distant link run several small frames ahead,
//! but it rests on estimates that are wrong exactly when the link changes,
//! and a quit then waits behind all of them. One frame is what "restore
//! within a round trip plus a frame" needs, and locally (a round trip of a
//! fraction of a millisecond) it costs nothing.
//!
//! The clock is whatever the caller passes in (`now`), so tests drive it.
//! A terminal that never answers the first query within
//! [`PacingConfig::first_reply`] is left alone: no more queries, frames
//! paced by the writes as before. Replies are matched to queries in order,
//! so a late one (after a time-out) is credited to its own query and never
//! releases a newer frame early.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use super::hold::{Hold, HoldBy, LinkRate};

/// Reads the SSH connection's send queue (see [`crate::backlog`]):
/// bytes queued, `None` when the socket is not found.
pub type ReadQueue = Box<dyn FnMut() -> Option<u64> + Send>;

/// Primary device attributes (DA1): answered `ESC [ ? … c` by every terminal.
pub const QUERY: &[u8] = b"\x1b[c";

/// Time-outs of the pacer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PacingConfig {
    /// No reply at all this long after the first query: the terminal does
    /// not answer; stop asking.
    pub first_reply: Duration,
    /// A terminal that has answered before but not this query for this
    /// long (and several times the expected delivery time): give up
    /// waiting for it (its reply is still matched when it comes).
    pub lost_reply: Duration,
    /// Send cheaper previews while input keeps coming over a slow link.
    pub previews: bool,
    /// Input counts as still coming for about one round trip after it,
    /// never less than this...
    pub quiet_min: Duration,
    /// ...nor more than this.
    pub quiet_max: Duration,
}

impl Default for PacingConfig {
    fn default() -> Self {
        PacingConfig {
            first_reply: Duration::from_secs(1),
            lost_reply: Duration::from_secs(2),
            previews: true,
            quiet_min: Duration::from_millis(60),
            quiet_max: Duration::from_millis(150),
        }
    }
}

/// Whether input keeps coming: a burst is input that follows other input
/// within the quiet time. A lone key after a pause is not one (it gets
/// the exact picture at once, as fast as before).
#[derive(Clone, Copy, Debug, Default)]
pub struct Activity {
    last: Option<Instant>,
    burst: bool,
}

impl Activity {
    /// Input was applied at `at`.
    pub fn input(&mut self, at: Instant, quiet: Duration) {
        self.burst = self
            .last
            .is_some_and(|t| at.saturating_duration_since(t) < quiet);
        self.last = Some(at);
    }

    /// Input is still coming at `now`.
    pub fn moving(&self, now: Instant, quiet: Duration) -> bool {
        self.burst && self.last.is_some_and(|t| now < t + quiet)
    }

    /// When input counts as stopped (`None`: there was none).
    pub fn settled_at(&self, quiet: Duration) -> Option<Instant> {
        self.last.map(|t| t + quiet)
    }
}

/// Whether the terminal answers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Answers {
    /// No reply yet (and the time-out not reached).
    Unknown,
    /// It answers: frames are paced by its replies.
    Yes,
    /// It never answered: frames are paced by the writes.
    No,
}

/// A query written and not yet answered.
#[derive(Clone, Copy, Debug)]
struct Flight {
    sent: Instant,
    /// Bytes written since the previous query (the frame this one follows).
    bytes: u64,
    /// Given up waiting for (its reply is still expected, in order).
    abandoned: bool,
    /// Written with no other query unanswered: nothing queued before it.
    alone: bool,
}

/// What the link looks like, for the cost panel and the preview decision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkInfo {
    pub answers: Answers,
    /// Smoothed time from a query written to its reply.
    pub round_trip: Option<Duration>,
    /// Smoothed bytes per second the terminal took in.
    pub throughput: Option<f64>,
    /// Replies that came after their query was given up.
    pub late_replies: u64,
    /// What else holds frames: the SSH send queue (inside tmux or screen)
    /// or a stated rate.
    pub held_by: HoldBy,
}

impl Default for LinkInfo {
    fn default() -> Self {
        LinkInfo {
            answers: Answers::Unknown,
            round_trip: None,
            throughput: None,
            late_replies: 0,
            held_by: HoldBy::Nothing,
        }
    }
}

/// Round-trip samples kept for the minimum (the base latency).
const RTT_WINDOW: usize = 8;
/// Frames smaller than this say little about throughput.
const THROUGHPUT_MIN_BYTES: u64 = 2048;
/// Weight of a new sample in the smoothed figures.
const SMOOTHING: f64 = 0.25;

/// The pacing state machine (see the module notes).
pub struct Pacer {
    config: PacingConfig,
    answers: Answers,
    flights: VecDeque<Flight>,
    first_query: Option<Instant>,
    rtt_samples: VecDeque<Duration>,
    round_trip: Option<f64>,
    throughput: Option<f64>,
    /// The last frames' bytes and transfer times (the throughput's samples).
    transfers: VecDeque<(u64, f64)>,
    late_replies: u64,
    /// What else holds frames where the replies do not see the link.
    hold: Hold,
    read_queue: Option<ReadQueue>,
    /// While the replies are in but the hold holds: when to look again.
    held_until: Option<Instant>,
}

impl std::fmt::Debug for Pacer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Pacer")
            .field("answers", &self.answers)
            .field("outstanding", &self.flights.len())
            .field("hold", &self.hold)
            .finish_non_exhaustive()
    }
}

impl Default for Pacer {
    fn default() -> Self {
        Pacer::new(PacingConfig::default())
    }
}

fn smooth(old: Option<f64>, sample: f64) -> f64 {
    match old {
        Some(o) => o + SMOOTHING * (sample - o),
        None => sample,
    }
}

impl Pacer {
    pub fn new(config: PacingConfig) -> Self {
        Pacer {
            config,
            answers: Answers::Unknown,
            flights: VecDeque::new(),
            first_query: None,
            rtt_samples: VecDeque::new(),
            round_trip: None,
            throughput: None,
            transfers: VecDeque::new(),
            late_replies: 0,
            hold: Hold::new(HoldBy::Nothing),
            read_queue: None,
            held_until: None,
        }
    }

    /// Frames are also held by `hold` (see [`crate::hold`]); `read`
    /// reads the send queue when the hold is by the queue.
    pub fn with_hold(mut self, hold: Hold, read: Option<ReadQueue>) -> Self {
        self.hold = hold;
        self.read_queue = read;
        self
    }

    /// What holds frames besides the replies.
    pub fn held_by(&self) -> HoldBy {
        self.hold.by()
    }

    /// A pacer that never asks: frames paced by the writes alone (a
    /// writer that is not a terminal).
    pub fn by_writes() -> Self {
        Pacer {
            answers: Answers::No,
            ..Pacer::default()
        }
    }

    /// Whether the next frame should end with [`QUERY`].
    pub fn asks(&self) -> bool {
        self.answers != Answers::No
    }

    /// A write went out at `at` (when it started) with `bytes`, followed by
    /// a query when `asked`.
    pub fn sent(&mut self, at: Instant, bytes: u64, asked: bool) {
        self.hold.wrote(at, bytes);
        if asked {
            self.first_query.get_or_insert(at);
            let alone = self.flights.is_empty();
            self.flights.push_back(Flight {
                sent: at,
                bytes,
                abandoned: false,
                alone,
            });
        }
    }

    /// The terminal answered a query at `at`: the oldest query written is
    /// answered (replies come in order). A reply with no query (one the
    /// terminal sent on its own) changes nothing.
    pub fn reply(&mut self, at: Instant) {
        let Some(flight) = self.flights.pop_front() else {
            return;
        };
        if flight.abandoned {
            self.late_replies += 1;
        }
        // A late reply still proves the terminal answers: pace by replies again.
        self.answers = Answers::Yes;
        let took = at.saturating_duration_since(flight.sent);
        // The base latency as known before this reply (none yet: no
        // throughput from this one, it would count the latency as transfer).
        let base = self.base_rtt().map(|b| b.min(took));
        // The base latency is sampled by small writes that queued behind
        // nothing: a run of large ones (the strips of an exact frame) would
        // otherwise push it out of the window, each then looking nearly
        // free (at 1 Mbit/s 26 kB strips read as 26 MB/s after eight).
        if self.rtt_samples.is_empty() || (flight.alone && flight.bytes < THROUGHPUT_MIN_BYTES) {
            self.rtt_samples.push_back(took);
            if self.rtt_samples.len() > RTT_WINDOW {
                self.rtt_samples.pop_front();
            }
        }
        self.round_trip = Some(smooth(self.round_trip, took.as_secs_f64()));
        if let Some(base) = base
            && flight.bytes >= THROUGHPUT_MIN_BYTES
            && !flight.abandoned
        {
            // Delivery time = base latency + bytes / throughput. The
            // recent frames' bytes over their transfer times: a small frame
            // (a strip of background, a few kB) takes as long as the round
            // trip's jitter, and its rate alone read several times the link.
            let transfer = (took.saturating_sub(base)).max(Duration::from_millis(1));
            self.transfers
                .push_back((flight.bytes, transfer.as_secs_f64()));
            if self.transfers.len() > RTT_WINDOW {
                self.transfers.pop_front();
            }
            let (bytes, secs) = self
                .transfers
                .iter()
                .fold((0.0, 0.0), |(b, t), &(fb, ft)| (b + fb as f64, t + ft));
            self.throughput = Some(bytes / secs);
        }
    }

    /// The shortest recent round trip: the latency with nothing queued.
    fn base_rtt(&self) -> Option<Duration> {
        self.rtt_samples.iter().min().copied()
    }

    /// Applies the time-outs at `now`; true when no frame is in flight and
    /// the next one may go (the hold reads the queue when it wants to).
    pub fn ready(&mut self, now: Instant) -> bool {
        let replied = self.replied(now);
        self.held_until = None;
        if !replied {
            return false;
        }
        if self.hold.wants_reading(now) {
            let queued = self.read_queue.as_mut().and_then(|read| read());
            self.hold.reading(now, queued);
        }
        self.held_until = self.hold.until(now);
        self.held_until.is_none()
    }

    /// [`Pacer::ready`] by the replies alone.
    fn replied(&mut self, now: Instant) -> bool {
        if self.answers == Answers::Unknown
            && self
                .first_query
                .is_some_and(|t| now.saturating_duration_since(t) >= self.config.first_reply)
        {
            // Never answered: pace by writes from now on.
            self.answers = Answers::No;
            for f in &mut self.flights {
                f.abandoned = true;
            }
        }
        if let Some(limit) = self.lost_after()
            && let Some(f) = self.flights.back_mut()
            && !f.abandoned
            && now.saturating_duration_since(f.sent) >= limit
        {
            for f in &mut self.flights {
                f.abandoned = true;
            }
        }
        self.flights.iter().all(|f| f.abandoned)
    }

    /// How long a known-answering terminal gets before a reply is given up.
    fn lost_after(&self) -> Option<Duration> {
        if self.answers != Answers::Yes {
            return None;
        }
        let expected = self.flights.back().map_or(Duration::ZERO, |f| {
            let rtt = self.round_trip.unwrap_or(0.0);
            let transfer = self.throughput().map_or(0.0, |t| f.bytes as f64 / t);
            Duration::from_secs_f64((rtt + transfer) * 4.0)
        });
        Some(self.config.lost_reply.max(expected))
    }

    /// The replies are in but the hold holds the next frame (as of the
    /// last [`Pacer::ready`]).
    pub fn held(&self) -> bool {
        self.held_until.is_some()
    }

    /// When the wait for the frame in flight times out, or, its reply in,
    /// when the hold looks again (`None`: nothing in flight and nothing
    /// held, or no time-out applies).
    pub fn deadline(&self) -> Option<Instant> {
        let Some(newest) = self.flights.back().filter(|f| !f.abandoned) else {
            return self.held_until;
        };
        match self.answers {
            Answers::Unknown => self.first_query.map(|t| t + self.config.first_reply),
            Answers::Yes => self.lost_after().map(|d| newest.sent + d),
            Answers::No => None,
        }
    }

    /// Queries written and not answered yet (given up or not): replies
    /// still on their way.
    pub fn outstanding(&self) -> usize {
        self.flights.len()
    }

    pub fn answers(&self) -> Answers {
        self.answers
    }

    /// Smoothed round trip.
    pub fn round_trip(&self) -> Option<Duration> {
        self.round_trip.map(Duration::from_secs_f64)
    }

    /// The link's throughput in bytes per second: the hold's rate (stated,
    /// or measured from the send queue) where it has one, else the one
    /// measured from the replies.
    pub fn throughput(&self) -> Option<f64> {
        self.hold.rate().or(self.throughput)
    }

    /// Whether `bytes` take longer than `interval` to reach the terminal
    /// (unknown throughput: no).
    pub fn too_slow_for(&self, bytes: u64, interval: Duration) -> bool {
        self.throughput()
            .is_some_and(|t| bytes as f64 / t > interval.as_secs_f64())
    }

    /// How long without input before input counts as stopped: about one
    /// round trip of the link itself (the shortest recent one: the
    /// smoothed figure also counts each frame's transfer, which says
    /// nothing about how input is spaced), within the configured bounds.
    pub fn quiet(&self) -> Duration {
        self.base_rtt()
            .unwrap_or(Duration::ZERO)
            .clamp(self.config.quiet_min, self.config.quiet_max)
    }

    /// Whether the next picture should be a preview: input keeps coming
    /// (`moving`) and the last exact picture (`exact_bytes`) takes the link
    /// longer than a frame `interval`.
    pub fn preview(&self, moving: bool, exact_bytes: Option<u64>, interval: Duration) -> bool {
        self.config.previews
            && moving
            && exact_bytes.is_some_and(|b| self.too_slow_for(b, interval))
    }

    pub fn info(&self) -> LinkInfo {
        LinkInfo {
            answers: self.answers,
            round_trip: self.round_trip(),
            throughput: self.throughput(),
            late_replies: self.late_replies,
            held_by: self.held_by(),
        }
    }
}

/// The pacer for this process: a stated rate holds by that rate; `auto`
/// holds by the SSH connection's send queue inside tmux or screen when one
/// is found (see [`crate::backlog::SendQueue::here`]), else the
/// replies alone pace.
pub fn pacer_here(link: LinkRate) -> Pacer {
    match link {
        LinkRate::Stated(rate) => Pacer::default().with_hold(Hold::new(HoldBy::Rate(rate)), None),
        LinkRate::Auto => match super::backlog::SendQueue::here() {
            Some(mut queue) => Pacer::default().with_hold(
                Hold::new(HoldBy::Queue),
                Some(Box::new(move || queue.queued())),
            ),
            None => Pacer::default(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fake clock: milliseconds after a fixed start.
    struct Clock(Instant);

    impl Clock {
        fn new() -> Self {
            Clock(Instant::now())
        }
        fn at(&self, ms: u64) -> Instant {
            self.0 + Duration::from_millis(ms)
        }
    }

    #[test]
    fn one_frame_in_flight_until_its_reply() {
        let c = Clock::new();
        let mut p = Pacer::default();
        assert!(p.asks() && p.ready(c.at(0)));
        p.sent(c.at(0), 25_000, true);
        assert!(!p.ready(c.at(10)));
        assert!(!p.ready(c.at(900)), "no time-out before the first one");
        p.reply(c.at(240));
        assert!(p.ready(c.at(240)));
        assert_eq!(p.answers(), Answers::Yes);
        assert_eq!(p.outstanding(), 0);
    }

    #[test]
    fn replies_are_matched_in_order() {
        let c = Clock::new();
        let mut p = Pacer::default();
        // The probe before the first frame, then the frame's own query.
        p.sent(c.at(0), 0, true);
        p.sent(c.at(0), 50_000, true);
        p.reply(c.at(40));
        assert!(
            !p.ready(c.at(40)),
            "the probe's reply does not release the frame"
        );
        assert_eq!(p.answers(), Answers::Yes);
        p.reply(c.at(440));
        assert!(p.ready(c.at(440)));
    }

    #[test]
    fn a_silent_terminal_is_paced_by_writes_after_the_time_out() {
        let c = Clock::new();
        let mut p = Pacer::default();
        p.sent(c.at(0), 25_000, true);
        assert_eq!(p.deadline(), Some(c.at(1000)));
        assert!(!p.ready(c.at(999)));
        assert!(p.ready(c.at(1000)));
        assert_eq!(p.answers(), Answers::No);
        assert!(!p.asks(), "no more queries");
        // Frames now go without queries and never wait.
        p.sent(c.at(1001), 25_000, false);
        assert!(p.ready(c.at(1001)));
        assert_eq!(p.deadline(), None);
    }

    #[test]
    fn a_late_reply_is_credited_to_its_own_query() {
        let c = Clock::new();
        let mut p = Pacer::default();
        p.sent(c.at(0), 10_000, true);
        assert!(p.ready(c.at(1000)), "given up");
        // The terminal does answer after all: the late reply is its query's.
        p.reply(c.at(1200));
        assert_eq!(p.outstanding(), 0);
        assert_eq!(p.answers(), Answers::Yes, "it answers: ask again");
        assert_eq!(p.info().late_replies, 1);
        // A new frame waits for its own reply; a stray reply with no
        // query changes nothing.
        p.sent(c.at(1300), 10_000, true);
        assert!(!p.ready(c.at(1301)));
        p.reply(c.at(1350));
        assert!(p.ready(c.at(1350)));
        p.reply(c.at(1360));
        assert!(p.ready(c.at(1360)) && p.outstanding() == 0);
    }

    #[test]
    fn a_late_reply_after_a_lost_one_does_not_release_the_newer_frame() {
        let c = Clock::new();
        let mut p = Pacer::default();
        p.sent(c.at(0), 1000, true);
        p.reply(c.at(40));
        // A frame whose reply is lost (given up after the lost-reply time).
        p.sent(c.at(100), 1000, true);
        assert!(!p.ready(c.at(2099)));
        assert!(p.ready(c.at(2100)));
        // The next frame is sent; then the old reply arrives: it belongs
        // to the abandoned query, so the new frame is still in flight.
        p.sent(c.at(2200), 1000, true);
        p.reply(c.at(2210));
        assert!(!p.ready(c.at(2210)));
        p.reply(c.at(2250));
        assert!(p.ready(c.at(2250)));
    }

    #[test]
    fn previews_only_while_input_keeps_coming_over_a_slow_link() {
        let c = Clock::new();
        let mut p = Pacer::default();
        let q = p.quiet();
        assert_eq!(q, Duration::from_millis(60));
        let frame = Duration::from_millis(33);
        let mut a = Activity::default();
        assert!(!a.moving(c.at(0), q) && a.settled_at(q).is_none());
        // A lone key after a pause: not a burst.
        a.input(c.at(1000), q);
        assert!(!a.moving(c.at(1001), q));
        // A second one 30 ms later: a burst, until 60 ms pass without input.
        a.input(c.at(1030), q);
        assert!(a.moving(c.at(1031), q) && a.moving(c.at(1089), q));
        assert!(!a.moving(c.at(1090), q));
        assert_eq!(a.settled_at(q), Some(c.at(1090)));
        // Unknown throughput: never a preview; a fast link neither.
        assert!(!p.preview(true, Some(25_000), frame));
        p.sent(c.at(0), 20, true);
        p.reply(c.at(40));
        p.sent(c.at(100), 25_000, true);
        p.reply(c.at(340));
        assert!(p.preview(true, Some(25_000), frame));
        assert!(!p.preview(false, Some(25_000), frame), "input stopped");
        assert!(!p.preview(true, Some(2_000), frame), "small enough");
        assert!(!p.preview(true, None, frame));
        // The quiet time follows the link's own round trip (40 ms here, not
        // the 240 ms the 25 kB frame took), within its bounds.
        assert_eq!(p.quiet(), Duration::from_millis(60));
        // Older samples leave the window; a slower link waits longer, up to 150 ms.
        for i in 0..RTT_WINDOW as u64 {
            p.sent(c.at(1000 + 200 * i), 20, true);
            p.reply(c.at(1000 + 200 * i + 120));
        }
        assert_eq!(p.quiet(), Duration::from_millis(120));
        for i in 0..RTT_WINDOW as u64 {
            p.sent(c.at(9000 + 500 * i), 20, true);
            p.reply(c.at(9000 + 500 * i + 400));
        }
        assert_eq!(p.quiet(), Duration::from_millis(150));
        let off = Pacer::new(PacingConfig {
            previews: false,
            ..PacingConfig::default()
        });
        assert!(!off.preview(true, Some(1 << 30), frame));
    }

    #[test]
    fn a_run_of_strips_keeps_the_base_latency_and_the_links_rate() {
        let c = Clock::new();
        let mut p = Pacer::default();
        // The probe: 40 ms with nothing queued.
        p.sent(c.at(0), 0, true);
        p.reply(c.at(40));
        // Twenty 26 kB strips at 125 kB/s, each after the last one's reply:
        // 40 + 208 ms each.
        let mut at = 100;
        for _ in 0..20 {
            p.sent(c.at(at), 26_000, true);
            p.reply(c.at(at + 248));
            at += 300;
        }
        let t = p.throughput().unwrap();
        assert!((t - 125_000.0).abs() < 1.0, "{t}");
        // Strips of background, 2.5 kB, within 5 ms of the round trip: the
        // link's bytes over its time, not their rates (500 kB/s) averaged.
        for _ in 0..6 {
            p.sent(c.at(at), 2_500, true);
            p.reply(c.at(at + 45));
            at += 100;
        }
        let t = p.throughput().unwrap();
        assert!(t < 160_000.0, "{t}");
        // A status line queued behind a frame says nothing of the latency.
        p.sent(c.at(at), 26_000, true);
        p.sent(c.at(at + 1), 300, true);
        p.reply(c.at(at + 248));
        p.reply(c.at(at + 250));
        assert_eq!(p.quiet(), Duration::from_millis(60));
    }

    #[test]
    fn round_trip_and_throughput_are_measured() {
        let c = Clock::new();
        let mut p = Pacer::default();
        assert_eq!(p.round_trip(), None);
        assert!(!p.too_slow_for(1 << 30, Duration::from_millis(33)));
        // 40 ms base latency (a tiny write), then 25 kB in 240 ms: 125 kB/s.
        p.sent(c.at(0), 20, true);
        p.reply(c.at(40));
        assert_eq!(p.round_trip(), Some(Duration::from_millis(40)));
        p.sent(c.at(100), 25_000, true);
        p.reply(c.at(340));
        let t = p.throughput().unwrap();
        assert!((t - 125_000.0).abs() < 1.0, "{t}");
        // 25 kB take 200 ms at this rate: longer than a 33 ms frame.
        assert!(p.too_slow_for(25_000, Duration::from_millis(33)));
        assert!(!p.too_slow_for(3_000, Duration::from_millis(33)));
        // Smoothed: one faster frame moves the figure part of the way.
        p.sent(c.at(400), 25_000, true);
        p.reply(c.at(540));
        let t2 = p.throughput().unwrap();
        assert!(t2 > t && t2 < 250_000.0, "{t2}");
        let rtt = p.round_trip().unwrap();
        assert!(rtt > Duration::from_millis(40) && rtt < Duration::from_millis(240));
    }

    #[test]
    fn inside_a_multiplexer_the_send_queue_holds_and_measures() {
        use crate::hold::{GRACE, POLL};
        use std::sync::{Arc, Mutex};
        let c = Clock::new();
        let queue = Arc::new(Mutex::new(Some(0u64)));
        let reads = Arc::new(Mutex::new(0));
        let (q, r) = (queue.clone(), reads.clone());
        let read: ReadQueue = Box::new(move || {
            *r.lock().unwrap() += 1;
            *q.lock().unwrap()
        });
        let mut p = Pacer::default().with_hold(Hold::new(HoldBy::Queue), Some(read));
        assert_eq!(p.held_by(), HoldBy::Queue);
        let frame = Duration::from_millis(33);
        // The multiplexer answers at once: the replies alone would let the
        // next frame go 2 ms later and call the link fast.
        p.sent(c.at(0), 20, true);
        p.reply(c.at(1));
        assert!(!p.ready(c.at(1)), "within the grace");
        assert_eq!(p.deadline(), Some(c.at(0) + GRACE));
        assert!(p.ready(c.at(20)), "the probe put nothing on the link");
        p.sent(c.at(100), 25_000, true);
        p.reply(c.at(102));
        assert!(!p.ready(c.at(102)), "within the grace");
        // The frame in the queue, as the multiplexer sent it: 28 000 bytes.
        // One frame may stay in flight (unacknowledged).
        *queue.lock().unwrap() = Some(28_000);
        assert!(p.ready(c.at(115)));
        p.sent(c.at(116), 25_000, true);
        p.reply(c.at(117));
        // Not two.
        *queue.lock().unwrap() = Some(56_000);
        assert!(!p.ready(c.at(131)));
        assert_eq!(p.deadline(), Some(c.at(131) + POLL));
        // Read once a poll, not at every look.
        let n = *reads.lock().unwrap();
        assert!(!p.ready(c.at(136)));
        assert_eq!(*reads.lock().unwrap(), n);
        // Draining at 140 kB/s of the multiplexer's bytes, 125 kB/s of
        // relief's (each of its bytes took 1.12 in the queue): 1 Mbit/s.
        *queue.lock().unwrap() = Some(54_600);
        assert!(!p.ready(c.at(141)));
        assert!((p.throughput().unwrap() - 125_000.0).abs() < 1e-6);
        assert_eq!(p.info().throughput, p.throughput());
        assert!(p.preview(true, Some(25_000), frame));
        *queue.lock().unwrap() = Some(0);
        assert!(p.ready(c.at(151)));
        assert_eq!(p.deadline(), None);
        // The socket gone (the session detached): the replies alone pace.
        p.sent(c.at(200), 25_000, true);
        p.reply(c.at(201));
        *queue.lock().unwrap() = None;
        assert!(p.ready(c.at(200) + GRACE));
    }
}

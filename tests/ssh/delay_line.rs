//! A fixed one-way delay between two interfaces of a network namespace, in user space.
//!
//! The usual tool, the `netem` queueing discipline, is missing from many kernels
//! (`CONFIG_NET_SCH_NETEM` unset). This does its job as a two-port bridge: every Ethernet
//! frame that arrives on one port is sent out of the other a fixed time later, in order.
//! The rate limit stays in the kernel (`tbf` on the ports' egress), so the delay line
//! and the bottleneck together behave like a slow router with a long wire.
//!
//! Packet sockets with a virtio-net header carry the checksum-offload and segmentation
//! state across unchanged: a frame from a veth whose checksum was left to "hardware"
//! keeps that state instead of arriving with a wrong checksum.

use std::fs::File;
use std::io;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// `<linux/if_packet.h>`: the socket option that adds the virtio-net header.
const PACKET_VNET_HDR: libc::c_int = 15;
/// `<linux/if_packet.h>`: a frame this host sent (seen by a packet socket too).
const PACKET_OUTGOING: u8 = 4;
/// Size of `struct virtio_net_hdr`.
const VNET_HDR_LEN: usize = 10;

/// The running bridge; dropping it stops and joins its threads.
pub struct DelayLine {
    stop: Arc<AtomicBool>,
    threads: Vec<JoinHandle<()>>,
}

impl DelayLine {
    /// Bridges interfaces `a` and `b` of the named namespace (`ip netns` name),
    /// delaying each frame by `delay`.
    pub fn start(netns: &str, a: &str, b: &str, delay: Duration) -> io::Result<DelayLine> {
        let (a, b) = (a.to_string(), b.to_string());
        let (fa, fb) = in_namespace(netns, move || Ok((packet_socket(&a)?, packet_socket(&b)?)))?;
        let (fa, fb) = (Arc::new(fa), Arc::new(fb));
        let stop = Arc::new(AtomicBool::new(false));
        let mut threads = Vec::new();
        for (from, to) in [(fa.clone(), fb.clone()), (fb, fa)] {
            let (tx, rx) = mpsc::channel::<(Instant, Vec<u8>)>();
            let s = stop.clone();
            threads.push(std::thread::spawn(move || receive(&from, &tx, delay, &s)));
            let s = stop.clone();
            threads.push(std::thread::spawn(move || send(&to, &rx, &s)));
        }
        Ok(DelayLine { stop, threads })
    }
}

impl Drop for DelayLine {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }
}

/// Runs `f` on a thread that has joined the named network namespace (`ip netns`
/// name), so the test's own threads stay where they are. Sockets made there keep
/// their namespace wherever they are used afterwards.
pub fn in_namespace<T: Send + 'static>(
    netns: &str,
    f: impl FnOnce() -> io::Result<T> + Send + 'static,
) -> io::Result<T> {
    let path = format!("/run/netns/{netns}");
    std::thread::spawn(move || {
        let ns = File::open(path)?;
        // SAFETY: setns on a valid descriptor affects only this thread.
        if unsafe { libc::setns(ns.as_raw_fd(), libc::CLONE_NEWNET) } != 0 {
            return Err(io::Error::last_os_error());
        }
        f()
    })
    .join()
    .expect("the namespace thread does not panic")
}

/// A raw packet socket on one interface, with the virtio-net header, a short
/// receive time-out (so the threads notice `stop`) and large buffers.
fn packet_socket(interface: &str) -> io::Result<OwnedFd> {
    let all = (libc::ETH_P_ALL as u16).to_be();
    // SAFETY: plain socket calls on a descriptor this function owns; every
    // pointer passed points at a live local of the size given.
    unsafe {
        let raw = libc::socket(libc::AF_PACKET, libc::SOCK_RAW, all as libc::c_int);
        if raw < 0 {
            return Err(io::Error::last_os_error());
        }
        let fd = OwnedFd::from_raw_fd(raw);
        let name = std::ffi::CString::new(interface).expect("no NUL in an interface name");
        let index = libc::if_nametoindex(name.as_ptr());
        if index == 0 {
            return Err(io::Error::last_os_error());
        }
        let one: libc::c_int = 1;
        let big: libc::c_int = 4 << 20;
        let timeout = libc::timeval {
            tv_sec: 0,
            tv_usec: 50_000,
        };
        let opts: [(libc::c_int, libc::c_int, *const libc::c_void, usize); 4] = [
            (
                libc::SOL_PACKET,
                PACKET_VNET_HDR,
                (&raw const one).cast(),
                size_of_val(&one),
            ),
            (
                libc::SOL_SOCKET,
                libc::SO_RCVBUF,
                (&raw const big).cast(),
                size_of_val(&big),
            ),
            (
                libc::SOL_SOCKET,
                libc::SO_SNDBUF,
                (&raw const big).cast(),
                size_of_val(&big),
            ),
            (
                libc::SOL_SOCKET,
                libc::SO_RCVTIMEO,
                (&raw const timeout).cast(),
                size_of_val(&timeout),
            ),
        ];
        for (level, opt, value, len) in opts {
            if libc::setsockopt(raw, level, opt, value, len as libc::socklen_t) != 0 {
                return Err(io::Error::last_os_error());
            }
        }
        let mut addr: libc::sockaddr_ll = std::mem::zeroed();
        addr.sll_family = libc::AF_PACKET as u16;
        addr.sll_protocol = all;
        addr.sll_ifindex = index as libc::c_int;
        let len = size_of_val(&addr) as libc::socklen_t;
        if libc::bind(raw, (&raw const addr).cast(), len) != 0 {
            return Err(io::Error::last_os_error());
        }
        Ok(fd)
    }
}

/// Reads frames arriving on `from` and queues them with the time they are due.
fn receive(
    from: &OwnedFd,
    queue: &mpsc::Sender<(Instant, Vec<u8>)>,
    delay: Duration,
    stop: &AtomicBool,
) {
    let mut buf = vec![0u8; VNET_HDR_LEN + 65_536];
    while !stop.load(Ordering::Relaxed) {
        // SAFETY: the buffer and the address are live locals of the sizes given.
        let (n, kind) = unsafe {
            let mut addr: libc::sockaddr_ll = std::mem::zeroed();
            let mut len = size_of_val(&addr) as libc::socklen_t;
            let n = libc::recvfrom(
                from.as_raw_fd(),
                buf.as_mut_ptr().cast(),
                buf.len(),
                0,
                (&raw mut addr).cast(),
                &mut len,
            );
            (n, addr.sll_pkttype)
        };
        // A time-out (checks `stop`), or a frame this port itself sent.
        if n <= 0 || kind == PACKET_OUTGOING {
            continue;
        }
        let due = Instant::now() + delay;
        if queue.send((due, buf[..n as usize].to_vec())).is_err() {
            return;
        }
    }
}

/// Sends each queued frame out of `to` once it is due. A frame the full
/// queue of the rate limit refuses is lost, as on a router.
fn send(to: &OwnedFd, queue: &mpsc::Receiver<(Instant, Vec<u8>)>, stop: &AtomicBool) {
    while !stop.load(Ordering::Relaxed) {
        let (due, frame) = match queue.recv_timeout(Duration::from_millis(50)) {
            Ok(item) => item,
            Err(mpsc::RecvTimeoutError::Timeout) => continue,
            Err(mpsc::RecvTimeoutError::Disconnected) => return,
        };
        let now = Instant::now();
        if due > now {
            std::thread::sleep(due - now);
        }
        // SAFETY: the frame is a live buffer of the length given.
        unsafe {
            libc::send(to.as_raw_fd(), frame.as_ptr().cast(), frame.len(), 0);
        }
    }
}

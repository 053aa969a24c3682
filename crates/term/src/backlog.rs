//! The SSH connection's send queue: the link as seen from inside tmux or
//! GNU screen on the server.
//!
//! A multiplexer answers the pacing query itself, at once, and then queues
//! every frame towards its slow client, so replies say nothing about the
//! link (see [`crate::pacing`]). The kernel does know: the socket of
//! the SSH connection holds what is written and not yet acknowledged by the
//! client, and `/proc/net/tcp` (IPv4) and `/proc/net/tcp6` show it as
//! `tx_queue` to any process. The socket is the one `SSH_CONNECTION` names
//! (`client-ip client-port server-ip server-port`): its local end is the
//! server's pair, its remote end the client's. Inside tmux the variable in
//! relief's own environment is the one the pane was started with; tmux keeps
//! the current one (updated when a client attaches) in the session's
//! environment, which `tmux show-environment` prints.
//!
//! Measured through a real SSH session at 1 Mbit/s (`tests/ssh_link.rs`,
//! docs/ssh-tmux.md): the queue reads 0 when the link is idle and rises to
//! the kernel's send buffer (about 80 kB) while tmux floods the link.

use std::net::{IpAddr, Ipv4Addr, Ipv6Addr, SocketAddr};
use std::time::{Duration, Instant};

/// The two ends of an SSH connection, as `SSH_CONNECTION` names them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SshConnection {
    pub client: SocketAddr,
    pub server: SocketAddr,
}

/// `client-ip client-port server-ip server-port`; `None` for anything else.
pub fn parse_ssh_connection(text: &str) -> Option<SshConnection> {
    let words: Vec<&str> = text.split_whitespace().collect();
    let [cip, cport, sip, sport] = words[..] else {
        return None;
    };
    // An IPv6 address may carry a zone (`fe80::1%eth0`): the table has none.
    let ip = |s: &str| s.split('%').next()?.parse::<IpAddr>().ok();
    Some(SshConnection {
        client: SocketAddr::new(ip(cip)?, cport.parse().ok()?),
        server: SocketAddr::new(ip(sip)?, sport.parse().ok()?),
    })
}

/// What `tmux show-environment SSH_CONNECTION` prints: `NAME=value`, or
/// `-NAME` when the variable was removed (no SSH client attached).
pub fn parse_tmux_environment(text: &str) -> Option<SshConnection> {
    let value = text.lines().next()?.strip_prefix("SSH_CONNECTION=")?;
    parse_ssh_connection(value)
}

/// An IPv4-mapped IPv6 address (`::ffff:a.b.c.d`, how a dual-stack sshd's
/// IPv4 connections appear in `tcp6`) as IPv4; the rest as they are.
fn canonical(addr: SocketAddr) -> SocketAddr {
    match addr.ip() {
        IpAddr::V6(v6) => match v6.to_ipv4_mapped() {
            Some(v4) => SocketAddr::new(IpAddr::V4(v4), addr.port()),
            None => addr,
        },
        IpAddr::V4(_) => addr,
    }
}

/// A table address `ADDR:PORT`: the port in hexadecimal, the address as
/// the kernel's 32-bit words (one for IPv4, four for IPv6), each printed
/// in hexadecimal as the machine stores it (host byte order).
fn parse_table_addr(text: &str) -> Option<SocketAddr> {
    let (addr, port) = text.split_once(':')?;
    let port = u16::from_str_radix(port, 16).ok()?;
    let word = |i: usize| -> Option<[u8; 4]> {
        let hex = addr.get(8 * i..8 * i + 8)?;
        Some(u32::from_str_radix(hex, 16).ok()?.to_ne_bytes())
    };
    let ip = match addr.len() {
        8 => IpAddr::V4(Ipv4Addr::from(word(0)?)),
        32 => {
            let mut octets = [0u8; 16];
            for i in 0..4 {
                octets[4 * i..4 * i + 4].copy_from_slice(&word(i)?);
            }
            IpAddr::V6(Ipv6Addr::from(octets))
        }
        _ => return None,
    };
    Some(SocketAddr::new(ip, port))
}

/// One line of `/proc/net/tcp` or `/proc/net/tcp6`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SocketLine {
    /// IPv4-mapped addresses as IPv4.
    pub local: SocketAddr,
    pub remote: SocketAddr,
    /// The kernel's TCP state (1: established, 10: listening).
    pub state: u8,
    /// Bytes written and not yet acknowledged by the other end.
    pub tx_queue: u64,
}

/// The lines of a `/proc/net/tcp` or `/proc/net/tcp6` text that parse.
pub fn sockets(table: &str) -> impl Iterator<Item = SocketLine> + '_ {
    table.lines().skip(1).filter_map(|line| {
        // sl local rem st tx_queue:rx_queue ...
        let mut fields = line.split_whitespace().skip(1);
        let local = canonical(parse_table_addr(fields.next()?)?);
        let remote = canonical(parse_table_addr(fields.next()?)?);
        let state = u8::from_str_radix(fields.next()?, 16).ok()?;
        let (tx, _rx) = fields.next()?.split_once(':')?;
        Some(SocketLine {
            local,
            remote,
            state,
            tx_queue: u64::from_str_radix(tx, 16).ok()?,
        })
    })
}

/// The send queue (bytes written and not yet acknowledged) of the socket
/// whose local end is the connection's server and remote end its client,
/// in the text of `/proc/net/tcp` or `/proc/net/tcp6`; `None` when no line
/// matches.
pub fn queued_in(table: &str, conn: &SshConnection) -> Option<u64> {
    let (server, client) = (canonical(conn.server), canonical(conn.client));
    sockets(table)
        .find(|s| s.local == server && s.remote == client)
        .map(|s| s.tx_queue)
}

/// The terminal multiplexer relief runs in, from its environment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Multiplexer {
    Tmux,
    Screen,
}

impl Multiplexer {
    /// `TMUX` set: tmux; `STY` set: GNU screen; else none.
    pub fn detect(tmux: Option<&str>, sty: Option<&str>) -> Option<Multiplexer> {
        let set = |v: Option<&str>| v.is_some_and(|v| !v.is_empty());
        if set(tmux) {
            Some(Multiplexer::Tmux)
        } else if set(sty) {
            Some(Multiplexer::Screen)
        } else {
            None
        }
    }
}

/// How often the connection is looked up again when its socket is gone
/// (tmux re-attached from another connection).
const RELOOK: Duration = Duration::from_secs(1);

/// The send queue of this process's SSH connection, read live.
#[derive(Debug)]
pub struct SendQueue {
    mux: Multiplexer,
    conn: Option<SshConnection>,
    looked: Instant,
}

impl SendQueue {
    /// The queue to watch here: only inside a multiplexer with an SSH
    /// connection known (plain SSH paces by the replies; a local tmux has
    /// no link to wait for).
    pub fn here() -> Option<SendQueue> {
        let env = |name| std::env::var(name).ok();
        let mux = Multiplexer::detect(env("TMUX").as_deref(), env("STY").as_deref())?;
        let conn = current_connection(mux)?;
        Some(SendQueue {
            mux,
            conn: Some(conn),
            looked: Instant::now(),
        })
    }

    /// The connection watched.
    pub fn connection(&self) -> Option<SshConnection> {
        self.conn
    }

    /// Bytes queued on the connection now; `None` when its socket is not
    /// found (then the connection is looked up again, at most once a second).
    pub fn queued(&mut self) -> Option<u64> {
        let found = self.conn.and_then(|c| read_queue(&c));
        if found.is_none() && self.looked.elapsed() >= RELOOK {
            self.looked = Instant::now();
            self.conn = current_connection(self.mux);
        }
        found
    }
}

/// The connection the multiplexer's client comes through now.
fn current_connection(mux: Multiplexer) -> Option<SshConnection> {
    if mux == Multiplexer::Tmux {
        let out = crate::depth::run_briefly(
            "tmux",
            &["show-environment", "SSH_CONNECTION"],
            Duration::from_millis(500),
        );
        if let Some(out) = out {
            // tmux answered: its word is the current one (`-SSH_CONNECTION`:
            // the attached client is not an SSH one).
            return parse_tmux_environment(&out);
        }
    }
    parse_ssh_connection(&std::env::var("SSH_CONNECTION").ok()?)
}

/// The connection's send queue from this process's network namespace.
fn read_queue(conn: &SshConnection) -> Option<u64> {
    let file = match canonical(conn.server).ip() {
        // A dual-stack sshd lists IPv4 connections in tcp6 (mapped).
        IpAddr::V4(_) => ["/proc/net/tcp", "/proc/net/tcp6"].as_slice(),
        IpAddr::V6(_) => ["/proc/net/tcp6"].as_slice(),
    };
    file.iter().find_map(|path| {
        let table = std::fs::read_to_string(path).ok()?;
        queued_in(&table, conn)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn conn(text: &str) -> SshConnection {
        parse_ssh_connection(text).unwrap()
    }

    #[test]
    fn ssh_connection_is_read_from_its_four_words() {
        let c = conn("10.77.0.1 50000 10.77.0.2 2222");
        assert_eq!(c.client, "10.77.0.1:50000".parse().unwrap());
        assert_eq!(c.server, "10.77.0.2:2222".parse().unwrap());
        let c = conn("2001:db8::5 41000 fe80::1%eth0 22");
        assert_eq!(c.client, "[2001:db8::5]:41000".parse().unwrap());
        assert_eq!(c.server, "[fe80::1]:22".parse().unwrap());
        for bad in [
            "",
            "10.0.0.1 1 10.0.0.2",
            "a b c d",
            "10.0.0.1 70000 10.0.0.2 22",
        ] {
            assert_eq!(parse_ssh_connection(bad), None, "{bad}");
        }
        assert_eq!(
            parse_tmux_environment("SSH_CONNECTION=10.77.0.1 50000 10.77.0.2 2222\n"),
            Some(c_v4())
        );
        assert_eq!(parse_tmux_environment("-SSH_CONNECTION\n"), None);
        assert_eq!(parse_tmux_environment(""), None);
    }

    fn c_v4() -> SshConnection {
        conn("10.77.0.1 50000 10.77.0.2 2222")
    }

    #[test]
    fn multiplexer_from_the_environment() {
        let d = Multiplexer::detect;
        assert_eq!(
            d(Some("/tmp/tmux-0/default,12,0"), None),
            Some(Multiplexer::Tmux)
        );
        assert_eq!(d(None, Some("1234.pts-0.host")), Some(Multiplexer::Screen));
        assert_eq!(d(Some(""), Some("")), None);
        assert_eq!(d(None, None), None);
    }

    // The tables below are written as a little-endian machine prints them.
    #[cfg(target_endian = "little")]
    #[test]
    fn the_queue_of_the_matching_ipv4_socket() {
        // 10.77.0.2 = 0x0A4D0002 in network order: stored bytes 0A 4D 00 02,
        // printed as the little-endian word 02004D0A. Port 2222 = 0x08AE,
        // 50000 = 0xC350, 50001 = 0xC351.
        let table = "  sl  local_address rem_address   st tx_queue rx_queue tr tm->when retrnsmt   uid  timeout inode\n\
   0: 02004D0A:08AE 00000000:0000 0A 00000000:00000000 00:00000000 00000000     0        0 100 1 0 100 0 0 10 0\n\
   1: 02004D0A:08AE 01004D0A:C351 01 00000400:00000000 01:00000014 00000000     0        0 101 4 0 20 4 30 10 -1\n\
   2: 02004D0A:08AE 01004D0A:C350 01 00013A10:00000000 01:00000014 00000000     0        0 102 4 0 20 4 30 10 -1\n";
        assert_eq!(queued_in(table, &c_v4()), Some(0x13A10));
        let lines: Vec<SocketLine> = sockets(table).collect();
        assert_eq!(lines.len(), 3);
        assert_eq!((lines[0].state, lines[2].state), (0x0A, 1));
        assert_eq!(lines[0].remote, "0.0.0.0:0".parse().unwrap());
        // The client's other connection, the listener and a wrong port are not it.
        let other = conn("10.77.0.1 50001 10.77.0.2 2222");
        assert_eq!(queued_in(table, &other), Some(0x400));
        assert_eq!(
            queued_in(table, &conn("10.77.0.1 50002 10.77.0.2 2222")),
            None
        );
        // Client and server swapped: the ends are not the same.
        assert_eq!(
            queued_in(table, &conn("10.77.0.2 2222 10.77.0.1 50000")),
            None
        );
        assert_eq!(queued_in("", &c_v4()), None);
        assert_eq!(queued_in("header\n   0: garbage\n", &c_v4()), None);
    }

    #[cfg(target_endian = "little")]
    #[test]
    fn the_queue_of_an_ipv6_or_mapped_socket() {
        // ::ffff:10.77.0.2 is the words 00000000 00000000 0000FFFF 02004D0A
        // (each little-endian: 00000000 00000000 FFFF0000 02004D0A).
        // 2001:db8::2 = words 20010db8 0 0 00000002: printed B80D0120
        // 00000000 00000000 02000000.
        let table = "  sl  local_address                         remote_address                        st tx_queue rx_queue tr tm->when retrnsmt   uid  timeout inode\n\
   0: 0000000000000000FFFF000002004D0A:08AE 0000000000000000FFFF000001004D0A:C350 01 00000C00:00000000 01:00000014 00000000     0        0 7 4 0 20 4 30 10 -1\n\
   1: B80D0120000000000000000002000000:0016 B80D0120000000000000000005000000:A028 01 00000001:00000000 01:00000014 00000000     0        0 8 4 0 20 4 30 10 -1\n";
        // sshd prints an IPv4-mapped client as plain IPv4.
        assert_eq!(queued_in(table, &c_v4()), Some(0xC00));
        let v6 = conn("2001:db8::5 41000 2001:db8::2 22");
        assert_eq!(queued_in(table, &v6), Some(1));
        assert_eq!(
            parse_table_addr("B80D0120000000000000000002000000:0016"),
            Some("[2001:db8::2]:22".parse().unwrap())
        );
        assert_eq!(
            parse_table_addr("0100007F:0016"),
            Some("127.0.0.1:22".parse().unwrap())
        );
        assert_eq!(parse_table_addr("0100007F"), None);
        assert_eq!(parse_table_addr("01007F:0016"), None);
    }
}

//! Simulated hosts: network namespaces joined to the test's namespace by veth pairs, and a TCP
//! forwarder that lets them reach the PostgreSQL server on 127.0.0.1 without touching its
//! configuration.
//!
//! Each [`Host`] is a namespace with one veth link `10.213.P.(4k+2)/30 ↔ 10.213.P.(4k+1)/30`
//! (P from this process id, k the host number), so runs in parallel use distinct names and
//! addresses. Dropping a [`Host`] deletes its namespace and link. Needs root and `ip netns`.

use std::net::{Ipv4Addr, SocketAddr};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicU8, Ordering};

use tokio::net::{TcpListener, TcpStream};
use tokio::task::JoinHandle;

/// Why the network-fault tests cannot run here, or `None` when they can.
pub fn unavailable() -> Option<String> {
    // `ip netns add` needs uid 0.
    let uid = std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find_map(|l| l.strip_prefix("Uid:"))
                .and_then(|l| l.split_whitespace().next().map(str::to_owned))
        });
    if uid.as_deref() != Some("0") {
        return Some("not running as root".into());
    }
    let probe = format!("mfprobe{}", std::process::id());
    let added = run_ip(&["netns", "add", &probe]);
    let _ = run_ip(&["netns", "del", &probe]);
    added
        .err()
        .map(|e| format!("`ip netns` is unavailable: {e}"))
}

fn run_ip(args: &[&str]) -> Result<(), String> {
    let out = Command::new("ip")
        .args(args)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("ip {}: {e}", args.join(" ")))?;
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "ip {}: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        ))
    }
}

static NEXT_HOST: AtomicU8 = AtomicU8::new(0);

/// A network namespace with a veth link to the test's namespace.
pub struct Host {
    /// Namespace name.
    pub name: String,
    /// Host-side interface (in the test's namespace).
    pub host_if: String,
    /// Address of the host side: where the namespace reaches the forwarder.
    pub host_addr: Ipv4Addr,
    /// Address inside the namespace.
    pub ns_addr: Ipv4Addr,
}

impl Host {
    /// Creates the namespace, the veth pair and their addresses, and brings the link up.
    pub fn create() -> Result<Self, String> {
        let k = NEXT_HOST.fetch_add(1, Ordering::Relaxed);
        assert!(k < 64, "at most 64 hosts per test process");
        let pid = std::process::id();
        let subnet = (pid % 250) as u8;
        let host = Host {
            name: format!("mfnf{pid}h{k}"),
            host_if: format!("mfh{}x{k}", pid % 1_000_000),
            host_addr: Ipv4Addr::new(10, 213, subnet, 4 * k + 1),
            ns_addr: Ipv4Addr::new(10, 213, subnet, 4 * k + 2),
        };
        let ns_if = format!("mfn{}x{k}", pid % 1_000_000);
        run_ip(&["netns", "add", &host.name])?;
        // From here on Drop cleans up whatever was made.
        run_ip(&[
            "link",
            "add",
            &host.host_if,
            "type",
            "veth",
            "peer",
            "name",
            &ns_if,
            "netns",
            &host.name,
        ])?;
        let host_cidr = format!("{}/30", host.host_addr);
        let ns_cidr = format!("{}/30", host.ns_addr);
        run_ip(&["addr", "add", &host_cidr, "dev", &host.host_if])?;
        run_ip(&["link", "set", &host.host_if, "up"])?;
        let in_ns = |args: &[&str]| {
            let mut all = vec!["netns", "exec", host.name.as_str(), "ip"];
            all.extend_from_slice(args);
            run_ip(&all)
        };
        in_ns(&["addr", "add", &ns_cidr, "dev", &ns_if])?;
        in_ns(&["link", "set", &ns_if, "up"])?;
        in_ns(&["link", "set", "lo", "up"])?;
        Ok(host)
    }

    /// Cuts the link (the host side goes down; packets in both directions are lost).
    pub fn cut(&self) {
        run_ip(&["link", "set", &self.host_if, "down"]).expect("cut link");
    }

    /// Restores the link.
    pub fn restore(&self) {
        run_ip(&["link", "set", &self.host_if, "up"]).expect("restore link");
    }

    /// `ip netns exec NAME`: append a program and its arguments to run it inside.
    pub fn launcher(&self) -> Command {
        let mut command = Command::new("ip");
        command.args(["netns", "exec", &self.name]);
        command
    }
}

impl Drop for Host {
    fn drop(&mut self) {
        // Deleting the namespace removes its end of the pair, which removes both ends; the
        // explicit delete covers a namespace that was never populated.
        let _ = run_ip(&["link", "del", &self.host_if]);
        if let Err(e) = run_ip(&["netns", "del", &self.name]) {
            eprintln!("clean-up of {}: {e}", self.name);
        }
    }
}

/// Forwards TCP connections arriving at `listen` to `target`, each in a task of its own,
/// until dropped.
pub struct Forwarder {
    /// Where it listens.
    pub addr: SocketAddr,
    task: JoinHandle<()>,
}

impl Forwarder {
    /// Listens on `ip` (port chosen by the system) and forwards to `target`.
    pub async fn start(ip: Ipv4Addr, target: SocketAddr) -> std::io::Result<Self> {
        let listener = TcpListener::bind((ip, 0)).await?;
        let addr = listener.local_addr()?;
        let task = tokio::spawn(async move {
            while let Ok((mut inbound, _)) = listener.accept().await {
                tokio::spawn(async move {
                    if let Ok(mut outbound) = TcpStream::connect(target).await {
                        let _ = tokio::io::copy_bidirectional(&mut inbound, &mut outbound).await;
                    }
                });
            }
        });
        Ok(Self { addr, task })
    }
}

impl Drop for Forwarder {
    fn drop(&mut self) {
        self.task.abort();
    }
}

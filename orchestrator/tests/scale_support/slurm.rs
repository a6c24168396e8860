//! A one-node Slurm cluster on this machine, for the test that runs the project's batch script
//! under a real scheduler: `munged`, `slurmctld` and `slurmd` (Debian's `munge` and
//! `slurm-wlm`) started in the foreground by the test, with every file they write (key,
//! socket, configuration, state, spool, logs, pid files) in a temporary directory and ports
//! chosen free, so that a Slurm already installed on the machine is neither used nor
//! disturbed. Settings that work in a container: process tracking through `/proc`, no task
//! plugin, no cgroups, no accounting, everything as root.
//!
//! Clients (`sbatch`, `squeue`, `scontrol`, `scancel`, `sinfo`) are pointed at the cluster by
//! `SLURM_CONF`, which batch jobs inherit with `--export=ALL`. Dropping the cluster cancels its
//! jobs, stops the three daemons by pid (also when the test panics), then ends any process
//! left that carries this cluster's `SLURM_CONF` in its environment (job steps and the jobs'
//! own processes, which `slurmd` starts detached): no other process is touched.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;
use std::fs;
use std::io::Read;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Name of the single compute node.
const NODE: &str = "moorfret-node";
/// Seconds Slurm waits between SIGTERM and SIGKILL when it ends a job (`KillWait`).
pub const KILL_WAIT_S: u64 = 10;

/// Programs the cluster needs.
const PROGRAMS: [&str; 9] = [
    "munged",
    "slurmctld",
    "slurmd",
    "sbatch",
    "squeue",
    "scontrol",
    "scancel",
    "sinfo",
    "kill",
];

/// Why a Slurm cluster cannot be started here (not root, a program missing), or `None`.
pub fn unavailable() -> Option<String> {
    let root = fs::read_to_string("/proc/self/status")
        .map(|s| s.lines().any(|l| l.starts_with("Uid:\t0\t")))
        .unwrap_or(false);
    if !root {
        return Some("not running as root (the Slurm daemons run as root)".into());
    }
    let missing: Vec<&str> = PROGRAMS
        .iter()
        .copied()
        .filter(|p| find_program(p).is_none())
        .collect();
    if !missing.is_empty() {
        return Some(format!(
            "{} not found (apt-get install slurm-wlm munge)",
            missing.join(", ")
        ));
    }
    None
}

/// `program` on PATH, or in the system directories the daemons live in.
fn find_program(program: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .chain(["/usr/sbin", "/sbin", "/usr/bin"].map(PathBuf::from))
        .map(|dir| dir.join(program))
        .find(|p| p.is_file())
}

/// Path of `name` as [`find_program`] finds it (the bare name if it does not).
fn program(name: &str) -> PathBuf {
    find_program(name).unwrap_or_else(|| PathBuf::from(name))
}

/// One daemon started by the cluster.
struct Daemon {
    name: &'static str,
    child: Child,
    log: PathBuf,
}

/// The state of one task of a job array, from `scontrol show job`.
#[derive(Debug, Clone)]
pub struct TaskInfo {
    /// Job id of the task.
    pub job_id: u64,
    /// Array index (text, as a pending range such as `2-3` is one record).
    pub array_task: String,
    /// `PENDING`, `RUNNING`, `COMPLETED`, `CANCELLED`, `TIMEOUT`…
    pub state: String,
    /// `exit:signal` of the batch script.
    pub exit_code: String,
    /// Start and end, s since the epoch (`None` while unknown).
    pub start_s: Option<i64>,
    /// End (or expected end while running), s since the epoch.
    pub end_s: Option<i64>,
}

impl TaskInfo {
    /// Whether the task has ended and its processes are gone.
    pub fn finished(&self) -> bool {
        matches!(
            self.state.as_str(),
            "COMPLETED"
                | "CANCELLED"
                | "TIMEOUT"
                | "FAILED"
                | "NODE_FAIL"
                | "PREEMPTED"
                | "OUT_OF_MEMORY"
                | "BOOT_FAIL"
                | "DEADLINE"
        )
    }
}

/// A running one-node cluster; stopped when dropped.
pub struct SlurmCluster {
    dir: tempfile::TempDir,
    conf: PathBuf,
    daemons: Vec<Daemon>,
    /// Exited job-step processes present before the cluster started (not its own).
    earlier_step_zombies: HashSet<u32>,
}

impl SlurmCluster {
    /// Writes the configuration and starts `munged`, `slurmctld` and `slurmd`; returns once
    /// the node is idle. Panics (stopping what was started) if the cluster does not come up.
    pub fn start() -> Self {
        let dir = tempfile::tempdir().expect("temporary directory");
        // munged requires every directory above its socket to be searchable by all.
        fs::set_permissions(dir.path(), fs::Permissions::from_mode(0o755))
            .expect("make the cluster directory searchable");
        let conf = dir.path().join("slurm.conf");
        let mut cluster = Self {
            dir,
            conf,
            daemons: Vec::new(),
            earlier_step_zombies: step_zombies(),
        };
        for sub in ["state", "spool", "log", "run", "jobs"] {
            fs::create_dir(cluster.path(sub)).expect("cluster directory");
        }
        let munge = cluster.path("munge");
        fs::create_dir(&munge).expect("munge directory");
        fs::set_permissions(&munge, fs::Permissions::from_mode(0o711)).expect("munge directory");
        let key = munge.join("munge.key");
        let mut bytes = vec![0_u8; 1024];
        fs::File::open("/dev/urandom")
            .and_then(|mut f| f.read_exact(&mut bytes))
            .expect("random munge key");
        fs::write(&key, &bytes).expect("write munge key");
        fs::set_permissions(&key, fs::Permissions::from_mode(0o400)).expect("munge key mode");
        let socket = munge.join("munge.socket");
        fs::write(&cluster.conf, cluster.configuration(&socket)).expect("write slurm.conf");

        let mut munged = Command::new(program("munged"));
        munged
            .arg("--foreground")
            .arg(format!("--key-file={}", key.display()))
            .arg(format!("--socket={}", socket.display()))
            .arg(format!("--pid-file={}", munge.join("munged.pid").display()))
            .arg(format!(
                "--seed-file={}",
                munge.join("munged.seed").display()
            ));
        cluster.spawn("munged", munged);
        cluster.wait_for("the munge socket", Duration::from_secs(10), |c| {
            c.daemons_alive();
            socket.exists()
        });
        let mut slurmctld = Command::new(program("slurmctld"));
        slurmctld.arg("-D").arg("-f").arg(&cluster.conf);
        cluster.spawn("slurmctld", slurmctld);
        let mut slurmd = Command::new(program("slurmd"));
        slurmd
            .arg("-D")
            .args(["-N", NODE])
            .arg("-f")
            .arg(&cluster.conf);
        cluster.spawn("slurmd", slurmd);
        cluster.wait_for("the node to be idle", Duration::from_secs(60), |c| {
            c.daemons_alive();
            let out = c
                .client("sinfo")
                .args(["-h", "-n", NODE, "-o", "%T"])
                .output();
            out.is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "idle")
        });
        cluster
    }

    /// `relative` inside the cluster's directory.
    pub fn path(&self, relative: &str) -> PathBuf {
        self.dir.path().join(relative)
    }

    /// Directory the test's batch jobs write their output to.
    pub fn jobs_dir(&self) -> PathBuf {
        self.path("jobs")
    }

    fn configuration(&self, munge_socket: &Path) -> String {
        let host = fs::read_to_string("/proc/sys/kernel/hostname")
            .map(|h| h.trim().split('.').next().unwrap_or("localhost").to_owned())
            .unwrap_or_else(|_| "localhost".into());
        let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
        let [ctld_port, slurmd_port] = free_ports();
        let p = |sub: &str| self.path(sub).display().to_string();
        let mut text = String::new();
        let lines = [
            "ClusterName=moorfrettest".to_owned(),
            format!("SlurmctldHost={host}(127.0.0.1)"),
            format!("SlurmctldPort={ctld_port}"),
            format!("SlurmdPort={slurmd_port}"),
            "SlurmUser=root".into(),
            "SlurmdUser=root".into(),
            "AuthType=auth/munge".into(),
            "CredType=cred/munge".into(),
            format!("AuthInfo=socket={}", munge_socket.display()),
            format!("StateSaveLocation={}", p("state")),
            format!("SlurmdSpoolDir={}", p("spool")),
            format!("SlurmctldPidFile={}", p("run/slurmctld.pid")),
            format!("SlurmdPidFile={}", p("run/slurmd.pid")),
            format!("SlurmctldLogFile={}", p("log/slurmctld.log")),
            format!("SlurmdLogFile={}", p("log/slurmd.log")),
            "ProctrackType=proctrack/linuxproc".into(),
            "TaskPlugin=task/none".into(),
            "JobAcctGatherType=jobacct_gather/none".into(),
            "AccountingStorageType=accounting_storage/none".into(),
            "JobCompType=jobcomp/none".into(),
            "SwitchType=switch/none".into(),
            "MpiDefault=none".into(),
            "MailProg=/bin/true".into(),
            "SelectType=select/cons_tres".into(),
            "SelectTypeParameters=CR_CPU".into(),
            "SchedulerType=sched/builtin".into(),
            "ReturnToService=2".into(),
            "MessageTimeout=10".into(),
            "SlurmdTimeout=60".into(),
            format!("KillWait={KILL_WAIT_S}"),
            // Finished jobs stay visible to scontrol for the rest of the test.
            "MinJobAge=900".into(),
            "InactiveLimit=0".into(),
            format!(
                "NodeName={NODE} NodeAddr=127.0.0.1 NodeHostname={host} CPUs={cpus} \
                 RealMemory=1024 State=UNKNOWN"
            ),
            format!("PartitionName=moorfret Nodes={NODE} Default=YES MaxTime=INFINITE State=UP"),
        ];
        for line in lines {
            let _ = writeln!(text, "{line}");
        }
        text
    }

    fn spawn(&mut self, name: &'static str, mut command: Command) {
        let log = self.path(&format!("log/{name}.out"));
        let file = fs::File::create(&log).expect("daemon log");
        let child = command
            .env("SLURM_CONF", &self.conf)
            .stdin(Stdio::null())
            .stdout(file.try_clone().expect("daemon log"))
            .stderr(file)
            .spawn()
            .unwrap_or_else(|e| panic!("start {name}: {e}"));
        self.daemons.push(Daemon { name, child, log });
    }

    /// Panics with its log if a daemon has exited.
    fn daemons_alive(&mut self) {
        for daemon in &mut self.daemons {
            if let Ok(Some(status)) = daemon.child.try_wait() {
                panic!(
                    "{} exited ({status}):\n{}",
                    daemon.name,
                    fs::read_to_string(&daemon.log).unwrap_or_default()
                );
            }
        }
    }

    fn wait_for(&mut self, what: &str, limit: Duration, mut ready: impl FnMut(&mut Self) -> bool) {
        let start = Instant::now();
        while !ready(self) {
            if start.elapsed() > limit {
                panic!("timed out waiting for {what}\n{}", self.logs());
            }
            std::thread::sleep(Duration::from_millis(200));
        }
    }

    /// The daemons' logs, for failure messages.
    pub fn logs(&self) -> String {
        let mut text = String::new();
        for name in ["log/munged.out", "log/slurmctld.log", "log/slurmd.log"] {
            let body = fs::read_to_string(self.path(name)).unwrap_or_default();
            let tail: Vec<&str> = body.lines().rev().take(40).collect();
            let _ = writeln!(text, "--- {name} (last lines)");
            for line in tail.into_iter().rev() {
                let _ = writeln!(text, "{line}");
            }
        }
        text
    }

    /// A Slurm client command aimed at this cluster; times are printed as seconds since the
    /// epoch.
    pub fn client(&self, program: &str) -> Command {
        let mut command = Command::new(self::program(program));
        command
            .env("SLURM_CONF", &self.conf)
            .env("SLURM_TIME_FORMAT", "%s")
            .stdin(Stdio::null());
        command
    }

    fn run(&self, mut command: Command, what: &str) -> String {
        let out = command.output().unwrap_or_else(|e| panic!("{what}: {e}"));
        assert!(
            out.status.success(),
            "{what} failed ({}): {}{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    /// Submits `script` with `options` (before the script on the command line) from an
    /// environment with `env` added (which `--export=ALL` hands to the job); returns the job
    /// id (of the array).
    pub fn sbatch(&self, options: &[String], script: &Path, env: &[(&str, String)]) -> u64 {
        let mut command = self.client("sbatch");
        command.arg("--parsable").args(options).arg(script);
        for (name, value) in env {
            command.env(name, value);
        }
        let out = self.run(command, "sbatch");
        let id = out.trim().split(';').next().unwrap_or_default();
        id.parse()
            .unwrap_or_else(|_| panic!("sbatch printed no job id: {out:?}"))
    }

    /// Cancels job (or array) `job`, as a user would: Slurm sends SIGTERM to every process of
    /// each running task, SIGKILL after [`KILL_WAIT_S`].
    pub fn scancel(&self, job: u64) {
        let mut command = self.client("scancel");
        command.arg(job.to_string());
        self.run(command, "scancel");
    }

    /// The batch script Slurm holds for `job`, byte for byte.
    pub fn batch_script(&self, job: u64) -> Vec<u8> {
        let mut command = self.client("scontrol");
        command.args(["write", "batch_script", &job.to_string(), "-"]);
        let out = command.output().expect("scontrol write batch_script");
        assert!(
            out.status.success(),
            "scontrol write batch_script: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        out.stdout
    }

    /// Every task record of job (or array) `job`.
    pub fn tasks(&self, job: u64) -> Vec<TaskInfo> {
        let mut command = self.client("scontrol");
        command.args(["-o", "show", "job", &job.to_string()]);
        let out = self.run(command, "scontrol show job");
        out.lines()
            .filter(|l| !l.trim().is_empty())
            .map(|line| {
                let fields: HashMap<&str, &str> = line
                    .split_whitespace()
                    .filter_map(|t| t.split_once('='))
                    .collect();
                let field = |k: &str| fields.get(k).copied().unwrap_or_default().to_owned();
                TaskInfo {
                    job_id: field("JobId").parse().unwrap_or(0),
                    array_task: field("ArrayTaskId"),
                    state: field("JobState"),
                    exit_code: field("ExitCode"),
                    start_s: field("StartTime").parse().ok(),
                    end_s: field("EndTime").parse().ok(),
                }
            })
            .collect()
    }

    /// Waits (at most `limit`) until every task of `job` has finished; returns their records.
    pub fn wait_finished(&self, job: u64, limit: Duration) -> Vec<TaskInfo> {
        let start = Instant::now();
        loop {
            let tasks = self.tasks(job);
            if !tasks.is_empty() && tasks.iter().all(TaskInfo::finished) {
                return tasks;
            }
            assert!(
                start.elapsed() < limit,
                "job {job} still unfinished after {limit:?}: {tasks:?}\n{}",
                self.logs()
            );
            std::thread::sleep(Duration::from_millis(500));
        }
    }

    /// Ends every job of the cluster and waits (briefly) for them to go.
    fn cancel_all_jobs(&self) {
        let list = self.client("squeue").args(["-h", "-o", "%A"]).output();
        let Ok(list) = list else { return };
        let ids: Vec<String> = String::from_utf8_lossy(&list.stdout)
            .split_whitespace()
            .map(str::to_owned)
            .collect();
        if ids.is_empty() {
            return;
        }
        let _ = self.client("scancel").args(&ids).output();
        let deadline = Instant::now() + Duration::from_secs(KILL_WAIT_S + 10);
        while Instant::now() < deadline {
            let left = self.client("squeue").args(["-h", "-o", "%A"]).output();
            if left.is_ok_and(|o| o.stdout.iter().all(u8::is_ascii_whitespace)) {
                return;
            }
            std::thread::sleep(Duration::from_millis(300));
        }
    }

    /// Processes other than this one whose environment names this cluster's configuration.
    fn leftover_processes(&self) -> Vec<u32> {
        let marker = format!("SLURM_CONF={}", self.conf.display()).into_bytes();
        let own = std::process::id();
        let Ok(entries) = fs::read_dir("/proc") else {
            return Vec::new();
        };
        entries
            .filter_map(|e| e.ok()?.file_name().to_str()?.parse::<u32>().ok())
            .filter(|&pid| pid != own)
            .filter(|pid| {
                fs::read(format!("/proc/{pid}/environ"))
                    .is_ok_and(|env| env.split(|&b| b == 0).any(|v| v == marker.as_slice()))
            })
            .collect()
    }
}

impl Drop for SlurmCluster {
    fn drop(&mut self) {
        self.cancel_all_jobs();
        // slurmd first, the controller next, munge last; each gets SIGTERM, then SIGKILL.
        for daemon in self.daemons.iter_mut().rev() {
            let pid = daemon.child.id().to_string();
            let _ = Command::new("kill")
                .args(["-TERM", &pid])
                .stderr(Stdio::null())
                .status();
            let deadline = Instant::now() + Duration::from_secs(10);
            loop {
                match daemon.child.try_wait() {
                    Ok(Some(_)) => break,
                    Ok(None) if Instant::now() < deadline => {
                        std::thread::sleep(Duration::from_millis(100));
                    }
                    _ => {
                        let _ = daemon.child.kill();
                        let _ = daemon.child.wait();
                        break;
                    }
                }
            }
        }
        // Job steps, jobs' processes and the controller's script helper were started for this
        // cluster only and carry its configuration in their environment.
        for pid in self.leftover_processes() {
            let _ = Command::new("kill")
                .args(["-KILL", &pid.to_string()])
                .stderr(Stdio::null())
                .status();
        }
        // Job-step processes are detached from slurmd: once exited they wait, as zombies, for
        // the system's init to collect them. Give it a few seconds, so that the cluster is
        // gone from the process table too when the test ends.
        let deadline = Instant::now() + Duration::from_secs(10);
        while Instant::now() < deadline && !step_zombies().is_subset(&self.earlier_step_zombies) {
            std::thread::sleep(Duration::from_millis(200));
        }
    }
}

/// Exited `slurmstepd` processes not yet collected by their parent.
fn step_zombies() -> HashSet<u32> {
    let Ok(entries) = fs::read_dir("/proc") else {
        return HashSet::new();
    };
    entries
        .filter_map(|e| e.ok()?.file_name().to_str()?.parse::<u32>().ok())
        .filter(|pid| {
            fs::read_to_string(format!("/proc/{pid}/stat"))
                .is_ok_and(|stat| stat.contains("(slurmstepd) Z "))
        })
        .collect()
}

/// Two TCP ports free on this machine now.
fn free_ports() -> [u16; 2] {
    let a = std::net::TcpListener::bind("127.0.0.1:0").expect("free port");
    let b = std::net::TcpListener::bind("127.0.0.1:0").expect("free port");
    [
        a.local_addr().expect("port").port(),
        b.local_addr().expect("port").port(),
    ]
}

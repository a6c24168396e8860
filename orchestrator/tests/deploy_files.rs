//! Checks of the deployment files in `deploy/`: shell syntax, Kubernetes manifests, systemd
//! units and the Slurm script's settings that the graceful stop depends on.
//!
//! `bash -n` and Python's `yaml` module are used where present; a check whose tool is missing
//! prints that it is skipped.

use std::path::{Path, PathBuf};
use std::process::Command;

fn deploy_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../deploy")
}

fn read(relative: &str) -> String {
    let path = deploy_dir().join(relative);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn tool_available(program: &str, probe: &[&str]) -> bool {
    let ok = Command::new(program)
        .args(probe)
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        eprintln!("SKIPPED: `{program}` is not available");
    }
    ok
}

#[test]
fn slurm_script_is_valid_bash() {
    if !tool_available("bash", &["-c", "true"]) {
        return;
    }
    let script = deploy_dir().join("slurm/moorfret-workers.sbatch");
    let out = Command::new("bash")
        .arg("-n")
        .arg(&script)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn slurm_script_stops_workers_gracefully_and_passes_the_wall_time() {
    let script = read("slurm/moorfret-workers.sbatch");
    let directive = |key: &str| {
        script
            .lines()
            .find_map(|l| l.strip_prefix(&format!("#SBATCH --{key}=")))
            .unwrap_or_else(|| panic!("no #SBATCH --{key}"))
            .to_owned()
    };
    assert_eq!(directive("signal"), "B:TERM@120");
    assert!(directive("array").starts_with("0-"));
    // The default lead matches --signal; an override of --signal comes with one of the lead.
    assert!(
        script.contains("SIGNAL_LEAD_S=${MOORFRET_SIGNAL_LEAD_S:-120}"),
        "lead must match --signal"
    );
    assert!(script.contains("--wall-time-s"));
    // The worker replaces the batch shell, so that a `B:` signal reaches it.
    assert!(script.contains(r#"exec "$worker" "${args[@]}""#));
}

/// The batch script run outside Slurm, with stand-ins for `squeue` (10 min left) and the
/// worker: the worker gets the time left less the lead as its wall time; SIGTERM sent to the
/// batch shell alone (as `--signal=B:TERM` does) or to its whole process group (as `scancel`
/// does) reaches the worker, and the script exits with the worker's own status. The scheduler
/// itself is exercised by `tests/slurm_cluster.rs`.
#[test]
fn slurm_script_passes_the_wall_time_and_exits_with_the_workers_status() {
    use std::os::unix::fs::PermissionsExt;
    use std::os::unix::process::CommandExt;
    if !tool_available("bash", &["-c", "true"]) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
        path
    };
    write("squeue", "#!/bin/sh\necho 10:00\n");
    let args_file = dir.path().join("worker-args");
    let worker = write(
        "worker",
        "#!/bin/bash\n\
         if [[ $1 == --help ]]; then echo '  --wall-time-s <S>'; exit 0; fi\n\
         trap 'kill $!; exit 0' TERM\n\
         echo \"$*\" > \"$ARGS_FILE.tmp\" && mv \"$ARGS_FILE.tmp\" \"$ARGS_FILE\"\n\
         sleep 30 & wait\n",
    );
    let path = format!(
        "{}:{}",
        dir.path().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    for lead in [None, Some("100")] {
        let _ = std::fs::remove_file(&args_file);
        let mut command = Command::new("bash");
        command
            .arg(deploy_dir().join("slurm/moorfret-workers.sbatch"))
            .env("PATH", &path)
            .env("SLURM_JOB_ID", "1")
            .env("MOORFRET_DB", "postgres://db-host/moorfret")
            .env("MOORFRET_ARTIFACTS", "/shared/artifacts")
            .env("MOORFRET_WORKER", &worker)
            .env("ARGS_FILE", &args_file)
            .stderr(std::process::Stdio::null())
            .process_group(0);
        match lead {
            Some(s) => command.env("MOORFRET_SIGNAL_LEAD_S", s),
            None => command.env_remove("MOORFRET_SIGNAL_LEAD_S"),
        };
        let mut shell = command.spawn().unwrap();
        let start = std::time::Instant::now();
        while !args_file.exists() {
            assert!(start.elapsed().as_secs() < 20, "the worker did not start");
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        let args = std::fs::read_to_string(&args_file).unwrap();
        let budget = 600 - lead.map_or(120, |s| s.parse::<i64>().unwrap());
        assert_eq!(
            args.trim(),
            format!(
                "--db postgres://db-host/moorfret --artifacts /shared/artifacts \
                 --exit-when-idle --wall-time-s {budget}"
            )
        );
        // The default lead: the batch shell alone, as `B:`; the other: the whole group.
        let target = match lead {
            None => shell.id().to_string(),
            Some(_) => format!("-{}", shell.id()),
        };
        assert!(Command::new("kill")
            .args(["-TERM", "--", &target])
            .status()
            .unwrap()
            .success());
        let status = shell.wait().unwrap();
        assert_eq!(status.code(), Some(0), "lead {lead:?}");
    }
}

/// Slurm prints time left as `[days-]hours:minutes:seconds`, `minutes:seconds`, `minutes`,
/// `days-hours` or `days-hours:minutes` (squeue(1), TIME FORMAT).
#[test]
fn slurm_time_left_is_converted_to_seconds() {
    if !tool_available("bash", &["-c", "true"]) {
        return;
    }
    let script = deploy_dir().join("slurm/moorfret-workers.sbatch");
    let cases = [
        ("1-02:03:04", "93784"),
        ("02:03:04", "7384"),
        ("08:09:09", "29349"),
        ("03:04", "184"),
        ("45", "2700"),
        ("1-02", "93600"),
        ("1-02:03", "93780"),
        ("UNLIMITED", ""),
    ];
    for (text, seconds) in cases {
        let out = Command::new("bash")
            .arg("-c")
            .arg(r#"source "$1" && slurm_time_to_s "$2""#)
            .arg("bash")
            .arg(&script)
            .arg(text)
            .env_remove("SLURM_JOB_ID")
            .output()
            .unwrap();
        assert!(out.status.success(), "{text}: {:?}", out);
        assert_eq!(
            String::from_utf8_lossy(&out.stdout).trim(),
            seconds,
            "{text}"
        );
    }
}

#[test]
fn kubernetes_manifests_parse_and_describe_a_work_queue_job() {
    if !tool_available("python3", &["-c", "import yaml"]) {
        return;
    }
    // Prints one line per fact checked below, so the assertions stay in Rust.
    let program = r#"
import sys, yaml
docs = {}
for path in sys.argv[1:]:
    for doc in yaml.safe_load_all(open(path)):
        docs[(doc["kind"], doc["metadata"]["name"])] = doc
job = docs[("Job", "moorfret-workers")]
spec = job["spec"]
pod = spec["template"]["spec"]
c = pod["containers"][0]
env = {e["name"]: e for e in c.get("env", [])}
ref = env["MOORFRET_DB"]["valueFrom"]["secretKeyRef"]
secret = docs[("Secret", ref["name"])]
claim = pod["volumes"][0]["persistentVolumeClaim"]["claimName"]
pvc = docs[("PersistentVolumeClaim", claim)]
print("parallelism", spec["parallelism"])
print("completions", spec.get("completions"))
print("restart", pod["restartPolicy"])
print("grace", pod["terminationGracePeriodSeconds"])
print("cpu", c["resources"]["requests"]["cpu"])
print("memory", c["resources"]["requests"]["memory"])
print("secret_key", ref["key"] in secret["stringData"])
print("args", " ".join(c["args"]))
print("pvc_mode", pvc["spec"]["accessModes"][0])
"#;
    let dir = deploy_dir().join("k8s");
    let out = Command::new("python3")
        .arg("-c")
        .arg(program)
        .arg(dir.join("worker-job.yaml"))
        .arg(dir.join("secret.yaml"))
        .arg(dir.join("artifacts-pvc.yaml"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let facts: std::collections::HashMap<&str, &str> =
        text.lines().filter_map(|l| l.split_once(' ')).collect();
    assert!(facts["parallelism"].parse::<u32>().unwrap() >= 1);
    assert_eq!(
        facts["completions"], "None",
        "work-queue mode leaves completions unset"
    );
    assert_eq!(facts["restart"], "OnFailure");
    assert!(facts["grace"].parse::<u32>().unwrap() >= 60);
    assert_eq!(facts["cpu"], "2");
    assert_eq!(facts["memory"], "4Gi");
    assert_eq!(facts["secret_key"], "True");
    assert!(facts["args"].contains("--db $(MOORFRET_DB)"));
    assert_eq!(facts["pvc_mode"], "ReadWriteMany");
}

#[test]
fn systemd_units_have_their_sections_and_a_graceful_stop() {
    for unit in [
        "systemd/moorfret-worker.service",
        "systemd/moorfret-worker@.service",
    ] {
        let text = read(unit);
        let sections: Vec<&str> = text
            .lines()
            .filter(|l| l.starts_with('[') && l.ends_with(']'))
            .collect();
        assert_eq!(sections, ["[Unit]", "[Service]", "[Install]"], "{unit}");
        for line in text
            .lines()
            .filter(|l| !l.is_empty() && !l.starts_with('#') && !l.starts_with('['))
        {
            assert!(line.contains('='), "{unit}: not a key=value line: {line}");
        }
        assert!(text.contains("KillSignal=SIGTERM"), "{unit}");
        assert!(text.contains("TimeoutStopSec=120"), "{unit}");
        assert!(
            text.contains("ExecStart=/usr/local/bin/moorfret-worker --db ${MOORFRET_DB}"),
            "{unit}"
        );
    }
    assert!(read("systemd/moorfret-worker@.service").contains("PartOf=moorfret-workers.target"));
}

#[test]
fn container_file_builds_in_one_stage_and_runs_in_another() {
    let text = read("Containerfile");
    let stages: Vec<&str> = text.lines().filter(|l| l.starts_with("FROM ")).collect();
    assert_eq!(stages.len(), 2, "{stages:?}");
    assert!(stages[0].ends_with(" AS build"));
    assert!(text.contains("COPY --from=build"));
    assert!(text.contains("USER moorfret"));
    assert!(read("Containerfile.dockerignore")
        .lines()
        .any(|l| l == "target"));
}

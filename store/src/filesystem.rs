//! Refusing SQLite on network file systems (ARCHITECTURE.md, the store).
//!
//! SQLite's locking relies on POSIX advisory locks and, in WAL mode, on shared memory; both are
//! unreliable or absent on NFS, Lustre, CIFS and similar, where concurrent workers could corrupt
//! the store. The file system of a path is read from the mount table (`/proc/self/mounts`):
//! the mount point that is the longest prefix of the path's nearest existing ancestor decides.

use std::path::{Path, PathBuf};

/// File system types on which an SQLite store is refused.
pub const NETWORK_FILESYSTEMS: &[&str] = &[
    "nfs",
    "nfs4",
    "lustre",
    "cifs",
    "smb3",
    "smbfs",
    "gpfs",
    "beegfs",
    "ceph",
    "fuse.sshfs",
    "9p",
    "afs",
    "glusterfs",
    "fuse.glusterfs",
];

/// The network file system type holding `path`, if any (`None` as well where the mount table
/// cannot be read).
pub fn network_filesystem_of(path: &Path) -> Option<String> {
    let mounts = std::fs::read_to_string("/proc/self/mounts").ok()?;
    let fs_type = filesystem_type_in(&mounts, &existing_ancestor(path))?;
    NETWORK_FILESYSTEMS
        .contains(&fs_type.as_str())
        .then_some(fs_type)
}

/// The nearest existing ancestor of `path`, made absolute and canonical.
fn existing_ancestor(path: &Path) -> PathBuf {
    let absolute = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir()
            .map(|d| d.join(path))
            .unwrap_or_else(|_| path.to_path_buf())
    };
    absolute
        .ancestors()
        .find_map(|a| a.canonicalize().ok())
        .unwrap_or(absolute)
}

/// File system type of the mount holding `path`, from mount-table text (`device mount-point
/// type options …` per line, spaces in names escaped as `\040`).
pub fn filesystem_type_in(mounts: &str, path: &Path) -> Option<String> {
    mounts
        .lines()
        .filter_map(|line| {
            let mut fields = line.split_whitespace();
            let _device = fields.next()?;
            let mount_point = PathBuf::from(unescape(fields.next()?));
            let fs_type = fields.next()?;
            path.starts_with(&mount_point)
                .then(|| (mount_point, fs_type.to_owned()))
        })
        .max_by_key(|(mount_point, _)| mount_point.components().count())
        .map(|(_, fs_type)| fs_type)
}

fn unescape(field: &str) -> String {
    let bytes = field.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let octal = bytes
            .get(i + 1..i + 4)
            .filter(|d| d.iter().all(|b| (b'0'..=b'7').contains(b)));
        match (bytes[i], octal) {
            (b'\\', Some(d)) => {
                out.push((d[0] - b'0') * 64 + (d[1] - b'0') * 8 + (d[2] - b'0'));
                i += 4;
            }
            (b, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    const MOUNTS: &str = "\
/dev/sda1 / ext4 rw,relatime 0 0
server:/export /shared nfs4 rw,vers=4.2 0 0
lfs@o2ib:/scratch /shared/scratch lustre rw 0 0
/dev/sdb1 /data\\040disk xfs rw 0 0
";

    #[test]
    fn the_longest_matching_mount_point_decides() {
        let of = |p: &str| filesystem_type_in(MOUNTS, Path::new(p));
        assert_eq!(of("/home/u/c.sqlite").as_deref(), Some("ext4"));
        assert_eq!(of("/shared/c.sqlite").as_deref(), Some("nfs4"));
        assert_eq!(
            of("/shared/scratch/run/c.sqlite").as_deref(),
            Some("lustre")
        );
        assert_eq!(of("/sharedx/c.sqlite").as_deref(), Some("ext4"));
        assert_eq!(of("/data disk/c.sqlite").as_deref(), Some("xfs"));
    }

    #[test]
    fn a_path_not_yet_created_is_judged_by_its_nearest_existing_ancestor() {
        let base = std::env::temp_dir().canonicalize().unwrap();
        let missing = std::env::temp_dir().join("not-yet-created/deeper/c.sqlite");
        assert_eq!(existing_ancestor(&missing), base);
    }
}

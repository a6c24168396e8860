//! Shared pieces of the command-line tests: the binary under test, the repository's campaign
//! files and the numeric CSV files the commands write.

#![allow(dead_code, unreachable_pub)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The `moorfret` binary under test.
pub fn moorfret() -> Command {
    Command::new(env!("CARGO_BIN_EXE_moorfret"))
}

/// A file of the repository's `campaigns/` directory.
pub fn campaign_file(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../campaigns")
        .join(relative)
}

/// Header and numeric rows of a CSV file, its last `skip_last` (text) columns dropped.
pub fn csv_rows(path: &Path, skip_last: usize) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let data = lines
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            cells[..cells.len() - skip_last]
                .iter()
                .map(|c| c.parse::<f64>().unwrap())
                .collect()
        })
        .collect();
    (header, data)
}

/// Copies the directory `from` with everything in it to `to`.
pub fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}

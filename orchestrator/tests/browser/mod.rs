//! Headless Chromium for the report tests: found on PATH, and a page's screenshot.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The Chromium to render with; `None` (the screenshot skipped, with a message) where none is
/// installed, except where the environment requires it (`MOORFRET_REQUIRE_SERVICES`, set by
/// `.ci/run`): there the test fails, so that CI cannot pass by skipping.
pub(crate) fn chromium_or_skip() -> Option<PathBuf> {
    let found = ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find_map(|name| {
            Command::new("sh")
                .arg("-c")
                .arg(format!("command -v {name}"))
                .output()
                .ok()
                .filter(|o| o.status.success())
                .map(|o| PathBuf::from(String::from_utf8_lossy(&o.stdout).trim()))
        });
    if found.is_none() {
        assert!(
            std::env::var_os("MOORFRET_REQUIRE_SERVICES").is_none(),
            "chromium is required here (MOORFRET_REQUIRE_SERVICES is set)"
        );
        eprintln!(
            "SKIPPED (screenshot): no chromium on PATH; install with apt-get install -y chromium"
        );
    }
    found
}

/// A screenshot of `page` (1280 × 2000) by headless Chromium into `png`, with its profile in
/// the directory `profile`: the PNG's bytes.
pub(crate) fn screenshot(browser: &Path, page: &Path, png: &Path, profile: &Path) -> Vec<u8> {
    let out = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--screenshot={}", png.display()))
        .arg("--window-size=1280,2000")
        .arg(format!("file://{}", page.display()))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "chromium failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    bytes
}

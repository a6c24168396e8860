//! The report tests' look at a page: its maps and their colour bars, and headless Chromium
//! (found on PATH) for its screenshot.

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

/// The maps of a report page: each from its figure's opening to the end of its SVG.
pub(crate) fn maps(page: &str) -> Vec<&str> {
    page.match_indices("class=\"fig map")
        .map(|(i, _)| {
            let rest = &page[i..];
            &rest[..rest.find("</svg>").expect("a map ends its svg")]
        })
        .collect()
}

/// Every map carries a colour bar: a column of at least 40 distinct colours (the bar's 48
/// steps), more than the cells or discs of a map alone.
pub(crate) fn every_map_has_a_colour_bar(page: &str) {
    let maps = maps(page);
    assert!(!maps.is_empty());
    for map in maps {
        let fills: std::collections::BTreeSet<&str> = map
            .split("fill=\"")
            .skip(1)
            .filter_map(|f| f.split('"').next())
            .filter(|f| *f != "none" && *f != "#FFFFFF" && *f != "#000000")
            .collect();
        assert!(
            fills.len() >= 40,
            "a map without its colour bar ({} colours): {}",
            fills.len(),
            &map[..map.len().min(300)]
        );
    }
}

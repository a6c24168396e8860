//! `moorfret report` on a store populated by the test fixture (hand-made rows, see
//! `fixture/mod.rs`): the page is self-contained, holds the plots and tables, and renders in
//! headless Chromium (skipped with a message when no Chromium is installed).

mod browser;
mod fixture;

use std::path::{Path, PathBuf};
use std::process::Command;

use moorfret_store::ArtifactStore;

/// The fixture campaign in an SQLite store with its artifacts: (directory, store file,
/// artifact store).
async fn populated_fixture() -> (tempfile::TempDir, PathBuf, ArtifactStore) {
    let Some((store, fixture::Location::Sqlite(dir))) = fixture::open(false).await else {
        panic!("SQLite fixture");
    };
    let db = dir.path().join("fixture.sqlite");
    let artifacts = ArtifactStore::beside_database(&db).unwrap();
    fixture::populate(&store, Some(&artifacts)).await;
    store.close().await;
    (dir, db, artifacts)
}

/// `moorfret report` of the fixture campaign in `db` into `out`.
fn report(db: &Path, out: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_moorfret"))
        .args(["report", fixture::NAME, "--out"])
        .arg(out)
        .arg("--db")
        .arg(db)
        .output()
        .unwrap()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn report_of_the_fixture_is_self_contained_and_renders() {
    let (dir, db, _) = populated_fixture().await;
    let out = dir.path().join("report");
    let run = report(&db, &out);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let page_path = out.join("index.html");
    let page = std::fs::read_to_string(&page_path).unwrap();
    // Occurrence and two damage maps, one series figure, the run-in map, two histograms.
    assert_eq!(page.matches("<svg").count(), 7, "inline SVG figures");
    assert!(page.contains("occurrence (% of the year"));
    // the counted strand result of each sea state (its last seed's run-in; sea state 1 none)
    assert!(
        page.contains("stops drifting: in 1 of 2 sea states (from 30.00 s to 30.00 s"),
        "run-in section"
    );
    assert!(page.contains("2 sea states from the FE model, 0 from the reduced"));
    assert!(page.contains("No sea state ran both fidelities."));
    assert!(page.contains("share of annual fretting damage"));
    assert!(page.contains("share of annual T-N damage (tn_dnv_spiral_rope)"));
    assert!(page.contains("layer interface 2, outer_arc"));
    assert!(page.contains("hot spot 0, layer interface 0"));
    // Sea state 0 carries 0.30·1e-6 / (0.30·1e-6 + 0.13758·4e-6) = 35 % of the fretting damage.
    assert!(page.contains(">\n35%\n</text>"), "share label");
    // Four maps (occurrence, fretting and T-N shares, run-in), each with its colour bar: a
    // column of at least 40 distinct colours (the bar's 48 steps), more than the discs alone.
    assert_eq!(browser::maps(&page).len(), 4);
    browser::every_map_has_a_colour_bar(&page);
    // every sea state of the fixture has its results; no sectors, no sector maps
    assert!(page.contains("Every sea state of the climate has its results."));
    assert!(!page.contains("sector-map"));
    // Offline: no scripts, no external resources (the SVG namespace is not fetched).
    assert!(!page.contains("<script"));
    assert!(!page.contains("src=\"http") && !page.contains("href=\"http"));

    let Some(browser) = browser::chromium_or_skip() else {
        return;
    };
    let png = dir.path().join("report.png");
    browser::screenshot(&browser, &page_path, &png, &dir.path().join("profile"));
    // MOORFRET_KEEP_SCREENSHOT=path keeps a copy for inspection.
    if let Ok(keep) = std::env::var("MOORFRET_KEEP_SCREENSHOT") {
        std::fs::copy(&png, keep).unwrap();
    }
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    // A rendered page of plots compresses to far more than a blank 1280 × 2000 image (< 10 kB).
    assert!(bytes.len() > 30_000, "screenshot of {} bytes", bytes.len());
}

/// An artifact changed on disk (one byte) or deleted is an error naming it, not a report
/// without its plot.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_damaged_or_missing_artifact_fails_the_report_naming_it() {
    let (dir, db, artifacts) = populated_fixture().await;
    let files: Vec<PathBuf> = std::fs::read_dir(artifacts.dir())
        .unwrap()
        .flat_map(|d| std::fs::read_dir(d.unwrap().path()).unwrap())
        .map(|f| f.unwrap().path())
        .collect();
    assert!(!files.is_empty());
    let out = dir.path().join("report");
    for damage in ["flip a byte", "delete"] {
        let originals: Vec<Vec<u8>> = files.iter().map(|f| std::fs::read(f).unwrap()).collect();
        for f in &files {
            if damage == "delete" {
                std::fs::remove_file(f).unwrap();
            } else {
                let mut bytes = std::fs::read(f).unwrap();
                bytes[0] ^= 1;
                std::fs::write(f, bytes).unwrap();
            }
        }
        let run = report(&db, &out);
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{damage}: {err}");
        assert!(err.contains("artifact hot_spot_"), "{damage}: {err}");
        for (f, bytes) in files.iter().zip(originals) {
            std::fs::write(f, bytes).unwrap();
        }
    }
    assert!(report(&db, &out).status.success());
}

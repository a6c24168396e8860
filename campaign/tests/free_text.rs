//! The free text of the shipped campaign files (`_about` and `_notes` texts, comment lines of
//! the scatter tables) enters no cache key: rewritten, every campaign resolves to the same
//! input hashes, so editing that prose never reruns a job. The floater description is the
//! exception: its `_about` is kept with the floater and enters every key, so its file is not
//! edited for wording.

use std::path::Path;

use moorfret_campaign::resolve;
use serde_json::Value;

/// Every file a shipped campaign names, relative to `campaigns/`.
const FILES: [&str; 8] = [
    "demo.json",
    "paper.json",
    "paper_case.json",
    "data/demo_scatter.tsv",
    "data/wsd_argoss_sector.tsv",
    "data/oc4_semi_floater.json",
    "data/strand_profiles.json",
    "benchmarks/strand_1_6_1.json",
];

const FLOATER: &str = "data/oc4_semi_floater.json";

fn copy_campaigns(dir: &Path) {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns");
    for f in FILES {
        let to = dir.join(f);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(src.join(f), to).unwrap();
    }
}

/// Replaces every string under a key starting with `_`, at any depth.
fn rewrite_comments(v: &mut Value) {
    match v {
        Value::Object(map) => {
            for (k, item) in map.iter_mut() {
                if k.starts_with('_') {
                    rewrite_strings(item);
                } else {
                    rewrite_comments(item);
                }
            }
        }
        Value::Array(items) => items.iter_mut().for_each(rewrite_comments),
        _ => {}
    }
}

fn rewrite_strings(v: &mut Value) {
    match v {
        Value::String(s) => *s = format!("reworded: {}", s.len()),
        Value::Object(map) => map.values_mut().for_each(rewrite_strings),
        Value::Array(items) => items.iter_mut().for_each(rewrite_strings),
        _ => {}
    }
}

fn rewrite_file(dir: &Path, f: &str) {
    let path = dir.join(f);
    let text = std::fs::read_to_string(&path).unwrap();
    let new = if f.ends_with(".json") {
        let mut v: Value = serde_json::from_str(&text).unwrap();
        rewrite_comments(&mut v);
        serde_json::to_string_pretty(&v).unwrap()
    } else {
        text.lines()
            .map(|l| {
                if l.starts_with('#') {
                    "# reworded".to_owned()
                } else {
                    l.to_owned()
                }
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_ne!(new, text, "{f} has no free text to rewrite");
    std::fs::write(path, new).unwrap();
}

/// (results, global) input hashes of each campaign in `dir`.
fn hashes(dir: &Path) -> Vec<(String, String)> {
    ["demo.json", "paper.json"]
        .iter()
        .map(|c| {
            let inputs = resolve(&dir.join(c)).unwrap().inputs;
            (inputs.results_sha256(), inputs.global_sha256())
        })
        .collect()
}

#[test]
fn rewording_the_campaign_files_changes_no_cache_key() {
    let original = tempfile::tempdir().unwrap();
    copy_campaigns(original.path());
    let reworded = tempfile::tempdir().unwrap();
    copy_campaigns(reworded.path());
    for f in FILES.iter().filter(|f| **f != FLOATER) {
        rewrite_file(reworded.path(), f);
    }
    assert_eq!(hashes(reworded.path()), hashes(original.path()));

    // the floater's own description is part of the stored floater
    rewrite_file(reworded.path(), FLOATER);
    let (before, after) = (hashes(original.path()), hashes(reworded.path()));
    for (b, a) in before.iter().zip(&after) {
        assert_ne!(a.0, b.0);
        assert_ne!(a.1, b.1);
    }
}

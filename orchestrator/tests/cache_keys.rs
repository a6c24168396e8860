//! The cache keys of the shipped campaign files are pinned: a change of the campaign format
//! (a new optional field, a new way to give the scatter diagram) must leave every job key of an
//! existing file unchanged, or its stored and cached results would be computed again and an
//! existing store would no longer match its file.
//!
//! The pinned digest is the sha256 of every planned job's cache key, in plan order. A change of
//! the solver version changes it on purpose (`SOLVER_VERSION` enters every key); then the digest
//! is updated with the version, and only then.

use std::path::Path;

use moorfret_orchestrator::plan;
use moorfret_store::SeaStateId;
use sha2::{Digest, Sha256};

/// sha256 over the cache keys of every job the campaign file at `name` plans.
fn plan_digest(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../campaigns")
        .join(name);
    let resolved = moorfret_campaign::resolve(&path).unwrap();
    let inputs = &resolved.inputs;
    let states = plan::campaign_sea_states(&resolved);
    let ids: Vec<SeaStateId> = (0..states.len() as i64).map(SeaStateId).collect();
    let jobs = plan::jobs(inputs, &inputs.results_sha256(), &states, &ids);
    let mut h = Sha256::new();
    for job in &jobs {
        h.update(job.cache_key.as_deref().unwrap_or("-").as_bytes());
        h.update([0]);
    }
    let hex: String = h.finalize().iter().map(|b| format!("{b:02x}")).collect();
    format!("{} jobs {hex}", jobs.len())
}

#[test]
fn shipped_campaign_files_keep_their_cache_keys() {
    assert_eq!(
        plan_digest("demo.json"),
        "6 jobs 8f5d36eaef59ea23698f5a9e1fa6ff957ae14a936e4d7a87ba9e378a6711bd89",
        "campaigns/demo.json plans other cache keys"
    );
    assert_eq!(
        plan_digest("paper.json"),
        "1066 jobs e4350c14602d474f5b9a3a37a49fefb2f25d20edfc28919fc21a8430b3fbc439",
        "campaigns/paper.json plans other cache keys"
    );
}

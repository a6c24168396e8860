//! Tension → strain for the strand stage: the axial stiffness EA of ε = T / EA, one rule for a
//! campaign's strand jobs and for `moorfret run strand`.
//!
//! - [`AxialStiffnessRule::StrandModel`] (the default): EA measured on the strand model itself
//!   (`moorfret_solver::strand::history::stiffness::measure_axial_stiffness_n`, a tension step
//!   at [`STIFFNESS_STRAIN`]). The strand section then carries the hot-spot tension T of the
//!   global model, which is what the two models share: the line's force. Its wire tensions, and
//!   the contact forces they press through the layers, are those of the rope at T. For the
//!   paper's six-layer strand EA is 3.125e8 N, 13 % below the line type's 3.6e8 N: the contacts'
//!   radial compliance (docs/strand-runs.md, "Six-layer strand: axial stiffness"). Loading it at
//!   T / 3.6e8 would leave it carrying 0.87 T.
//! - [`AxialStiffnessRule::LineType`]: EA of the global line type at the hot spot. For a
//!   stand-in strand that is not the rope (the demo's 1+6+1 benchmark strand, EA far below the
//!   rope's): it is kept at the rope's strains instead of being given the rope's tension.
//!
//! The rule not used is reported with the one used (`axial_stiffness` of a strand job's result).
//! The same EA gives the fretting stress measure its metallic area EA / E, so the wire stress of
//! a slip cycle is E ε, the stress at the strain the strand is loaded with.
//!
//! Measured values are cached in one small JSON file per (strand, model parameters, measuring
//! strain, Newton settings, program version), named by the SHA-256 of that description and
//! written by temporary file and rename ([`StiffnessCache`]): `run strand` keeps them in the
//! user's cache directory, a campaign in its artifact directory. A stale value is never used: a
//! changed input is another key, and at worst EA is measured again.

use std::path::{Path, PathBuf};

use moorfret_solver::linalg::NewtonParams;
use moorfret_solver::strand::model::StrandModelParameters;
use moorfret_solver::strand::profile::Strand;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

/// Axial strain of the tension step that measures EA: of the order of the service strains
/// (the strand is nearly linear in tension, Costello Ch. 2).
pub const STIFFNESS_STRAIN: f64 = 1e-3;

/// Which EA converts the hot-spot tension to the strand's axial strain (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AxialStiffnessRule {
    /// EA measured on the strand model: the strand carries the hot-spot tension.
    StrandModel,
    /// EA of the global line type at the hot spot: a stand-in strand at the rope's strains.
    LineType,
}

impl AxialStiffnessRule {
    /// The name of the rule in campaign files and results.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::StrandModel => "strand_model",
            Self::LineType => "line_type",
        }
    }
}

/// A cached EA entry (module docs).
#[derive(Debug, Serialize, Deserialize)]
struct CachedStiffness {
    ea_n: f64,
    measured_at_strain: f64,
    /// What the key hashes, for a reader of the cache.
    model: String,
}

/// The cache entry of one strand model's measured EA (module docs).
#[derive(Debug, Clone)]
pub struct StiffnessCache {
    file: PathBuf,
    /// What the key hashes.
    description: String,
}

impl StiffnessCache {
    /// The entry in `dir` of the model of `strand` built with `params`, measured at `strain`
    /// with the Newton settings `newton`.
    pub fn new(
        dir: &Path,
        strand: &Strand,
        params: &StrandModelParameters,
        strain: f64,
        newton: &NewtonParams,
    ) -> Self {
        let description = format!(
            "moorfret {} axial stiffness; strand {:?}; model {:?}; strain {:e}; newton {:?}",
            env!("CARGO_PKG_VERSION"),
            strand,
            params,
            strain,
            newton
        );
        let key = hex::encode(Sha256::digest(description.as_bytes()));
        let file = dir.join("axial_stiffness").join(format!("{key}.json"));
        Self { file, description }
    }

    /// The entry's file.
    pub fn file(&self) -> &Path {
        &self.file
    }

    /// The cached EA (N), if the entry exists and reads back as a finite positive value.
    pub fn get(&self) -> Option<f64> {
        let text = std::fs::read_to_string(&self.file).ok()?;
        let entry: CachedStiffness = serde_json::from_str(&text).ok()?;
        (entry.ea_n.is_finite() && entry.ea_n > 0.0).then_some(entry.ea_n)
    }

    /// Stores `ea_n` measured at `strain` ([`replace_file`]).
    pub fn put(&self, ea_n: f64, strain: f64) -> std::io::Result<()> {
        let entry = CachedStiffness {
            ea_n,
            measured_at_strain: strain,
            model: self.description.clone(),
        };
        replace_file(&self.file, &serde_json::to_vec_pretty(&entry)?)
    }
}

/// Replaces `path` by `bytes` (creating its directory) through a temporary file beside it and
/// a rename, so that a reader never sees a partial file. The temporary name is random: two
/// writers of the same file (a swept worker and its job's new claimant, possibly on another
/// host sharing the directory) never share one. It is removed if the write fails.
pub fn replace_file(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(format!(".{}.tmp", uuid::Uuid::new_v4()));
    let tmp = PathBuf::from(tmp);
    let written = std::fs::write(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    written
}

#[cfg(test)]
mod tests {
    use super::*;
    use moorfret_solver::strand::model::EndKind;
    use moorfret_solver::strand::profile::select_profile;

    fn strand() -> Strand {
        let text = include_str!("../../campaigns/benchmarks/strand_1_6_1.json");
        select_profile(text, None).unwrap().validate().unwrap()
    }

    #[test]
    fn an_entry_reads_back_and_another_model_is_another_entry() {
        let dir = tempfile::tempdir().unwrap();
        let strand = strand();
        let params = StrandModelParameters {
            ends: EndKind::Periodic,
            ..StrandModelParameters::default()
        };
        let newton = NewtonParams::default();
        let cache = StiffnessCache::new(dir.path(), &strand, &params, STIFFNESS_STRAIN, &newton);
        assert_eq!(cache.get(), None);
        cache.put(3.125e8, STIFFNESS_STRAIN).unwrap();
        assert_eq!(cache.get(), Some(3.125e8));
        // the same inputs: the same entry
        let again = StiffnessCache::new(dir.path(), &strand, &params, STIFFNESS_STRAIN, &newton);
        assert_eq!(again.file(), cache.file());
        assert_eq!(again.get(), Some(3.125e8));
        // another strain, another end condition: other entries, not measured yet
        let strain = StiffnessCache::new(dir.path(), &strand, &params, 2e-3, &newton);
        assert_ne!(strain.file(), cache.file());
        assert_eq!(strain.get(), None);
        let ties = StrandModelParameters {
            ends: EndKind::PenaltyTies,
            ..params
        };
        let other = StiffnessCache::new(dir.path(), &strand, &ties, STIFFNESS_STRAIN, &newton);
        assert_ne!(other.file(), cache.file());
        // an entry that does not read as a finite positive EA is no entry
        std::fs::write(
            cache.file(),
            r#"{"ea_n": -1, "measured_at_strain": 1e-3, "model": ""}"#,
        )
        .unwrap();
        assert_eq!(cache.get(), None);
        std::fs::write(cache.file(), "{").unwrap();
        assert_eq!(cache.get(), None);
    }

    #[test]
    fn the_rule_reads_and_writes_its_campaign_names() {
        for rule in [
            AxialStiffnessRule::StrandModel,
            AxialStiffnessRule::LineType,
        ] {
            let text = serde_json::to_string(&rule).unwrap();
            assert_eq!(text, format!("\"{}\"", rule.as_str()));
            assert_eq!(
                serde_json::from_str::<AxialStiffnessRule>(&text).unwrap(),
                rule
            );
        }
        assert!(serde_json::from_str::<AxialStiffnessRule>("\"rope\"").is_err());
    }
}

//! `moorfret report NAME --out DIR [--db URL] [--artifacts DIR]`: an offline HTML page of a
//! campaign's results ([`moorfret_orchestrator::report`]).

use crate::cli::output::outln;
use std::path::PathBuf;

use clap::Args;

use super::query::open_existing;
use moorfret_orchestrator::query::DEFAULT_DB;
use moorfret_store::{ArtifactStore, StoreLocation};

/// Arguments of `moorfret report`.
#[derive(Debug, Args)]
pub(crate) struct ReportArgs {
    /// Campaign name.
    pub(crate) name: String,
    /// Output directory (created if missing); the page is `DIR/index.html`.
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Store: SQLite file path or `postgres://…` URL.
    #[arg(long, default_value = DEFAULT_DB, env = "MOORFRET_DB")]
    pub(crate) db: String,
    /// Artifact directory (default: next to an SQLite store; none for PostgreSQL).
    #[arg(long)]
    pub(crate) artifacts: Option<PathBuf>,
}

/// Writes the report and prints the path of the page. The store is opened first: a refused
/// store leaves no directory behind, and an artifact directory is read, never created.
pub(crate) fn execute(args: ReportArgs) -> anyhow::Result<()> {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()?;
    let page = runtime.block_on(async {
        let store = open_existing(&args.db).await?;
        let page = match artifact_dir(&args) {
            Ok(artifacts) => {
                moorfret_orchestrator::report::write_report(
                    &store,
                    &args.name,
                    &args.out,
                    artifacts.as_ref(),
                )
                .await
            }
            Err(err) => Err(err),
        };
        store.close().await;
        page
    })?;
    outln!("{}", page.display())?;
    Ok(())
}

/// The artifact directory of the report: `--artifacts DIR` (which must exist), or the one
/// beside an SQLite store when there is one.
fn artifact_dir(args: &ReportArgs) -> anyhow::Result<Option<ArtifactStore>> {
    Ok(match (&args.artifacts, StoreLocation::parse(&args.db)?) {
        (Some(dir), _) => {
            anyhow::ensure!(
                dir.is_dir(),
                "no artifact directory {} (--artifacts)",
                dir.display()
            );
            Some(ArtifactStore::open(dir.clone())?)
        }
        (None, StoreLocation::Sqlite(path)) => {
            let mut name = path.file_name().unwrap_or_default().to_os_string();
            name.push(".artifacts");
            let dir = path.with_file_name(name);
            if dir.is_dir() {
                Some(ArtifactStore::open(dir)?)
            } else {
                None
            }
        }
        _ => None,
    })
}

//! `moorfret query damage-inputs|sea-states|lifetime|contacts --campaign NAME [--db URL]
//! [--format table|csv|json]`: a campaign's results from the store's views
//! ([`crate::query`]).

use std::io::Write;

use clap::Args;

use crate::query::{self, OutputFormat, QueryKind, DEFAULT_DB};
use crate::store::{Store, StoreOptions};

/// Arguments of `moorfret query`.
#[derive(Debug, Args)]
pub struct QueryArgs {
    /// What to list.
    #[arg(value_enum)]
    pub kind: QueryKind,
    /// Campaign name.
    #[arg(long)]
    pub campaign: String,
    /// Store: SQLite file path or `postgres://…` URL.
    #[arg(long, default_value = DEFAULT_DB)]
    pub db: String,
    /// Output format.
    #[arg(long, value_enum, default_value_t = OutputFormat::Table)]
    pub format: OutputFormat,
    /// Fretting measure of `damage-inputs`: `fretting_max` (most damaged contact of a class)
    /// or `fretting_mean` (mean over its contacts).
    #[arg(long, default_value = "fretting_max")]
    pub measure: String,
}

/// Opens an existing store (never creates one for a read).
pub(crate) async fn open_existing(db: &str) -> anyhow::Result<Store> {
    if let crate::store::StoreLocation::Sqlite(path) = crate::store::StoreLocation::parse(db)? {
        if !path.exists() {
            anyhow::bail!("--db `{db}`: no such database file");
        }
    }
    Ok(Store::open(db, StoreOptions::default()).await?)
}

/// Runs the query and prints it on stdout.
pub fn execute(args: QueryArgs) -> anyhow::Result<()> {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()?;
    let table = runtime.block_on(async {
        let store = open_existing(&args.db).await?;
        let table = query::run(&store, &args.campaign, args.kind, &args.measure).await;
        store.close().await;
        table
    })?;
    let text = table.render(args.format)?;
    std::io::stdout().lock().write_all(text.as_bytes())?;
    Ok(())
}

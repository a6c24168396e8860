//! `moorfret query damage-inputs|sea-states|lifetime|seeds|contacts|fidelity --campaign NAME [--db URL]
//! [--format table|csv|json] [--wide]`: a campaign's results from the store's views
//! ([`moorfret_orchestrator::query`]).

use anyhow::Context;
use clap::Args;

use moorfret_orchestrator::query::{self, OutputFormat, QueryKind, DEFAULT_DB};
use moorfret_store::{Store, StoreOptions};

/// Arguments of `moorfret query`.
#[derive(Debug, Args)]
pub(crate) struct QueryArgs {
    /// What to list.
    #[arg(value_enum)]
    pub(crate) kind: QueryKind,
    /// Campaign name.
    #[arg(long)]
    pub(crate) campaign: String,
    /// Store: SQLite file path or `postgres://…` URL.
    #[arg(long, default_value = DEFAULT_DB, env = "MOORFRET_DB")]
    pub(crate) db: String,
    /// Output format.
    #[arg(long, value_enum, default_value_t = OutputFormat::Table)]
    pub(crate) format: OutputFormat,
    /// Fretting measure of `damage-inputs` and `seeds`: `fretting_max` (most damaged contact
    /// of a class) or `fretting_mean` (mean over its contacts).
    #[arg(long, default_value = "fretting_max")]
    pub(crate) measure: String,
    /// Every column in the text table; without it, the columns that fit 120 characters and a
    /// note naming the others.
    #[arg(long)]
    pub(crate) wide: bool,
}

/// Width of a query's text table without `--wide` (characters).
const TABLE_WIDTH: usize = 120;

/// Opens an existing store (never creates one for a read).
pub(crate) async fn open_existing(db: &str) -> anyhow::Result<Store> {
    Store::open_existing(db, StoreOptions::default())
        .await
        .with_context(|| format!("opening the store {db}"))
}

/// Runs the query and prints it on stdout.
pub(crate) fn execute(args: QueryArgs) -> anyhow::Result<()> {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()?;
    let table = runtime.block_on(async {
        let store = open_existing(&args.db).await?;
        let table = query::run(&store, &args.campaign, args.kind, &args.measure).await;
        store.close().await;
        table
    })?;
    let text = if args.format == OutputFormat::Table && !args.wide {
        table.render_fitted(TABLE_WIDTH)?
    } else {
        table.render(args.format)?
    };
    super::output::write_out(format_args!("{text}"))?;
    Ok(())
}

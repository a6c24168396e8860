//! The `moorfret` command line: argument types and one module per command family.
//! Each command returns `anyhow::Result`; `main` maps errors to exit codes.

use clap::{Parser, Subcommand};

pub(crate) mod campaign;
pub(crate) mod drive;
pub(crate) mod import;
pub(crate) mod output;
pub(crate) mod query;
pub(crate) mod rainflow;
pub(crate) mod report;
pub(crate) mod run;
pub(crate) mod scatter;
pub(crate) mod strand;
pub(crate) mod worker;

/// moorfret: fretting fatigue of spiral-strand mooring ropes over a site's long-term sea climate.
#[derive(Debug, Parser)]
#[command(name = "moorfret", version, about, long_about = None)]
pub(crate) struct Cli {
    /// The command to run.
    #[command(subcommand)]
    pub(crate) command: Command,
}

/// Top-level commands.
#[derive(Debug, Subcommand)]
pub(crate) enum Command {
    /// Single runs of one stage for one case, outside any campaign.
    #[command(subcommand)]
    Run(run::RunCommand),
    /// The reduced strand response: calibrate it, compare a reduced run with an FE run.
    #[command(subcommand)]
    Strand(strand::StrandCommand),
    /// Other tools' input files as moorfret cases (`import moordyn DECK --out CASE.json`).
    #[command(subcommand)]
    Import(import::ImportCommand),
    /// Rainflow-count one column of a CSV file (ASTM E1049-85), cycles as JSON or CSV.
    Rainflow(rainflow::RainflowArgs),
    /// Directional scatter tables from a hindcast or buoy series (time, Hs, Tp, direction),
    /// with the `sectors` of a campaign file.
    Scatter(scatter::ScatterArgs),
    /// Campaigns: launch, resume, status, cancel.
    #[command(subcommand)]
    Campaign(campaign::CampaignCommand),
    /// A worker process serving a store's campaigns.
    Worker(worker::WorkerArgs),
    /// A campaign's results: damage inputs, sea states, lifetime damage or contacts.
    Query(query::QueryArgs),
    /// An offline HTML report of a campaign (plots and tables).
    Report(report::ReportArgs),
}

/// Execute a parsed command line.
pub(crate) fn execute(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Run(cmd) => run::execute(cmd),
        Command::Strand(cmd) => strand::execute(cmd),
        Command::Import(cmd) => import::execute(cmd),
        Command::Rainflow(args) => rainflow::execute(args),
        Command::Scatter(args) => scatter::execute(args),
        Command::Campaign(cmd) => campaign::execute(cmd),
        Command::Worker(args) => worker::execute(args),
        Command::Query(args) => query::execute(args),
        Command::Report(args) => report::execute(args),
    }
}

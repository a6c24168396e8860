//! Errors of reading, resolving and planning a campaign. Each names the file or the field path
//! at fault and the reason; all are permanent (fix the campaign file and launch again).

use std::path::PathBuf;

use thiserror::Error;

/// Why a campaign could not be read, resolved or planned.
#[derive(Debug, Error)]
pub enum CampaignError {
    /// A file could not be read.
    #[error("{field}: cannot read {path}: {source}")]
    Io {
        /// Field of the campaign file that names the file (`campaign file` for itself).
        field: String,
        /// The path tried.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// The campaign file is not valid JSON for a campaign (unknown field, wrong type, …).
    #[error("campaign file is not a valid campaign description: {message}")]
    Json {
        /// Parser message with line, column and field.
        message: String,
    },
    /// A value is out of range.
    #[error("{field} {reason} (got {value})")]
    Invalid {
        /// Field path, e.g. `simulation.duration_s`.
        field: String,
        /// The value found.
        value: String,
        /// What is required.
        reason: String,
    },
    /// A referenced file has invalid content.
    #[error("{field} ({path}): {message}")]
    File {
        /// Field of the campaign file that names the file.
        field: String,
        /// The file.
        path: PathBuf,
        /// What is wrong, from the file's parser.
        message: String,
    },
}

//! Writing the JSON reports of the subcommands; the map's report is the library's
//! ([`demkit::report::Report`], DESIGN.md "Report").

use crate::Failure;
use serde::Serialize;
use std::path::Path;

/// Writes any report as pretty JSON followed by a newline.
pub fn write_json(path: &Path, report: &impl Serialize) -> Result<(), Failure> {
    let text = serde_json::to_string_pretty(report).map_err(|e| Failure {
        code: 1,
        message: e.to_string(),
    })?;
    demkit::io::write_bytes_atomically(path, (text + "\n").as_bytes())
        .map_err(|e| Failure::input(format!("{}: {e}", path.display())))
}

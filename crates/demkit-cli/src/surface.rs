//! Reading the input mesh: the file read, the surface validated, its warnings printed.

use crate::Failure;
use demkit::Surface;
use std::path::Path;

/// Reads and validates a mesh ([`Surface`]), printing validation warnings unless `quiet`.
pub fn read_valid_mesh(path: &Path, quiet: bool) -> Result<Surface, Failure> {
    let surface = Surface::from_mesh(demkit::io::read_mesh(path)?)?;
    if !quiet {
        for w in surface.warnings() {
            eprintln!("warning: {w}");
        }
    }
    Ok(surface)
}

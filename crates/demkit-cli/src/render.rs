//! Pictures: `demkit render`, and `map --render` / `map --histogram`.

use crate::Failure;
use crate::args::RenderArgs;
use crate::map::Computed;
use demkit::TriMesh;
use std::path::Path;

/// Pictures are written as .png only.
pub fn check_png_extension(path: &Path) -> Result<(), Failure> {
    let png = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if png {
        Ok(())
    } else {
        Err(Failure::input(format!(
            "cannot write '{}': pictures are written as .png",
            path.display()
        )))
    }
}

/// Draws the mapped mesh coloured by the input population density.
pub fn render_map(_png: &Path, _mesh: &TriMesh, _c: &Computed) -> Result<(), Failure> {
    Err(Failure::not_implemented("--render"))
}

/// Draws the initial and final density histograms side by side.
pub fn render_histograms(_png: &Path, _mesh: &TriMesh, _c: &Computed) -> Result<(), Failure> {
    Err(Failure::not_implemented("--histogram"))
}

/// Runs the render command; returns the exit code.
pub fn run(_a: &RenderArgs) -> Result<u8, Failure> {
    Err(Failure::not_implemented("demkit render"))
}

//! `demkit generate`: synthetic meshes made by demkit itself.

use crate::Failure;
use crate::args::{GenerateArgs, GenerateKind};
use demkit::generate as g;

/// Writes the requested mesh to `--out`.
pub fn run(a: &GenerateArgs) -> Result<u8, Failure> {
    let out = a
        .out
        .as_ref()
        .ok_or_else(|| Failure::input("generate needs --out FILE (.obj or .ply)"))?;
    crate::map::check_output_extension(out)?;
    crate::paths::check(&[], &[crate::paths::named("--out", out)])?;
    let mesh = match &a.kind {
        GenerateKind::Grid {
            nx,
            ny,
            width,
            height,
        } => g::square_grid(*nx, *ny, *width, *height)?,
        GenerateKind::Polygon { sides, rings } => g::regular_polygon(*sides, *rings)?,
        GenerateKind::Peaks { n } => g::peaks(*n)?,
        GenerateKind::Gaussian { n } => g::gaussian(*n)?,
        GenerateKind::Annulus {
            inner,
            outer,
            radial,
            angular,
        } => g::annulus(*inner, *outer, *radial, *angular)?,
        GenerateKind::DiskHoles { holes, resolution } => {
            let parsed = holes
                .iter()
                .map(|h| parse_hole(h))
                .collect::<Result<Vec<_>, _>>()?;
            g::disk_with_holes(&parsed, *resolution)?
        }
        GenerateKind::RectHoles {
            width,
            height,
            holes,
            resolution,
        } => {
            let parsed = holes
                .iter()
                .map(|h| parse_hole(h))
                .collect::<Result<Vec<_>, _>>()?;
            g::rectangle_with_holes(*width, *height, &parsed, *resolution)?
        }
        GenerateKind::Icosphere { subdivisions } => g::icosphere(*subdivisions)?,
        GenerateKind::UvSphere { lat, lon } => g::uv_sphere(*lat, *lon)?,
        GenerateKind::Torus {
            big_r,
            small_r,
            major,
            minor,
        } => g::torus(*big_r, *small_r, *major, *minor)?,
    };
    demkit::io::write_mesh(out, &mesh)?;
    Ok(0)
}

fn parse_hole(s: &str) -> Result<(f64, f64, f64), Failure> {
    let v: Vec<Option<f64>> = s.split(':').map(|x| x.trim().parse::<f64>().ok()).collect();
    match v.as_slice() {
        [Some(cx), Some(cy), Some(r)] => Ok((*cx, *cy, *r)),
        _ => Err(Failure::input(format!(
            "--hole '{s}' must be CX:CY:R with three numbers"
        ))),
    }
}

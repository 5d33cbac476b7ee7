//! `demkit cut`: holes cut into a surface around given points ([`demkit::mesh::cut_holes`]), to
//! make the surfaces with holes that DEQ and the circle-domain map take.

use crate::Failure;
use crate::args::CutArgs;
use crate::paths::{check, named};
use demkit::mesh::{Hole, cut_holes, topology};

/// Cuts the holes and writes the surface.
pub fn run(a: &CutArgs) -> Result<u8, Failure> {
    crate::map::check_output_extension(&a.out)?;
    check(&[named("MESH", &a.mesh)], &[named("--out", &a.out)])?;
    let holes = a
        .hole
        .iter()
        .map(|h| parse_hole(h))
        .collect::<Result<Vec<Hole>, Failure>>()?;
    let (mesh, warnings) = demkit::mesh::validate(demkit::io::read_mesh(&a.mesh)?)?;
    if !a.quiet {
        for w in warnings {
            eprintln!("warning: {w}");
        }
    }
    let cut = cut_holes(&mesh, &holes, a.planar)?;
    demkit::io::write_mesh(&a.out, &cut)?;
    if !a.quiet {
        eprintln!(
            "{} vertices, {} faces -> {} vertices, {} faces, {} boundary loops",
            mesh.n_vertices(),
            mesh.n_faces(),
            cut.n_vertices(),
            cut.n_faces(),
            topology(&cut).boundary_loops.len()
        );
    }
    Ok(0)
}

/// `X,Y,Z,R` as a hole; the radius is checked by [`cut_holes`].
fn parse_hole(text: &str) -> Result<Hole, Failure> {
    let values: Vec<f64> = text
        .split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| Failure::input(format!("--hole '{text}': expected four numbers X,Y,Z,R")))?;
    match values[..] {
        [x, y, z, r] => Ok(Hole {
            centre: [x, y, z],
            radius: r,
        }),
        _ => Err(Failure::input(format!(
            "--hole '{text}': expected four numbers X,Y,Z,R, got {}",
            values.len()
        ))),
    }
}

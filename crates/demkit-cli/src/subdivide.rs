//! `demkit subdivide`: regular subdivision of a mesh ([`demkit::mesh::subdivide_parts`]; midpoint
//! subdivision by default) and of its population file, to make a finer mesh of the same surface (the scale cases of `demkit bench`).

use crate::Failure;
use crate::args::SubdivideArgs;
use crate::paths::{check, given, named};
use demkit::mesh::{split_population_parts, subdivide_parts};
use demkit::population::{check_population, read_face_values};
use std::fmt::Write;

/// Subdivides the mesh `--levels` times in `--parts` and writes it (and the split population)
/// out.
pub fn run(a: &SubdivideArgs) -> Result<u8, Failure> {
    crate::map::check_output_extension(&a.out)?;
    let mut inputs = vec![named("MESH", &a.mesh)];
    if let Some(p) = &a.population {
        inputs.push(named("--population", p));
    }
    check(
        &inputs,
        &given(&[
            ("--out", Some(&a.out)),
            ("--population-out", a.population_out.as_ref()),
        ]),
    )?;
    let (mesh, warnings) = demkit::mesh::validate(demkit::io::read_mesh(&a.mesh)?)?;
    if !a.quiet {
        for w in warnings {
            eprintln!("warning: {w}");
        }
    }
    let population = match &a.population {
        Some(path) => {
            let values = read_face_values(path, mesh.n_faces(), "population file")?;
            check_population(&values, mesh.n_faces())?;
            Some(split_population_parts(&values, a.parts, a.levels)?)
        }
        None => None,
    };
    let fine = subdivide_parts(&mesh, a.parts, a.levels)?;
    demkit::io::write_mesh(&a.out, &fine)?;
    if let (Some(values), Some(path)) = (population, &a.population_out) {
        demkit::io::write_bytes_atomically(path, population_text(&values).as_bytes())
            .map_err(|e| Failure::input(format!("{}: {e}", path.display())))?;
    }
    if !a.quiet {
        eprintln!(
            "{} vertices, {} faces -> {} vertices, {} faces ({} level{} in {} parts)",
            mesh.n_vertices(),
            mesh.n_faces(),
            fine.n_vertices(),
            fine.n_faces(),
            a.levels,
            if a.levels == 1 { "" } else { "s" },
            a.parts
        );
    }
    Ok(0)
}

/// One value per line, each the shortest text that reads back as the same `f64` (plain
/// decimals for ordinary magnitudes, exponent notation for very large or small ones).
fn population_text(values: &[f64]) -> String {
    let mut text = String::with_capacity(values.len() * 20);
    for &v in values {
        let _ = if (1e-5..1e15).contains(&v.abs()) {
            writeln!(text, "{v}")
        } else {
            writeln!(text, "{v:e}")
        };
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn population_values_read_back_exactly() {
        let values = [0.25, 1.0 / 3.0, 1e-300, 7.5e20, 123456.789];
        let text = population_text(&values);
        assert_eq!(text.lines().next(), Some("0.25"));
        assert_eq!(text.lines().nth(2), Some("1e-300"));
        let back: Vec<f64> = text.lines().map(|l| l.parse().unwrap()).collect();
        assert_eq!(back, values);
    }
}

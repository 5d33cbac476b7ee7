//! What the circle-domain methods (DEQ, LDEQ and the conformal circle-domain map) give back
//! when they cannot compute their map: a surface whose conformal map, or whose harmonic
//! embedding, shrinks a region below double precision (a long corridor wound around itself,
//! such as a spiral), or a factorization that broke down on the way. The run is then not
//! converged (stop reason `max_iter`, exit code 3 in the command line), a note gives the
//! reason, and the positions are the best stand-in the method had: a bijective circle domain
//! map of an earlier stage when there is one, else the surface laid flat
//! ([`planar_stand_in`]).

use crate::geometry::signed_area_2d;
use crate::methods::{MapResult, StopReason};
use crate::{Error, Result, TriMesh};

/// Splits a numerical failure off `r`: `Ok(Err(why))` for [`Error::Numerical`], which a
/// circle-domain method turns into a refused run ([`refused`]); every other error (the input's)
/// passes on.
pub(crate) fn numerical<T>(r: Result<T>) -> Result<std::result::Result<T, String>> {
    match r {
        Ok(v) => Ok(Ok(v)),
        Err(Error::Numerical(why)) => Ok(Err(why)),
        Err(e) => Err(e),
    }
}

/// The run of `method` that could not compute its map because of `why`: `positions` (what
/// `stand_in` describes) as both its initial and final map, no iterations, not converged.
pub(crate) fn refused(
    method: &'static str,
    positions: Vec<[f64; 3]>,
    why: &str,
    stand_in: &str,
) -> MapResult {
    let mut result = MapResult::new(
        method,
        positions.clone(),
        positions,
        StopReason::MaxIter,
        0,
        Vec::new(),
    );
    result.refused = true;
    result.notes.push(format!(
        "{method} could not compute its map: {why}; the result is {stand_in}"
    ));
    result
}

/// What [`planar_stand_in`] is, for the note of a refused run.
pub(crate) const PLANAR_STAND_IN: &str =
    "the surface's own x, y coordinates moved into the unit disk, not a circle domain map";

/// The surface's x, y coordinates (z dropped) moved into the unit disk: centred on the mean of
/// the outer loop's vertices, scaled so that the farthest vertex lies on the unit circle, and
/// mirrored when more of the faces turn clockwise than counter-clockwise. For a planar domain
/// with holes this is a bijective map onto a region of the disk (not a circle domain); for a
/// curved surface it may fold.
pub(crate) fn planar_stand_in(mesh: &TriMesh, outer: &[u32]) -> Vec<[f64; 3]> {
    let m = outer.len().max(1) as f64;
    let (cx, cy) = outer.iter().fold((0.0, 0.0), |(x, y), &v| {
        let p = mesh.positions[v as usize];
        (x + p[0] / m, y + p[1] / m)
    });
    let radius = mesh
        .positions
        .iter()
        .map(|p| (p[0] - cx).hypot(p[1] - cy))
        .fold(0.0, f64::max);
    let scale = if radius > 0.0 && radius.is_finite() {
        1.0 / radius
    } else {
        1.0
    };
    let mut x: Vec<[f64; 3]> = mesh
        .positions
        .iter()
        .map(|p| [(p[0] - cx) * scale, (p[1] - cy) * scale, 0.0])
        .collect();
    let clockwise = mesh
        .faces
        .iter()
        .filter(|f| {
            let [a, b, c] = f.map(|v| x[v as usize]);
            signed_area_2d(a, b, c) < 0.0
        })
        .count();
    if 2 * clockwise > mesh.faces.len() {
        x.iter_mut().for_each(|p| p[0] = -p[0]);
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::annulus;
    use crate::geometry::count_nonpositive;

    #[test]
    fn a_planar_domain_laid_flat_is_bijective_in_the_unit_disk_either_way_round() {
        let mesh = annulus(0.3, 1.0, 8, 24).unwrap();
        let outer = crate::mesh::topology::topology(&mesh).boundary_loops[0].clone();
        let mut mirrored = mesh.clone();
        mirrored
            .positions
            .iter_mut()
            .for_each(|p| p[0] = 3.0 - 2.0 * p[0]);
        for m in [&mesh, &mirrored] {
            let x = planar_stand_in(m, &outer);
            assert_eq!(count_nonpositive(&x, &m.faces), 0);
            let r = x.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max);
            assert!((r - 1.0).abs() < 1e-12, "{r}");
        }
    }

    #[test]
    fn a_numerical_failure_is_split_off_and_an_input_error_passes() {
        let n: Result<()> = Err(Error::Numerical("crushed".into()));
        assert_eq!(numerical(n).unwrap(), Err("crushed".to_string()));
        let a: Result<()> = Err(Error::Argument("bad".into()));
        assert!(numerical(a).is_err());
        let r = refused("deq", vec![[0.0; 3]], "crushed", PLANAR_STAND_IN);
        assert!(r.refused && !r.converged && r.notes[0].contains("crushed"));
    }
}

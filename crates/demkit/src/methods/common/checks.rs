//! Input checks every method shares: a valid mesh, landmark vertices in range.

/// Refuses a mesh the methods cannot work on, whoever built it: the first error of
/// [`crate::mesh::validate::check`] (a face index out of range, a non-finite coordinate, a
/// degenerate or non-manifold face, ...). The CLI validates on reading; this keeps a library
/// caller's unvalidated mesh from reaching the numerics.
pub(crate) fn require_valid_mesh(mesh: &crate::TriMesh, method: &str) -> crate::Result<()> {
    match crate::mesh::validate::check(mesh).errors.into_iter().next() {
        Some(e) => Err(crate::Error::InvalidMesh(format!("{method}: {e}"))),
        None => Ok(()),
    }
}

/// Checks what every landmark method needs of its landmarks: at least one, vertex indices in
/// range, each vertex once (landmarks are numbered from 1 in the messages).
pub(crate) fn check_landmark_vertices(
    landmarks: &[(usize, [f64; 3])],
    n_vertices: usize,
    method: &str,
) -> crate::Result<()> {
    use crate::Error;
    if landmarks.is_empty() {
        return Err(Error::Landmarks(format!(
            "{method} needs at least one landmark"
        )));
    }
    let mut seen = vec![false; n_vertices];
    for (k, &(v, _)) in landmarks.iter().enumerate() {
        if v >= n_vertices {
            return Err(Error::Landmarks(format!(
                "landmark {}: vertex {v} is out of range (mesh has {n_vertices} vertices)",
                k + 1
            )));
        }
        if std::mem::replace(&mut seen[v], true) {
            return Err(Error::Landmarks(format!(
                "landmark {}: vertex {v} appears twice",
                k + 1
            )));
        }
    }
    Ok(())
}

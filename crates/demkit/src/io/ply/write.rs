//! The writer: binary little-endian PLY.

use crate::TriMesh;
use std::io::Write;

/// Writes `mesh` as binary little-endian PLY with `double` x, y, z and a `uchar int`
/// `vertex_indices` list per face. Flushes `w` at the end.
pub fn write_ply<W: Write>(mut w: W, mesh: &TriMesh) -> std::io::Result<()> {
    write!(
        w,
        "ply\nformat binary_little_endian 1.0\ncomment written by demkit\n\
         element vertex {}\nproperty double x\nproperty double y\nproperty double z\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        mesh.positions.len(),
        mesh.faces.len()
    )?;
    let mut buf = [0u8; 24];
    for p in &mesh.positions {
        for k in 0..3 {
            buf[8 * k..8 * k + 8].copy_from_slice(&p[k].to_le_bytes());
        }
        w.write_all(&buf)?;
    }
    let mut buf = [0u8; 13];
    buf[0] = 3;
    for f in &mesh.faces {
        for k in 0..3 {
            buf[1 + 4 * k..5 + 4 * k].copy_from_slice(&(f[k] as i32).to_le_bytes());
        }
        w.write_all(&buf)?;
    }
    w.flush()
}

//! Small meshes for unit tests of the operators (test-only).

use crate::TriMesh;

/// The unit square 0(0,0) 1(1,0) 2(1,1) 3(0,1) in the plane z = 0, as two counter-clockwise
/// triangles.
pub fn unit_square() -> TriMesh {
    TriMesh::new(
        vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
        vec![[0, 1, 2], [0, 2, 3]],
    )
}

/// A jittered planar grid on [0,1]² with `n × n` squares: positions (z = 0), counter-clockwise
/// faces, and a boundary flag per vertex. Jitter moves interior vertices by up to `jitter / n`
/// deterministically, keeping every triangle positively oriented for `jitter < 0.25`.
pub fn grid(n: usize, jitter: f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>, Vec<bool>) {
    let m = n + 1;
    let mut pos = Vec::with_capacity(m * m);
    let mut boundary = Vec::with_capacity(m * m);
    for j in 0..m {
        for i in 0..m {
            let on_b = i == 0 || j == 0 || i == n || j == n;
            let (dx, dy) = if on_b {
                (0.0, 0.0)
            } else {
                let s = ((i * 7 + j * 13) % 11) as f64 / 10.0 - 0.5;
                let t = ((i * 5 + j * 3) % 7) as f64 / 6.0 - 0.5;
                (jitter * s / n as f64, jitter * t / n as f64)
            };
            pos.push([i as f64 / n as f64 + dx, j as f64 / n as f64 + dy, 0.0]);
            boundary.push(on_b);
        }
    }
    let mut faces = Vec::with_capacity(2 * n * n);
    for j in 0..n {
        for i in 0..n {
            let a = (j * m + i) as u32;
            let b = a + 1;
            let c = a + m as u32 + 1;
            let d = a + m as u32;
            faces.push([a, b, c]);
            faces.push([a, c, d]);
        }
    }
    (pos, faces, boundary)
}

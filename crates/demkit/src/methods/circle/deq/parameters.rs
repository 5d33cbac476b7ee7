//! Circle domain maps as unknowns: every free vertex's position, the angle of every boundary
//! vertex on its circle, and each hole's centre and radius (unless the holes keep their
//! circles). Every map these unknowns describe has its outer loop on the unit circle and each
//! hole's loop on a circle.

use super::circles::Circle;

/// How a vertex's position depends on the unknowns.
#[derive(Debug, Clone, Copy)]
enum Role {
    /// Does not move.
    Fixed,
    /// Free: unknowns `k`, `k + 1`.
    Free(usize),
    /// On the unit circle at angle unknown `k`.
    Outer(usize),
    /// On hole `h`'s circle at angle unknown `k`.
    Hole(usize, usize),
}

/// The parameterization of the circle domain maps of one mesh.
pub(crate) struct Parameters {
    role: Vec<Role>,
    /// Index of every hole's centre x, centre y and radius in the parameter vector.
    hole_base: Vec<usize>,
    /// Number of unknowns. With fixed holes the circles sit after the unknowns in the
    /// parameter vector.
    pub n: usize,
    fixed_holes: bool,
}

/// A vertex's unknowns and `∂(x, y)/∂unknown` for each (the first `count` entries).
pub(crate) struct VertexJacobian {
    pub unknowns: [usize; 4],
    pub derivatives: [[f64; 2]; 4],
    pub count: usize,
}

impl Parameters {
    /// The parameterization of the maps of `n_vertices` vertices in which the vertices of
    /// `faces` move, those of `outer` on the unit circle and those of each loop of `holes` on
    /// its circle, and `pinned` vertices and the vertices of no face stay.
    pub fn new(
        n_vertices: usize,
        faces: &[[u32; 3]],
        outer: &[u32],
        holes: &[Vec<u32>],
        pinned: &[u32],
        fixed_holes: bool,
    ) -> Self {
        let mut role = vec![Role::Fixed; n_vertices];
        for &v in faces.iter().flatten() {
            role[v as usize] = Role::Free(0);
        }
        // Loop vertices slide on their circles (those of the faces only: the rest stay).
        for &v in outer {
            if let Role::Free(_) = role[v as usize] {
                role[v as usize] = Role::Outer(0);
            }
        }
        for (h, lp) in holes.iter().enumerate() {
            for &v in lp {
                if let Role::Free(_) = role[v as usize] {
                    role[v as usize] = Role::Hole(h, 0);
                }
            }
        }
        for &v in pinned {
            role[v as usize] = Role::Fixed;
        }
        let mut n = 0;
        for r in role.iter_mut() {
            match r {
                Role::Free(k) => {
                    *k = n;
                    n += 2;
                }
                Role::Outer(k) | Role::Hole(_, k) => {
                    *k = n;
                    n += 1;
                }
                Role::Fixed => {}
            }
        }
        let hole_base = (0..holes.len()).map(|h| n + 3 * h).collect();
        if !fixed_holes {
            n += 3 * holes.len();
        }
        Self {
            role,
            hole_base,
            n,
            fixed_holes,
        }
    }

    /// The parameters of the map `x` whose hole loops are `holes`.
    pub fn read(&self, x: &[[f64; 3]], holes: &[Vec<u32>]) -> Vec<f64> {
        let mut u = vec![0.0; self.n.max(self.hole_base.last().map_or(0, |b| b + 3))];
        let circles: Vec<Circle> = holes.iter().map(|lp| Circle::fit(x, lp)).collect();
        for (h, c) in circles.iter().enumerate() {
            let b = self.hole_base[h];
            u[b] = c.center[0];
            u[b + 1] = c.center[1];
            u[b + 2] = c.radius;
        }
        for (v, r) in self.role.iter().enumerate() {
            match *r {
                Role::Free(k) => {
                    u[k] = x[v][0];
                    u[k + 1] = x[v][1];
                }
                Role::Outer(k) => u[k] = x[v][1].atan2(x[v][0]),
                Role::Hole(h, k) => {
                    let c = &circles[h];
                    u[k] = (x[v][1] - c.center[1]).atan2(x[v][0] - c.center[0]);
                }
                Role::Fixed => {}
            }
        }
        u
    }

    /// Writes the map of the parameters `u` into `x` (fixed vertices keep their place).
    pub fn write(&self, u: &[f64], x: &mut [[f64; 3]]) {
        for (v, r) in self.role.iter().enumerate() {
            match *r {
                Role::Free(k) => x[v] = [u[k], u[k + 1], 0.0],
                Role::Outer(k) => x[v] = [u[k].cos(), u[k].sin(), 0.0],
                Role::Hole(h, k) => {
                    let b = self.hole_base[h];
                    x[v] = [
                        u[b] + u[b + 2] * u[k].cos(),
                        u[b + 1] + u[b + 2] * u[k].sin(),
                        0.0,
                    ];
                }
                Role::Fixed => {}
            }
        }
    }

    /// True when every hole of the parameters `u` has a positive radius.
    pub fn radii_positive(&self, u: &[f64]) -> bool {
        self.hole_base.iter().all(|&b| u[b + 2] > 0.0)
    }

    /// The unknowns vertex `v` depends on at the parameters `u`, and its derivatives.
    pub fn jacobian(&self, v: usize, u: &[f64]) -> VertexJacobian {
        let none = [[0.0; 2]; 4];
        match self.role[v] {
            Role::Fixed => VertexJacobian {
                unknowns: [0; 4],
                derivatives: none,
                count: 0,
            },
            Role::Free(k) => VertexJacobian {
                unknowns: [k, k + 1, 0, 0],
                derivatives: [[1.0, 0.0], [0.0, 1.0], [0.0; 2], [0.0; 2]],
                count: 2,
            },
            Role::Outer(k) => {
                let (s, c) = u[k].sin_cos();
                VertexJacobian {
                    unknowns: [k, 0, 0, 0],
                    derivatives: [[-s, c], [0.0; 2], [0.0; 2], [0.0; 2]],
                    count: 1,
                }
            }
            Role::Hole(h, k) => {
                // x = cx + ρ cos θ, y = cy + ρ sin θ in (θ, cx, cy, ρ).
                let b = self.hole_base[h];
                let (s, c) = u[k].sin_cos();
                let r = u[b + 2];
                VertexJacobian {
                    unknowns: [k, b, b + 1, b + 2],
                    derivatives: [[-r * s, r * c], [1.0, 0.0], [0.0, 1.0], [c, s]],
                    count: if self.fixed_holes { 1 } else { 4 },
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn read_then_write_reproduces_a_circle_domain_map() {
        // An outer vertex, a free one, and a hole of three vertices on a circle.
        let c = [0.2, -0.1];
        let hole: Vec<[f64; 3]> = (0..3)
            .map(|k| {
                let t = 2.0 * k as f64;
                [c[0] + 0.3 * t.cos(), c[1] + 0.3 * t.sin(), 0.0]
            })
            .collect();
        let mut x = vec![[0.6f64.cos(), 0.6f64.sin(), 0.0], [0.1, 0.5, 0.0]];
        x.extend(hole);
        let faces = [[0u32, 1, 2], [1, 3, 4]];
        let holes = vec![vec![2u32, 3, 4]];
        let p = Parameters::new(5, &faces, &[0], &holes, &[], false);
        assert_eq!(p.n, 1 + 2 + 3 + 3);
        let u = p.read(&x, &holes);
        let mut y = vec![[9.0; 3]; 5];
        p.write(&u, &mut y);
        for (a, b) in x.iter().zip(&y) {
            assert!((a[0] - b[0]).abs() < 1e-14 && (a[1] - b[1]).abs() < 1e-14);
        }
        // The Jacobian of a hole vertex by finite differences of write.
        let j = p.jacobian(3, &u);
        for s in 0..j.count {
            let mut v = u.clone();
            v[j.unknowns[s]] += 1e-7;
            let mut z = y.clone();
            p.write(&v, &mut z);
            for d in 0..2 {
                let fd = (z[3][d] - y[3][d]) / 1e-7;
                assert!((fd - j.derivatives[s][d]).abs() < 1e-6);
            }
        }
    }
}

//! The diffusion of a density on a grid of nx × ny unit cells with reflecting (Neumann)
//! walls, solved in closed form with the discrete cosine transform (Gastner, Seguy & More
//! 2018): the density's cosine coefficients decay as exp(−π²(kx²/nx² + ky²/ny²) t), and the
//! flow's velocity at time t is v = −∇ρ(t)/ρ(t).
//!
//! Cells are indexed row-major (`y * nx + x`); cell (x, y) covers [x, x+1] × [y, y+1].
//! Velocities live on the (nx+1) × (ny+1) cell corners (the nodes).

use rayon::prelude::*;
use rustdct::{DctPlanner, TransformType2And3};
use std::sync::Arc;

/// A density's cosine coefficients, ready to give the density at any time.
pub struct Diffusion {
    nx: usize,
    ny: usize,
    /// The coefficients, row-major like the density.
    coef: Vec<f64>,
    row: Arc<dyn TransformType2And3<f64>>,
    col: Arc<dyn TransformType2And3<f64>>,
}

/// The velocity on the nodes at one time.
pub struct Velocity {
    /// Nodes per row (nx + 1).
    pub stride: usize,
    /// x and y components, row-major over the nodes.
    pub vx: Vec<f64>,
    /// See `vx`.
    pub vy: Vec<f64>,
    /// A bound on the velocity's spatial derivative (the largest sum of the absolute
    /// differences of its components between neighbouring nodes).
    pub lipschitz: f64,
}

/// Transposes an `rows` × `cols` row-major matrix.
fn transpose(a: &[f64], rows: usize, cols: usize) -> Vec<f64> {
    let mut t = vec![0.0; a.len()];
    const B: usize = 32;
    for r0 in (0..rows).step_by(B) {
        for c0 in (0..cols).step_by(B) {
            for r in r0..(r0 + B).min(rows) {
                for c in c0..(c0 + B).min(cols) {
                    t[c * rows + r] = a[r * cols + c];
                }
            }
        }
    }
    t
}

impl Diffusion {
    /// The coefficients of `rho` (nx × ny cells, all positive).
    pub fn new(rho: &[f64], nx: usize, ny: usize) -> Diffusion {
        let mut planner = DctPlanner::new();
        let row = planner.plan_dct2(nx);
        let col = planner.plan_dct2(ny);
        let mut a = rho.to_vec();
        a.par_chunks_mut(nx).for_each(|r| row.process_dct2(r));
        let mut t = transpose(&a, ny, nx);
        t.par_chunks_mut(ny).for_each(|c| col.process_dct2(c));
        let coef = transpose(&t, nx, ny);
        Diffusion {
            nx,
            ny,
            coef,
            row,
            col,
        }
    }

    /// The density at time `t` (cell units), into a new vector.
    pub fn density(&self, t: f64) -> Vec<f64> {
        let (nx, ny) = (self.nx, self.ny);
        let pi2 = std::f64::consts::PI * std::f64::consts::PI;
        let ex: Vec<f64> = (0..nx)
            .map(|k| (-pi2 * (k * k) as f64 / (nx * nx) as f64 * t).exp())
            .collect();
        let ey: Vec<f64> = (0..ny)
            .map(|k| (-pi2 * (k * k) as f64 / (ny * ny) as f64 * t).exp())
            .collect();
        let mut a: Vec<f64> = self.coef.clone();
        a.par_chunks_mut(nx).enumerate().for_each(|(ky, r)| {
            for (kx, c) in r.iter_mut().enumerate() {
                *c *= ex[kx] * ey[ky];
            }
            self.row.process_dct3(r);
        });
        let mut t = transpose(&a, ny, nx);
        t.par_chunks_mut(ny).for_each(|c| self.col.process_dct3(c));
        let scale = 4.0 / (nx * ny) as f64;
        let mut out = transpose(&t, nx, ny);
        out.par_iter_mut().for_each(|v| *v *= scale);
        out
    }

    /// The velocity −∇ρ/ρ on the nodes for the density `rho` (as from
    /// [`Diffusion::density`]): differences of the four cells around each node, the cells
    /// beyond the walls mirroring those inside, so that the velocity along a wall is parallel
    /// to it and zero at the corners.
    pub fn velocity(&self, rho: &[f64]) -> Velocity {
        let (nx, ny) = (self.nx, self.ny);
        let stride = nx + 1;
        let cell = |x: isize, y: isize| {
            let x = x.clamp(0, nx as isize - 1) as usize;
            let y = y.clamp(0, ny as isize - 1) as usize;
            rho[y * nx + x]
        };
        let rows: Vec<(Vec<f64>, Vec<f64>)> = (0..=ny)
            .into_par_iter()
            .map(|j| {
                let mut vx = vec![0.0; stride];
                let mut vy = vec![0.0; stride];
                let y = j as isize;
                for i in 0..=nx {
                    let x = i as isize;
                    let (a, b, c, d) = (
                        cell(x - 1, y - 1),
                        cell(x, y - 1),
                        cell(x - 1, y),
                        cell(x, y),
                    );
                    let r = 0.25 * (a + b + c + d);
                    let (gx, gy) = if r > 0.0 {
                        (0.5 * (b + d - a - c) / r, 0.5 * (c + d - a - b) / r)
                    } else {
                        (0.0, 0.0)
                    };
                    vx[i] = if i == 0 || i == nx { 0.0 } else { -gx };
                    vy[i] = if j == 0 || j == ny { 0.0 } else { -gy };
                }
                (vx, vy)
            })
            .collect();
        let mut vx = Vec::with_capacity(stride * (ny + 1));
        let mut vy = Vec::with_capacity(stride * (ny + 1));
        for (x, y) in rows {
            vx.extend(x);
            vy.extend(y);
        }
        let lipschitz = (0..ny)
            .into_par_iter()
            .map(|j| {
                let mut m = 0.0f64;
                for i in 0..nx {
                    let k = j * stride + i;
                    let d = (vx[k + 1] - vx[k]).abs()
                        + (vx[k + stride] - vx[k]).abs()
                        + (vy[k + 1] - vy[k]).abs()
                        + (vy[k + stride] - vy[k]).abs();
                    m = m.max(d);
                }
                m
            })
            .reduce(|| 0.0, f64::max);
        Velocity {
            stride,
            vx,
            vy,
            lipschitz,
        }
    }
}

impl Velocity {
    /// The velocity at `p` (cell units, inside the grid), interpolated bilinearly.
    pub fn at(&self, p: [f64; 2]) -> [f64; 2] {
        let nx = self.stride - 1;
        let ny = self.vx.len() / self.stride - 1;
        let x = p[0].clamp(0.0, nx as f64);
        let y = p[1].clamp(0.0, ny as f64);
        let i = (x.floor() as usize).min(nx - 1);
        let j = (y.floor() as usize).min(ny - 1);
        let (fx, fy) = (x - i as f64, y - j as f64);
        let k = j * self.stride + i;
        let s = self.stride;
        let lerp = |v: &[f64]| {
            (1.0 - fy) * ((1.0 - fx) * v[k] + fx * v[k + 1])
                + fy * ((1.0 - fx) * v[k + s] + fx * v[k + s + 1])
        };
        [lerp(&self.vx), lerp(&self.vy)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn density_at_time_zero_is_the_input_and_mass_is_kept() {
        let (nx, ny) = (8, 4);
        let rho: Vec<f64> = (0..nx * ny).map(|k| 1.0 + (k % 5) as f64).collect();
        let d = Diffusion::new(&rho, nx, ny);
        let back = d.density(0.0);
        for (a, b) in rho.iter().zip(&back) {
            assert!((a - b).abs() < 1e-12, "{a} {b}");
        }
        let later = d.density(3.0);
        let (m0, m1): (f64, f64) = (rho.iter().sum(), later.iter().sum());
        assert!((m0 - m1).abs() < 1e-9);
        // Long after, uniform.
        let end = d.density(1e4);
        let mean = m0 / (nx * ny) as f64;
        assert!(end.iter().all(|v| (v - mean).abs() < 1e-9));
    }

    #[test]
    fn velocity_points_from_dense_to_sparse_and_walls_hold() {
        let (nx, ny) = (4, 4);
        let rho: Vec<f64> = (0..16).map(|k| if k % 4 < 2 { 2.0 } else { 1.0 }).collect();
        let d = Diffusion::new(&rho, nx, ny);
        let v = d.velocity(&rho);
        let mid = v.at([2.0, 2.0]);
        assert!(mid[0] > 0.0 && mid[1].abs() < 1e-12, "{mid:?}");
        assert_eq!(v.at([0.0, 2.0])[0], 0.0);
        assert_eq!(v.at([4.0, 2.0])[0], 0.0);
        assert!(v.lipschitz > 0.0);
    }
}

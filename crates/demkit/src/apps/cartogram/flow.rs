//! The density-equalizing flow of Gastner, Seguy & More (2018, eqs. 5–8) on a grid of
//! nx × ny unit cells with reflecting (Neumann) walls. The density goes linearly in time from
//! the map's, ρ₀, to the mean ρ̄:
//!
//! ρ(t) = (1 − t) ρ₀ + t ρ̄,  t ∈ [0, 1],
//!
//! which the continuity equation ∂ρ/∂t + ∇·(ρ v) = 0 satisfies with the flux ρ v = ∇Ψ of the
//! potential ∇²Ψ = ρ₀ − ρ̄. Ψ is solved once, in closed form with the discrete cosine
//! transform, and its gradient is taken spectrally (a sine series); the velocity at any time
//! is then v = ∇Ψ / ρ(t), interpolated at each point, with no further transform.
//!
//! Cells are indexed row-major (`y * nx + x`); cell (x, y) covers [x, x+1] × [y, y+1]. The
//! fields are kept at the cell centres plus a ghost line on each wall, where the velocity's
//! normal component is zero.

use rayon::prelude::*;
use rustdct::{DctPlanner, TransformType2And3};
use std::f64::consts::PI;
use std::sync::Arc;

/// The `rows` × `cols` row-major matrix `a` transposed into `t` (`cols` × `rows`), in
/// blocks of rows of `t` shared between threads.
fn transpose(a: &[f64], rows: usize, cols: usize, t: &mut [f64]) {
    const B: usize = 32;
    t.par_chunks_mut(B * rows)
        .enumerate()
        .for_each(|(block, out)| {
            let c0 = block * B;
            let c1 = (c0 + B).min(cols);
            for r0 in (0..rows).step_by(B) {
                for r in r0..(r0 + B).min(rows) {
                    let src = &a[r * cols..][..cols];
                    for c in c0..c1 {
                        out[(c - c0) * rows + r] = src[c];
                    }
                }
            }
        });
}

/// Which inverse transform an axis gets: the cosine series (the value) or the sine series
/// of its derivative.
#[derive(Clone, Copy, PartialEq)]
enum Series {
    Cosine,
    Sine,
}

/// The 2-D transforms of one grid. Coefficients are held column-major (`kx * ny + ky`), the
/// layout the forward transform ends in and the inverse starts from, so each direction
/// needs one transposition.
struct Transforms {
    nx: usize,
    ny: usize,
    row: Arc<dyn TransformType2And3<f64>>,
    col: Arc<dyn TransformType2And3<f64>>,
}

impl Transforms {
    fn new(nx: usize, ny: usize) -> Transforms {
        let mut planner = DctPlanner::new();
        Transforms {
            nx,
            ny,
            row: planner.plan_dct2(nx),
            col: planner.plan_dct2(ny),
        }
    }

    /// The cosine coefficients of `rho` (row-major cells; unnormalised DCT-II along both
    /// axes), column-major, and a second buffer of the same size the transform used as
    /// scratch (its content undefined), for the caller to reuse.
    fn forward(&self, rho: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let (nx, ny) = (self.nx, self.ny);
        let mut a = rho.to_vec();
        a.par_chunks_mut(nx).for_each(|r| self.row.process_dct2(r));
        let mut t = vec![0.0; nx * ny];
        transpose(&a, ny, nx, &mut t);
        t.par_chunks_mut(ny).for_each(|c| self.col.process_dct2(c));
        (t, a)
    }

    /// The values at the cell centres (row-major) of the series with the column-major
    /// coefficients `coef` (as from [`Transforms::forward`], already multiplied by whatever
    /// the series needs), each axis summed as a cosine or a sine series, times `scale`. For
    /// a sine series the coefficient of frequency k is read at index k (k ≥ 1) and shifted
    /// into the transform's own layout here. `coef` is used as scratch; the values are
    /// written into `out` (nx × ny).
    fn inverse(&self, coef: &mut [f64], x: Series, y: Series, scale: f64, out: &mut [f64]) {
        let (nx, ny) = (self.nx, self.ny);
        let shift = |r: &mut [f64], s: Series| {
            if s == Series::Sine {
                // DST-III reads frequency k + 1 at index k; frequency n does not exist.
                r.rotate_left(1);
                if let Some(last) = r.last_mut() {
                    *last = 0.0;
                }
            }
        };
        coef.par_chunks_mut(ny).for_each(|c| {
            shift(c, y);
            match y {
                Series::Cosine => self.col.process_dct3(c),
                Series::Sine => self.col.process_dst3(c),
            }
        });
        transpose(coef, nx, ny, out);
        out.par_chunks_mut(nx).for_each(|r| {
            shift(r, x);
            match x {
                Series::Cosine => self.row.process_dct3(r),
                Series::Sine => self.row.process_dst3(r),
            }
            r.iter_mut().for_each(|v| *v *= scale);
        });
    }
}

/// The flow of one density: its flux ∇Ψ and its (blurred) start density ρ₀ at the cell
/// centres and on ghost lines along the walls, and the mean density ρ̄.
pub struct Flow {
    nx: usize,
    ny: usize,
    /// Per padded sample, (nx + 2) × (ny + 2) row-major with the ghost lines first and last:
    /// the flux's x and y components and ρ₀, together so that one interpolation reads
    /// neighbouring memory.
    samples: Vec<[f64; 3]>,
    /// ρ̄.
    mean: f64,
}

/// Where `x` (cell units, in [0, n]) falls among the padded samples of one axis (the wall
/// at 0, the centres i + ½, the wall at n): the lower sample's index and the fraction.
fn locate(x: f64, n: usize) -> (usize, f64) {
    let nf = n as f64;
    if !(x > 0.5) {
        (0, (2.0 * x).clamp(0.0, 1.0))
    } else if x >= nf - 0.5 {
        (n, (2.0 * (x - (nf - 0.5))).clamp(0.0, 1.0))
    } else {
        let s = x + 0.5;
        // s > 1: truncation is the floor.
        let i = (s as usize).clamp(1, n - 1);
        (i, s - i as f64)
    }
}

/// The cell-centred `field` (nx × ny) written into component `q` of the padded `samples`
/// ((nx + 2) × (ny + 2), zero on entry), with a ghost line on each wall: copies of the
/// nearest centres, or left zero on the walls across which `normal` (0: x, 1: y) points.
fn pad(
    field: &[f64],
    nx: usize,
    ny: usize,
    normal: Option<usize>,
    samples: &mut [[f64; 3]],
    q: usize,
) {
    let (px, py) = (nx + 2, ny + 2);
    samples.par_chunks_mut(px).enumerate().for_each(|(j, row)| {
        if normal == Some(1) && (j == 0 || j == py - 1) {
            return;
        }
        let src = &field[(j.clamp(1, ny) - 1) * nx..][..nx];
        for (s, &v) in row[1..=nx].iter_mut().zip(src) {
            s[q] = v;
        }
        if normal != Some(0) {
            row[0][q] = src[0];
            row[nx + 1][q] = src[nx - 1];
        }
    });
}

impl Flow {
    /// The flow of the density `rho` (nx × ny cells, all positive) blurred first by a
    /// diffusion for time `blur` (cells²: a Gaussian of standard deviation √(2·blur) cells),
    /// which softens the steps of density between regions.
    pub fn new(rho: &[f64], nx: usize, ny: usize, blur: f64) -> Flow {
        let tr = Transforms::new(nx, ny);
        // The blurred density's coefficients replace the density's in `coef`; the flux's
        // go into the forward transform's scratch and one more buffer.
        let (mut coef, mut dx) = tr.forward(rho);
        let mean = coef.first().copied().unwrap_or(0.0) / (nx * ny) as f64;
        // Per axis: the wavenumber π k / n, its square, and the blur's decay.
        let axis = |n: usize| -> Vec<(f64, f64, f64)> {
            (0..n)
                .map(|k| {
                    let w = PI * k as f64 / n as f64;
                    (w, w * w, (-w * w * blur.max(0.0)).exp())
                })
                .collect()
        };
        let (ax, ay) = (axis(nx), axis(ny));
        let mut dy = vec![0.0; nx * ny];
        coef.par_chunks_mut(ny)
            .zip(dx.par_chunks_mut(ny))
            .zip(dy.par_chunks_mut(ny))
            .enumerate()
            .for_each(|(kx, ((b, gx), gy))| {
                let (wx, wx2, ex) = ax[kx];
                for ky in 0..ny {
                    let (wy, wy2, ey) = ay[ky];
                    let c = b[ky] * ex * ey;
                    b[ky] = c;
                    // Ψ's coefficient (∇²Ψ = ρ₀ − ρ̄, the mean dropped), then the
                    // derivatives' sine coefficients.
                    let l = wx2 + wy2;
                    let psi = if l > 0.0 { -c / l } else { 0.0 };
                    gx[ky] = -psi * wx;
                    gy[ky] = -psi * wy;
                }
            });
        let scale = 4.0 / (nx * ny) as f64;
        let mut samples = vec![[0.0; 3]; (nx + 2) * (ny + 2)];
        // Each inverse writes into a buffer whose coefficients are spent.
        let mut out = vec![0.0; nx * ny];
        tr.inverse(&mut dy, Series::Cosine, Series::Sine, scale, &mut out);
        pad(&out, nx, ny, Some(1), &mut samples, 1);
        tr.inverse(&mut coef, Series::Cosine, Series::Cosine, scale, &mut out);
        pad(&out, nx, ny, None, &mut samples, 2);
        tr.inverse(&mut dx, Series::Sine, Series::Cosine, scale, &mut out);
        pad(&out, nx, ny, Some(0), &mut samples, 0);
        Flow {
            nx,
            ny,
            samples,
            mean,
        }
    }

    /// The mean density ρ̄.
    pub fn mean(&self) -> f64 {
        self.mean
    }

    /// The blurred start density ρ₀ at the centre of cell (x, y).
    pub fn start_density(&self, x: usize, y: usize) -> f64 {
        self.samples[(y + 1) * (self.nx + 2) + x + 1][2]
    }

    /// The velocity ∇Ψ / ρ(t) at `p` (cell units, clamped into the grid), the flux and
    /// density interpolated bilinearly.
    pub fn at(&self, p: [f64; 2], t: f64) -> [f64; 2] {
        let (i, fx) = locate(p[0], self.nx);
        let (j, fy) = locate(p[1], self.ny);
        let s = self.nx + 2;
        let k = j * s + i;
        let v = &self.samples;
        let (w00, w10) = ((1.0 - fy) * (1.0 - fx), (1.0 - fy) * fx);
        let (w01, w11) = (fy * (1.0 - fx), fy * fx);
        let (a, b, c, d) = (v[k], v[k + 1], v[k + s], v[k + s + 1]);
        let lerp = |q: usize| w00 * a[q] + w10 * b[q] + w01 * c[q] + w11 * d[q];
        let r = (1.0 - t) * lerp(2) + t * self.mean;
        if r > 0.0 {
            [lerp(0) / r, lerp(1) / r]
        } else {
            [0.0, 0.0]
        }
    }

    /// A bound on the velocity's spatial derivative at time `t` around `p`: over the padded
    /// cell holding `p`, the sum of the absolute differences of both components across the
    /// cell in x and in y, each divided by the cell's width.
    pub fn local_lipschitz(&self, p: [f64; 2], t: f64) -> f64 {
        let (i, _) = locate(p[0], self.nx);
        let (j, _) = locate(p[1], self.ny);
        let s = self.nx + 2;
        let k = j * s + i;
        let v = |k: usize| {
            let [fx, fy, rho] = self.samples[k];
            let r = (1.0 - t) * rho + t * self.mean;
            if r > 0.0 {
                [fx / r, fy / r]
            } else {
                [0.0, 0.0]
            }
        };
        let (a, b, c, d) = (v(k), v(k + 1), v(k + s), v(k + s + 1));
        let width = |i: usize, n: usize| if i == 0 || i == n { 0.5 } else { 1.0 };
        let (hx, hy) = (width(i, self.nx), width(j, self.ny));
        let across_x = (b[0] - a[0]).abs().max((d[0] - c[0]).abs())
            + (b[1] - a[1]).abs().max((d[1] - c[1]).abs());
        let across_y = (c[0] - a[0]).abs().max((d[0] - b[0]).abs())
            + (c[1] - a[1]).abs().max((d[1] - b[1]).abs());
        across_x / hx + across_y / hy
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One cosine mode on a grid: cos(π kx (x+½)/nx) cos(π ky (y+½)/ny) at the centres.
    fn mode(nx: usize, ny: usize, kx: usize, ky: usize) -> Vec<f64> {
        (0..nx * ny)
            .map(|c| {
                let (x, y) = ((c % nx) as f64 + 0.5, (c / nx) as f64 + 0.5);
                (PI * kx as f64 * x / nx as f64).cos() * (PI * ky as f64 * y / ny as f64).cos()
            })
            .collect()
    }

    #[test]
    fn the_flux_is_the_gradient_of_the_poisson_potential() {
        // ρ₀ = 2 + cos(πx·3/16)cos(πy·2/8): Ψ = −mode/λ, ∇Ψ in closed form.
        let (nx, ny, kx, ky) = (16, 8, 3, 2);
        let m = mode(nx, ny, kx, ky);
        let rho: Vec<f64> = m.iter().map(|v| 2.0 + v).collect();
        let flow = Flow::new(&rho, nx, ny, 0.0);
        assert!((flow.mean() - 2.0).abs() < 1e-12);
        let (ax, ay) = (PI * kx as f64 / nx as f64, PI * ky as f64 / ny as f64);
        let lambda = ax * ax + ay * ay;
        for (x, y) in [(3usize, 4usize), (0, 0), (15, 7), (8, 2)] {
            let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
            // ∂Ψ/∂x = ax sin(ax cx) cos(ay cy) / λ, and likewise in y.
            let gx = ax * (ax * cx).sin() * (ay * cy).cos() / lambda;
            let gy = ay * (ax * cx).cos() * (ay * cy).sin() / lambda;
            let r = flow.start_density(x, y);
            assert!((r - rho[y * nx + x]).abs() < 1e-12);
            let v = flow.at([cx, cy], 0.0);
            assert!((v[0] * r - gx).abs() < 1e-12, "{} {gx}", v[0] * r);
            assert!((v[1] * r - gy).abs() < 1e-12, "{} {gy}", v[1] * r);
            // At t = 1 the density is the mean.
            let w = flow.at([cx, cy], 1.0);
            assert!((w[0] * 2.0 - gx).abs() < 1e-12);
        }
    }

    #[test]
    fn velocity_points_from_dense_to_sparse_and_walls_hold() {
        let (nx, ny) = (8, 8);
        let rho: Vec<f64> = (0..64).map(|k| if k % 8 < 4 { 2.0 } else { 1.0 }).collect();
        let flow = Flow::new(&rho, nx, ny, 0.0);
        let mid = flow.at([4.0, 4.0], 0.0);
        assert!(mid[0] > 0.0 && mid[1].abs() < 1e-12, "{mid:?}");
        assert_eq!(flow.at([0.0, 4.0], 0.3)[0], 0.0);
        assert_eq!(flow.at([8.0, 4.0], 0.3)[0], 0.0);
        assert_eq!(flow.at([4.0, 0.0], 0.3)[1], 0.0);
        // Across the step of density the velocity changes; far from it, it does not.
        assert!(flow.local_lipschitz([4.0, 4.0], 0.0) > 0.0);
        assert!(flow.local_lipschitz([0.2, 4.0], 0.0) < flow.local_lipschitz([4.0, 4.0], 0.0));
    }

    #[test]
    fn blurring_keeps_the_mass_and_damps_the_modes() {
        let (nx, ny) = (16, 16);
        let m = mode(nx, ny, 4, 0);
        let rho: Vec<f64> = m.iter().map(|v| 3.0 + v).collect();
        let blur = 2.0;
        let flow = Flow::new(&rho, nx, ny, blur);
        let decay = (-(PI * 4.0 / 16.0).powi(2) * blur).exp();
        for (x, mode_x) in m.iter().enumerate().take(nx) {
            let want = 3.0 + decay * mode_x;
            assert!((flow.start_density(x, 5) - want).abs() < 1e-12);
        }
    }
}

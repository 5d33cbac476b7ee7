//! The edge weights of the periodic harmonic map, from the conformal choice to the ones that
//! always give an embedding.
//!
//! Cotangent weights give the discrete conformal (harmonic) map, but an edge whose two opposite
//! angles add up to more than π has a negative weight, and the map may then fold triangles.
//! With positive symmetric weights the periodic harmonic map of a torus triangulation is an
//! embedding (Gortler, Gotsman & Thurston 2006, the toroidal analogue of Tutte's theorem). The
//! fallbacks raise the weights of the edges around the folds first (close to conformal, no
//! guarantee), then of every edge (guaranteed), and finally use uniform weights.

/// Which edge weights a periodic harmonic map was computed with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HarmonicWeights {
    /// The cotangent weights `½ (cot α + cot β)`: the discrete conformal map.
    Cotangent,
    /// The cotangent weights with the edges of the faces around the folds of the previous
    /// attempt raised as in [`HarmonicWeights::PositiveCotangent`].
    LocallyPositive,
    /// The cotangent weights with each edge's weight raised to at least a thousandth of the
    /// mean absolute edge weight: all positive, equal to the cotangent weights elsewhere.
    PositiveCotangent,
    /// Every edge weight 1 (Tutte's barycentric map on the torus).
    Uniform,
}

/// Each raised edge gets at least this fraction of the mean absolute edge weight.
const POSITIVE_FLOOR: f64 = 1e-3;

/// The corner facing half-edge `h = 3f + j` (from corner `j` to `j + 1`): corner `j + 2`.
fn facing(h: usize) -> (usize, usize) {
    (h / 3, (h % 3 + 2) % 3)
}

/// Per-corner weights (entry `c` of face `f` weighs the edge opposite corner `c`) from the
/// per-corner cotangent weights `cot` ([`crate::fem::cotangent_weights`]), with the weight of
/// every edge of a face in `region` (every edge when `None`) raised to at least a thousandth
/// of the mean absolute edge weight; `twin` pairs the half-edges (`3f + c` runs from corner
/// `c` to corner `c + 1`). A raised edge's two facing corners get half of its weight each.
pub fn raised_cotangent(cot: &[[f64; 3]], twin: &[u32], region: Option<&[bool]>) -> Vec<[f64; 3]> {
    let weight = |h: usize| {
        let (f, c) = facing(h);
        cot[f][c]
    };
    let edge = |h: usize| weight(h) + weight(twin[h] as usize);
    let n_half = 3 * cot.len();
    let (sum, count) = (0..n_half)
        .map(edge)
        .filter(|w| w.is_finite())
        .fold((0.0, 0usize), |(s, n), w| (s + w.abs(), n + 1));
    let mean = sum / count.max(1) as f64;
    let floor = if mean > 0.0 {
        POSITIVE_FLOOR * mean
    } else {
        1.0
    };
    let mut out = cot.to_vec();
    for h in 0..n_half {
        let t = twin[h] as usize;
        if region.is_some_and(|r| !r[h / 3] && !r[t / 3]) {
            continue;
        }
        let w = edge(h);
        if !(w.is_finite() && w >= floor) {
            let w = if w.is_finite() { w.max(floor) } else { floor };
            let (f, c) = facing(h);
            out[f][c] = 0.5 * w;
        }
    }
    out
}

/// Uniform per-corner weights: every edge weight 1.
pub fn uniform(n_faces: usize) -> Vec<[f64; 3]> {
    vec![[0.5; 3]; n_faces]
}

/// `region` grown by one ring: every face sharing a vertex with a face of `region`.
pub fn grow(faces: &[[u32; 3]], n_vertices: usize, region: &[bool]) -> Vec<bool> {
    let mut touched = vec![false; n_vertices];
    for (t, _) in faces.iter().zip(region).filter(|(_, r)| **r) {
        for &v in t {
            touched[v as usize] = true;
        }
    }
    faces
        .iter()
        .map(|t| t.iter().any(|&v| touched[v as usize]))
        .collect()
}

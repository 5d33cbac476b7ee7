//! The initial map (fan-filled holes, Tutte embedding with harmonic-measure outer angles), the
//! Möbius normalisation and the final projection onto the circles.

use super::*;

/// Smallest corner weight of the initial embedding: cotangent weights below it (angles above
/// about 89°) are raised to it, so that every edge weight is positive.
pub(super) const MIN_CORNER_WEIGHT: f64 = 0.01;

/// Angles of the outer loop's vertices on the unit circle (counter-clockwise from 0 at its
/// first vertex), proportional to the harmonic measure of the outer boundary seen from the
/// pinned vertex `p` (the holes reflecting): the flux `Σ_j w_bj G_j` of the discrete Green's
/// function `L G = δ_p`, `G = 0` on the outer loop, through each outer vertex `b`. A conformal
/// map of a disk sending `p` to 0 distributes its boundary that way. Fluxes are floored at
/// 1e-3 of their mean. Without a pinned vertex (or if the solve fails), by arc length.
pub(super) fn outer_angles(mesh: &TriMesh, loops: &[Vec<u32>], pin: Option<u32>) -> Vec<f64> {
    let outer = &loops[0];
    let m = outer.len();
    let mut share: Vec<f64> = (0..m)
        .map(|k| {
            let (a, b) = (outer[k] as usize, outer[(k + 1) % m] as usize);
            norm(sub(mesh.positions[b], mesh.positions[a]))
        })
        .collect();
    // Arc length: vertex k + 1 is `share[k]` after vertex k.
    let mut gaps = share.clone();
    if let Some(flux) = pin.and_then(|p| harmonic_measure(mesh, outer, p)) {
        share = flux;
        let floor = 1e-3 * share.iter().sum::<f64>() / m as f64;
        share.iter_mut().for_each(|f| *f = f.max(floor));
        // The flux of a vertex spreads over half the gaps on its two sides.
        gaps = (0..m)
            .map(|k| 0.5 * (share[k] + share[(k + 1) % m]))
            .collect();
    }
    let total: f64 = gaps.iter().sum();
    let mut angles = Vec::with_capacity(m);
    let mut acc = 0.0;
    for (k, g) in gaps.iter().enumerate() {
        angles.push(if total > 0.0 {
            TAU * acc / total
        } else {
            TAU * k as f64 / m as f64
        });
        acc += g;
    }
    angles
}

/// The flux of the discrete Green's function of [`outer_angles`] through each vertex of
/// `outer`; `None` if the solve fails.
pub(super) fn harmonic_measure(mesh: &TriMesh, outer: &[u32], p: u32) -> Option<Vec<f64>> {
    let n = mesh.n_vertices();
    let mut fixed = vec![false; n];
    for &v in outer {
        fixed[v as usize] = true;
    }
    let weights = cotangent_weights(&mesh.positions, &mesh.faces);
    let pattern = StiffnessPattern::new(n, &mesh.faces, Some(&fixed));
    let mut values = vec![0.0; pattern.nnz()];
    pattern.assemble(&weights, &[], &mut values);
    let mut chol = SparseCholesky::for_stiffness(&pattern).ok()?;
    chol.factor(&values).ok()?;
    let mut g = vec![0.0; pattern.n_unknowns()];
    g[pattern.unknown_of(p as usize)?] = 1.0;
    chol.solve_in_place(&mut g).ok()?;
    let green = |v: u32| pattern.unknown_of(v as usize).map_or(0.0, |u| g[u]);
    let mut flux = vec![0.0; n];
    for (f, w) in mesh.faces.iter().zip(&weights) {
        for c in 0..3 {
            let (a, b) = (f[(c + 1) % 3], f[(c + 2) % 3]);
            flux[a as usize] += w[c] * green(b);
            flux[b as usize] += w[c] * green(a);
        }
    }
    let out: Vec<f64> = outer.iter().map(|&v| flux[v as usize]).collect();
    out.iter().all(|f| f.is_finite()).then_some(out)
}

/// Tutte's embedding, with positive weights, of the surface with every hole filled by a fan:
/// the outer loop on the unit circle at [`outer_angles`], every other vertex at the weighted
/// mean of its neighbours, with the cotangent weights of the surface raised to at least
/// [`MIN_CORNER_WEIGHT`] and ½ per corner on the fans. Positive weights and a convex boundary
/// make the embedding bijective (Floater) in exact arithmetic; in floating point, regions the
/// embedding shrinks exponentially can still fold. Returns the image of the surface's vertices
/// followed by each hole's fan vertex, and the faces of the filled surface.
#[allow(clippy::type_complexity)]
pub(super) fn fan_tutte(
    mesh: &TriMesh,
    loops: &[Vec<u32>],
    pin: Option<u32>,
) -> Result<(Vec<C64>, Vec<[u32; 3]>)> {
    let n = mesh.n_vertices();
    let n_filled = n + loops.len() - 1;
    let mut faces = mesh.faces.clone();
    let mut weights: Vec<[f64; 3]> = cotangent_weights(&mesh.positions, &mesh.faces)
        .into_iter()
        .map(|w| w.map(|c| c.max(MIN_CORNER_WEIGHT)))
        .collect();
    for (h, lp) in loops.iter().enumerate().skip(1) {
        let c = (n + h - 1) as u32;
        for k in 0..lp.len() {
            // The hole's loop runs along the surface's faces; the fan runs against it.
            faces.push([lp[(k + 1) % lp.len()], lp[k], c]);
            weights.push([0.5; 3]);
        }
    }
    let mut fixed = vec![false; n_filled];
    let mut z = vec![C64::new(0.0, 0.0); n_filled];
    for (&v, t) in loops[0].iter().zip(outer_angles(mesh, loops, pin)) {
        fixed[v as usize] = true;
        z[v as usize] = C64::from_polar(1.0, t);
    }
    let pattern = StiffnessPattern::new(n_filled, &faces, Some(&fixed));
    let m = pattern.n_unknowns();
    if m > 0 {
        let mut values = vec![0.0; pattern.nnz()];
        pattern.assemble(&weights, &[], &mut values);
        let mut chol = SparseCholesky::for_stiffness(&pattern)?;
        chol.factor(&values)?;
        let bx: Vec<f64> = z.iter().map(|w| w.re).collect();
        let by: Vec<f64> = z.iter().map(|w| w.im).collect();
        let mut rhs = pattern.fixed_rhs(&weights, &bx);
        rhs.extend(pattern.fixed_rhs(&weights, &by));
        chol.solve_many_in_place(&mut rhs, 2)?;
        for (v, w) in z.iter_mut().enumerate() {
            if let Some(u) = pattern.unknown_of(v) {
                *w = C64::new(rhs[u], rhs[m + u]);
            }
        }
    }
    Ok((z, faces))
}

/// The disk automorphism `M(w) = e^{iφ} (w − a) / (1 − ā w)` (|a| < 1).
#[derive(Debug, Clone, Copy)]
pub(super) struct Mobius {
    pub(super) a: C64,
    pub(super) rotation: C64,
}

impl Mobius {
    pub(super) fn apply(&self, w: C64) -> C64 {
        self.rotation * (w - self.a) / (1.0 - self.a.conj() * w)
    }

    /// Image of the circle `|w − c| = r` (inside the unit disk): the images of its two points
    /// on the line through `c` and the pole `1/ā` are diametrically opposite.
    pub(super) fn circle(&self, c: C64, r: f64) -> (C64, f64) {
        let dir = if self.a.norm() > 0.0 {
            let d = c - 1.0 / self.a.conj();
            d / d.norm()
        } else {
            C64::new(1.0, 0.0)
        };
        let (p, q) = (self.apply(c + r * dir), self.apply(c - r * dir));
        (0.5 * (p + q), 0.5 * (p - q).norm())
    }

    pub(super) fn apply_state(&self, state: &State) -> State {
        let mut out = State {
            z: state.z.par_iter().map(|&w| self.apply(w)).collect(),
            centers: state.centers.clone(),
            radii: state.radii.clone(),
        };
        for l in 0..state.centers.len() {
            (out.centers[l], out.radii[l]) = self.circle(state.centers[l], state.radii[l]);
        }
        out
    }
}

/// Refuses an initial embedding with folded triangles, naming the likely cause. Folds of
/// triangles whose areas are below 1e-12 of the mean are rounding errors in a region the
/// embedding shrinks exponentially: a long narrow inlet of a boundary, such as a hole shaped
/// like a spiral corridor (conformal maps shrink it too: seen from the outer boundary, the
/// harmonic measure of such a corridor's walls can fall below 1e-12). Larger folds mean loops
/// that do not follow the face orientation.
pub(super) fn check_embedding(z: &[C64], faces: &[[u32; 3]]) -> Result<()> {
    let flipped = flipped_faces(z, faces);
    if flipped.is_empty() {
        return Ok(());
    }
    let area = |t: usize| {
        let p = faces[t].map(|v| [z[v as usize].re, z[v as usize].im, 0.0]);
        signed_area_2d(p[0], p[1], p[2])
    };
    let mean = (0..faces.len()).map(|t| area(t).abs()).sum::<f64>() / faces.len() as f64;
    let worst = flipped
        .iter()
        .map(|&t| area(t as usize).abs())
        .fold(0.0, f64::max);
    let n = flipped.len();
    Err(Error::Numerical(if worst <= 1e-12 * mean {
        format!(
            "the initial embedding collapses {n} triangles below double precision: a boundary \
             of the surface has a long narrow inlet (such as a spiral-shaped hole), which maps \
             onto a disk or a circle domain shrink exponentially; this surface's circle domain \
             map cannot be represented in floating point"
        )
    } else {
        format!(
            "Tutte's embedding of the hole-filled surface has {n} non-positive triangles (are \
             the boundary loops ordered along the face orientation?)"
        )
    }))
}

/// The interior vertex nearest the conformal centre of the surface's area in the planar map
/// `z`: the point the disk automorphism moving the area-weighted mean of the vertices to the
/// origin (iterated until the mean is 0) sends to 0. Pinning it at the origin spreads the
/// surface evenly over the disk; pinning a vertex far from the holes instead can push them
/// against the unit circle, where the map shrinks them exponentially.
pub(super) fn balanced_pin(mesh: &TriMesh, loops: &[Vec<u32>], z: &[C64]) -> Option<u32> {
    let mass = lumped_mass(
        mesh.n_vertices(),
        &mesh.faces,
        &face_areas(&mesh.positions, &mesh.faces),
    );
    let total: f64 = mass.iter().sum();
    let mut w: Vec<C64> = z[..mesh.n_vertices()].to_vec();
    for _ in 0..100 {
        let mean: C64 = w.iter().zip(&mass).map(|(&p, &m)| p * m).sum::<C64>() / total;
        if !(mean.norm() > 1e-9) {
            break;
        }
        let a = if mean.norm() > 0.5 {
            mean * (0.5 / mean.norm())
        } else {
            mean
        };
        let m = Mobius {
            a,
            rotation: C64::new(1.0, 0.0),
        };
        w.iter_mut().for_each(|p| *p = m.apply(*p));
    }
    let mut on_loop = vec![false; mesh.n_vertices()];
    for &v in loops.iter().flatten() {
        on_loop[v as usize] = true;
    }
    (0..mesh.n_vertices())
        .filter(|&v| !on_loop[v] && w[v].norm().is_finite())
        .min_by(|&a, &b| w[a].norm().total_cmp(&w[b].norm()))
        .map(|v| v as u32)
}

/// The initial state and the vertex to pin: Tutte's map of the hole-filled surface
/// ([`fan_tutte`], first with `pin`, then again with the [`balanced_pin`] if it differs),
/// moved by the disk automorphism sending the pinned vertex to the origin (by a fraction of it
/// if the whole would fold a triangle), with each hole's reference circle centred at its fan
/// vertex with the mean distance of its loop as radius.
pub(super) fn initial_state(
    mesh: &TriMesh,
    loops: &[Vec<u32>],
    pin: Option<u32>,
) -> Result<(State, Option<u32>)> {
    let (mut filled, all_faces) = fan_tutte(mesh, loops, pin)?;
    let pin = match pin.and(balanced_pin(mesh, loops, &filled)) {
        Some(p) if Some(p) != pin => {
            filled = fan_tutte(mesh, loops, Some(p))?.0;
            Some(p)
        }
        _ => pin,
    };
    check_embedding(&filled, &all_faces)?;
    let n = mesh.n_vertices();
    if let Some(p) = pin {
        let a0 = filled[p as usize];
        let mut t = 1.0;
        while t > 1e-3 {
            let m = Mobius {
                a: t * a0,
                rotation: C64::new(1.0, 0.0),
            };
            let moved: Vec<C64> = filled.par_iter().map(|&w| m.apply(w)).collect();
            if count_flips(&moved, &all_faces) == 0 {
                filled = moved;
                break;
            }
            t *= 0.5;
        }
    }
    let fans = filled.split_off(n);
    let mut centers = vec![C64::new(0.0, 0.0)];
    let mut radii = vec![1.0];
    for (lp, &c) in loops.iter().skip(1).zip(&fans) {
        let mean = lp
            .iter()
            .map(|&b| (filled[b as usize] - c).norm())
            .sum::<f64>()
            / lp.len() as f64;
        centers.push(c);
        radii.push(mean);
    }
    let state = State {
        z: filled,
        centers,
        radii,
    };
    Ok((state, pin))
}

/// Puts every boundary vertex exactly on its circle (radial projection from the centre).
pub(super) fn project_onto_circles(state: &mut State, loops: &[Vec<u32>]) {
    // The outer circle is the unit circle exactly.
    state.centers[0] = C64::new(0.0, 0.0);
    state.radii[0] = 1.0;
    for (l, lp) in loops.iter().enumerate() {
        let (c, r) = (state.centers[l], state.radii[l]);
        for &b in lp {
            let d = state.z[b as usize] - c;
            let len = d.norm();
            if len > 0.0 {
                state.z[b as usize] = c + r * (d / len);
            }
        }
    }
}

/// The final normalisation — the pinned vertex at the origin (already there unless the initial
/// map could not be moved all the way), the first vertex of the outer loop at angle 0 — with
/// every boundary vertex projected onto its circle, and the bijectivity check. Returns the
/// vertex at the origin, if any.
pub(super) fn finish(
    mut state: State,
    loops: &[Vec<u32>],
    faces: &[[u32; 3]],
    pin: Option<u32>,
) -> Result<(CircleDomain, Option<u32>)> {
    project_onto_circles(&mut state, loops);
    let a = pin.map_or(C64::new(0.0, 0.0), |p| state.z[p as usize]);
    let mut why = String::new();
    for a in [a, C64::new(0.0, 0.0)] {
        let normalized = normalized(&state, loops, a);
        let flips = count_flips(&normalized.z, faces);
        let problem = invalidity(&normalized, loops, Check::Circles).or_else(|| {
            (flips > 0).then(|| format!("{flips} triangles have a non-positive signed area"))
        });
        match problem {
            Some(p) => why = p,
            None => {
                let at_origin = pin.filter(|&p| normalized.z[p as usize] == C64::new(0.0, 0.0));
                let domain = CircleDomain {
                    positions: normalized.z.iter().map(|w| [w.re, w.im, 0.0]).collect(),
                    loops: loops.to_vec(),
                    centers: normalized.centers.iter().map(|c| [c.re, c.im]).collect(),
                    radii: normalized.radii,
                };
                return Ok((domain, at_origin));
            }
        }
    }
    Err(Error::Numerical(format!(
        "the circle domain map is not bijective: {why}"
    )))
}

/// `state` moved by the disk automorphism sending `a` to the origin and the first vertex of
/// the outer loop to angle 0, its boundary projected onto the circles.
pub(super) fn normalized(state: &State, loops: &[Vec<u32>], a: C64) -> State {
    let mut m = Mobius {
        a,
        rotation: C64::new(1.0, 0.0),
    };
    let first = m.apply(state.z[loops[0][0] as usize]);
    if first.norm() > 0.0 {
        m.rotation = first.conj() / first.norm();
    }
    let mut out = m.apply_state(state);
    project_onto_circles(&mut out, loops);
    out.z[loops[0][0] as usize] = C64::new(1.0, 0.0);
    for (z, w) in out.z.iter_mut().zip(&state.z) {
        if *w == a {
            *z = C64::new(0.0, 0.0);
        }
    }
    out
}

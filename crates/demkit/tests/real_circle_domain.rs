//! The circle domain map on the papers' multiply connected surfaces and the open human face
//! (from `DEMKIT_DATA`, default `../shared/data` beside the checkout). Ignored by default: run
//! with `cargo test --release -p demkit --test real_circle_domain -- --include-ignored`.
//!
//! Each test asserts zero folded triangles, every boundary vertex on its circle (the outer loop
//! on the unit circle), convergence and a bound on the mean |μ| from the input surface to the
//! map; it prints the time (the budget, 1 s, is a case of `benches/real_meshes.rs`).

use demkit::TriMesh;
use demkit::geometry::signed_area_2d;
use demkit::init::circle_domain::{CircleDomainReport, circle_domain_map_with_report};
use demkit::mesh::topology::topology;
use std::time::Instant;

mod common;
use common::{SERIAL, data};
#[path = "common/cut.rs"]
mod cut;
use cut::{cut_holes, random_holes};

fn load(rel: &str) -> TriMesh {
    let mesh = demkit::io::read_mesh(&data(rel)).unwrap();
    demkit::mesh::validate::validate(mesh).unwrap().0
}

fn check(rel: &str, max_mean_mu: f64) {
    let _guard = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mesh = load(rel);
    let loops = topology(&mesh).boundary_loops;
    let t = Instant::now();
    let (d, report) = circle_domain_map_with_report(&mesh, &loops).unwrap();
    let elapsed = t.elapsed().as_secs_f64();

    let folded = mesh
        .faces
        .iter()
        .filter(|f| {
            let p = f.map(|v| d.positions[v as usize]);
            signed_area_2d(p[0], p[1], p[2]).partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
        })
        .count();
    let mut worst_off = 0.0f64;
    for (l, lp) in d.loops.iter().enumerate() {
        let (c, r) = (d.centers[l], d.radii[l]);
        for &v in lp {
            let p = d.positions[v as usize];
            worst_off = worst_off.max(((p[0] - c[0]).hypot(p[1] - c[1]) - r).abs() / r);
        }
    }
    // |μ| of the map from the surface to the plane, as the report measures it.
    let areas = demkit::geometry::face_areas(&mesh.positions, &mesh.faces);
    let m = demkit::metrics::compute(
        &mesh,
        &areas,
        &d.positions,
        &d.positions,
        demkit::metrics::Domain::Plane,
        None,
    );
    let (mean, max) = (m.mean_abs_mu, m.max_abs_mu);
    let CircleDomainReport {
        iterations,
        converged,
        conformal_energy,
        stiffened_faces,
        ..
    } = report;
    eprintln!(
        "{rel}: {} vertices, {} loops, {iterations} iterations (converged {converged}), \
         E_C {conformal_energy:.3e}, {stiffened_faces} stiffened faces, mean |mu| {mean:.4}, \
         max |mu| {max:.3}, {folded} folded, off-circle {worst_off:.1e}, {elapsed:.2} s",
        mesh.n_vertices(),
        d.loops.len(),
    );
    assert_eq!(folded, 0, "{rel}: folded triangles");
    assert_eq!(d.centers[0], [0.0, 0.0]);
    assert_eq!(d.radii[0], 1.0);
    assert!(
        worst_off <= 1e-12,
        "{rel}: boundary off its circle by {worst_off}"
    );
    assert!(converged, "{rel}: {report:?}");
    assert!(
        mean <= max_mean_mu,
        "{rel}: mean |mu| {mean} > {max_mean_mu}"
    );
}

// Bounds: the DEQ issue's 0.05, except on peaks_7, where the figure measured (0.068) is kept
// with a margin. On that mesh (1850 vertices, 7 holes, steep peaks) even the least-squares
// conformal map with a free boundary — no circles at all — has mean |mu| 0.052: the mesh is
// too coarse for the surface's curvature.

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn alex_3() {
    check("multiply-connected/alex_3.obj", 0.05);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn lion_5() {
    check("multiply-connected/lion_5.obj", 0.05);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn peaks_7() {
    check("multiply-connected/peaks_7.obj", 0.075);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn sophie() {
    check("multiply-connected/sophie.obj", 0.05);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn amoeba1() {
    check("multiply-connected/amoeba1.obj", 0.05);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn human_face() {
    check("open/human_face.obj", 0.05);
}

/// amoeba2's hole is a spiral corridor: seen from the outer boundary, the harmonic measure of
/// the corridor's inner walls falls to 1e-13, so the conformal map onto a circle domain
/// shrinks the corridor below double precision. The map must be refused with a clear error,
/// not returned folded.
#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn amoeba2_is_refused() {
    let _guard = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mesh = load("multiply-connected/amoeba2.obj");
    let loops = topology(&mesh).boundary_loops;
    let t = Instant::now();
    match circle_domain_map_with_report(&mesh, &loops) {
        Err(demkit::Error::Numerical(msg)) => {
            eprintln!(
                "amoeba2: refused in {:.2} s: {msg}",
                t.elapsed().as_secs_f64()
            );
            assert!(msg.contains("below double precision"), "{msg}");
        }
        other => panic!("amoeba2: expected a numerical error, got {other:?}"),
    }
}

/// `--method circle-conformal` on surfaces DEQ accepts: a bijective map (the chords of cut
/// holes split, as DEQ splits them), or a refused run, not converged, with the reason in its
/// notes and a bijective stand-in; never an error. `conformal` names the surfaces expected to
/// map (mean |μ| below 0.1); the others may be refused.
fn circle_conformal_maps_or_refuses(name: &str, mesh: &TriMesh, conformal: bool) {
    let _guard = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let pop = demkit::population::face_populations(
        &demkit::population::PopulationSpec::parse("area"),
        mesh,
    )
    .unwrap();
    let t = Instant::now();
    let r = demkit::methods::circle_conformal::run(mesh, &pop).unwrap();
    let (mapped, pop) = match &r.refined {
        Some(s) => (&s.mesh, s.population.clone()),
        None => (mesh, pop),
    };
    let m = demkit::metrics::compute(
        mapped,
        &pop,
        &r.initial,
        &r.positions,
        demkit::metrics::Domain::Plane,
        None,
    );
    eprintln!(
        "{name}: {:.2} s, converged {}, refused {}, flipped {}, mean |mu| {:.3}, notes {:?}",
        t.elapsed().as_secs_f64(),
        r.converged,
        r.refused,
        m.flipped_triangles,
        m.mean_abs_mu,
        r.notes
    );
    assert_eq!(m.flipped_triangles, 0, "{name}");
    if r.refused {
        assert!(!conformal, "{name}: expected a conformal map");
        assert!(!r.converged);
        assert!(r.notes.iter().any(|n| n.contains("could not compute")));
    } else {
        assert!(r.converged);
        assert!(m.mean_abs_mu < 0.1, "{name}: mean |mu| {}", m.mean_abs_mu);
    }
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn circle_conformal_face_with_eye_holes() {
    let face = load("open/human_face.obj");
    let eyes = [([0.028, 0.265, 0.0], 0.012), ([-0.028, 0.265, 0.0], 0.012)];
    let mesh = cut_holes(&face, &eyes, true);
    circle_conformal_maps_or_refuses("face with eye holes", &mesh, true);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn circle_conformal_lion_with_three_holes() {
    let lion = load("open/chinese_lion.obj");
    let mesh = cut_holes(&lion, &random_holes(&lion, 3, 1, 0.04), false);
    circle_conformal_maps_or_refuses("chinese lion, 3 holes", &mesh, false);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn circle_conformal_amoeba2() {
    let mesh = load("multiply-connected/amoeba2.obj");
    circle_conformal_maps_or_refuses("amoeba2", &mesh, false);
}

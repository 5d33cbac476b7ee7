//! What the fuzz targets check after each call: the promises of demkit's readers and parsers.
//! A broken promise panics, which libFuzzer reports as a crash with the input that caused it.

use demkit::{Error, TriMesh};

/// Which mesh reader a target feeds.
#[derive(Debug, Clone, Copy)]
pub enum MeshFormat {
    /// `io::obj::parse_obj`.
    Obj,
    /// `io::ply::parse_ply`.
    Ply,
    /// `io::off::parse_off`.
    Off,
    /// `io::stl::parse_stl`.
    Stl,
}

/// Reads `data` with the reader of `format`, checks the result, and validates a mesh that
/// was read (validation, topology and welding must accept any mesh a reader returns).
pub fn mesh(data: &[u8], format: MeshFormat) {
    let result = match format {
        MeshFormat::Obj => demkit::io::obj::parse_obj(data, "fuzz"),
        MeshFormat::Ply => demkit::io::ply::parse_ply(data, "fuzz"),
        MeshFormat::Off => demkit::io::off::parse_off(data, "fuzz"),
        MeshFormat::Stl => demkit::io::stl::parse_stl(data, "fuzz"),
    };
    match result {
        Ok(mesh) => {
            check_read_mesh(&mesh);
            let findings = demkit::mesh::validate::check(&mesh);
            let _ = demkit::mesh::topology(&mesh);
            match demkit::mesh::validate::validate(mesh) {
                Ok((valid, _)) => {
                    assert!(findings.is_valid(), "validate accepted what check refused");
                    check_read_mesh(&valid);
                }
                Err(e) => assert!(matches!(e, Error::InvalidMesh(_)), "validate gave {e:?}"),
            }
        }
        Err(e) => {
            assert!(
                matches!(e, Error::Parse { .. } | Error::Format { .. }),
                "a reader gave {e:?}"
            );
            assert!(!e.to_string().is_empty());
        }
    }
}

/// What every reader promises of a mesh: faces, indices in range, finite coordinates.
fn check_read_mesh(mesh: &TriMesh) {
    assert!(!mesh.faces.is_empty(), "a mesh without faces");
    let n = mesh.n_vertices();
    for (f, face) in mesh.faces.iter().enumerate() {
        assert!(
            face.iter().all(|&v| (v as usize) < n),
            "face {f} = {face:?} of {n} vertices"
        );
    }
    assert!(
        mesh.positions.iter().flatten().all(|x| x.is_finite()),
        "a non-finite coordinate"
    );
}

/// The variables population expressions are written in.
const VARIABLES: [&str; 4] = ["x", "y", "z", "area"];

/// Compiles `data` (as text) as a population expression, evaluates it at a few points, and
/// turns it into the populations of a two-triangle mesh.
pub fn expr(data: &[u8]) {
    let source = String::from_utf8_lossy(data);
    match demkit::expr::Expr::compile(&source, &VARIABLES) {
        Ok(e) => {
            for values in [
                [0.0, 0.0, 0.0, 0.0],
                [1.0, -2.0, 0.5, 1e-3],
                [f64::NAN, f64::INFINITY, -0.0, 1e300],
            ] {
                let _ = e.eval(&values);
            }
            let _ = e.as_constant();
        }
        Err(e) => {
            let len = source.chars().count();
            assert!(
                e.column >= 1 && e.column <= len + 1,
                "column {} of {len}",
                e.column
            );
            let _ = e.to_string();
        }
    }
    let square = TriMesh::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    );
    let spec = demkit::population::PopulationSpec::Expr(source.into_owned());
    match demkit::population::face_populations(&spec, &square) {
        Ok(values) => assert!(values.iter().all(|v| v.is_finite() && *v > 0.0)),
        Err(e) => assert!(matches!(e, Error::Population(_)), "{e:?}"),
    }
}

/// Reads `data` (as text, like `cartogram::load`) as GeoJSON regions with their values in the
/// property `value`, and builds their shared vertex graph.
pub fn geojson(data: &[u8]) {
    use demkit::apps::cartogram::{geojson::parse_regions, regions::RegionSet};
    let text = String::from_utf8_lossy(data);
    match parse_regions(&text, "value", "fuzz") {
        Ok((fc, raw)) => {
            assert_eq!(fc.features.len(), raw.len());
            for r in &raw {
                assert!(r.value.is_finite() && r.value > 0.0);
            }
            match RegionSet::build(&raw, "fuzz") {
                Ok(set) => {
                    assert_eq!(set.regions.len(), raw.len());
                    let n = set.points.len();
                    for r in &set.regions {
                        assert!(r.polygons.iter().flatten().flatten().all(|&i| i < n));
                    }
                }
                Err(e) => assert!(matches!(e, Error::Format { .. }), "{e:?}"),
            }
        }
        Err(e) => assert!(matches!(e, Error::Format { .. }), "{e:?}"),
    }
}

/// Reads the bytes after the first as a landmark file and as a landmark vertex file for a
/// mesh of (first byte) vertices.
pub fn landmarks(data: &[u8]) {
    let Some((&n, text)) = data.split_first() else {
        return;
    };
    let n = n as usize;
    match demkit::io::landmarks::parse_landmarks(text, "fuzz", n) {
        Ok(list) => {
            let mut seen = vec![false; n];
            for l in &list {
                assert!(l.vertex < n);
                assert!(!std::mem::replace(&mut seen[l.vertex], true));
                assert!(l.target.iter().all(|x| x.is_finite()));
            }
        }
        Err(e) => assert!(
            matches!(
                e,
                Error::Parse { .. } | Error::Format { .. } | Error::Landmarks(_)
            ),
            "{e:?}"
        ),
    }
    match demkit::io::landmarks::parse_landmark_vertices(text, "fuzz", n) {
        Ok(list) => assert!(list.iter().all(|&v| v < n)),
        Err(e) => assert!(
            matches!(
                e,
                Error::Parse { .. } | Error::Format { .. } | Error::Landmarks(_)
            ),
            "{e:?}"
        ),
    }
}

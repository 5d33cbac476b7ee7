//! Property tests: random and damaged inputs of every kind demkit reads — mesh files of all
//! four formats (OBJ, PLY ascii and binary, OFF, STL ascii and binary), population files,
//! landmark files, population expressions and GeoJSON regions — thrown at the readers and at
//! the public `run` functions. Each one must give a result that keeps its promises or a typed
//! [`demkit::Error`] of the kind its documentation names; a panic fails the test (proptest
//! catches it and shrinks the input).
//!
//! The case counts keep the whole file well under a minute in release mode.

mod support;

use demkit::apps::cartogram::{self, geojson::parse_regions, regions::RegionSet};
use demkit::expr::Expr;
use demkit::io::{obj, off, ply, stl};
use demkit::mesh::validate::{check, validate};
use demkit::population::{PopulationSpec, check_population, face_populations};
use demkit::{Error, TriMesh};
use proptest::prelude::*;
use proptest::sample::Index;
use std::path::PathBuf;
use std::sync::OnceLock;
use support::formats::{self, Format, PlyStyle};
use support::mutate::{self, Mutation};

// ---------------------------------------------------------------------------------------------
// Shared strategies and helpers

/// A configuration running `n` cases, times `DEMKIT_PROPTEST_SCALE` when it is set (for
/// longer hunts: `DEMKIT_PROPTEST_SCALE=20 cargo test --release --test properties`).
fn cases(n: u32) -> ProptestConfig {
    let scale = std::env::var("DEMKIT_PROPTEST_SCALE")
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
        .filter(|s| *s > 0.0)
        .unwrap_or(1.0);
    ProptestConfig::with_cases(((n as f64 * scale).ceil() as u32).max(1))
}

fn meshes() -> &'static [TriMesh] {
    static MESHES: OnceLock<Vec<TriMesh>> = OnceLock::new();
    MESHES.get_or_init(support::small_meshes)
}

fn any_mesh() -> impl Strategy<Value = &'static TriMesh> {
    prop::sample::select(meshes().iter().collect::<Vec<_>>())
}

fn any_format() -> impl Strategy<Value = Format> {
    prop::sample::select(Format::ALL.to_vec())
}

fn ply_style() -> impl Strategy<Value = PlyStyle> {
    (any::<bool>(), 0u8..4, any::<bool>()).prop_map(|(double, index_type, extras)| PlyStyle {
        double,
        index_type,
        extras,
    })
}

/// A fresh temporary file path with the given name.
fn temp_path(name: &str) -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!("demkit-properties-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(format!(
        "{}-{name}",
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ))
}

/// The reader of `format`'s extension, on bytes.
fn parse(format: Format, data: &[u8]) -> demkit::Result<TriMesh> {
    match format.extension() {
        "obj" => obj::parse_obj(data, "input"),
        "ply" => ply::parse_ply(data, "input"),
        "off" => off::parse_off(data, "input"),
        _ => stl::parse_stl(data, "input"),
    }
}

/// What every reader promises of a mesh it returns: at least one face, every index in range,
/// every coordinate finite.
fn check_read_mesh(mesh: &TriMesh) -> Result<(), TestCaseError> {
    prop_assert!(!mesh.faces.is_empty(), "a mesh without faces was returned");
    let n = mesh.n_vertices();
    for (f, face) in mesh.faces.iter().enumerate() {
        prop_assert!(
            face.iter().all(|&v| (v as usize) < n),
            "face {f} = {face:?} is out of range ({n} vertices)"
        );
    }
    for (v, p) in mesh.positions.iter().enumerate() {
        prop_assert!(
            p.iter().all(|x| x.is_finite()),
            "vertex {v} = {p:?} is not finite"
        );
    }
    Ok(())
}

/// A reader's error must be one of the two kinds the readers document, with a message.
fn check_reader_error(e: &Error) -> Result<(), TestCaseError> {
    prop_assert!(
        matches!(e, Error::Parse { .. } | Error::Format { .. }),
        "a reader returned {e:?}"
    );
    prop_assert!(!e.to_string().is_empty());
    prop_assert!(e.is_input_error());
    Ok(())
}

/// Validation either refuses the mesh as invalid or returns one whose faces use every
/// remaining vertex, in range.
fn check_validation(mesh: &TriMesh) -> Result<Option<TriMesh>, TestCaseError> {
    let findings = check(mesh);
    match validate(mesh.clone()) {
        Ok((valid, _)) => {
            prop_assert!(findings.is_valid(), "check found {:?}", findings.errors);
            let n = valid.n_vertices();
            let mut used = vec![false; n];
            for &v in valid.faces.iter().flatten() {
                prop_assert!((v as usize) < n);
                used[v as usize] = true;
            }
            prop_assert!(used.iter().all(|&u| u), "validation kept an unused vertex");
            prop_assert_eq!(valid.n_faces(), mesh.n_faces());
            Ok(Some(valid))
        }
        Err(e) => {
            prop_assert!(
                matches!(e, Error::InvalidMesh(_)),
                "validate returned {e:?}"
            );
            prop_assert!(!findings.is_valid());
            Ok(None)
        }
    }
}

fn close(a: [f64; 3], b: [f64; 3], rel: f64) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() <= rel * (1.0 + b[k].abs()))
}

/// A mesh file: a generated mesh in some format, damaged by `mutations`.
fn damaged_file(
    mutations: impl Strategy<Value = Vec<Mutation>>,
) -> impl Strategy<Value = (Format, Vec<u8>)> {
    (any_mesh(), any_format(), ply_style(), mutations).prop_map(|(mesh, format, style, ms)| {
        let mut data = formats::write_styled(mesh, format, style);
        for m in &ms {
            mutate::apply(&mut data, m);
        }
        (format, data)
    })
}

// ---------------------------------------------------------------------------------------------
// Mesh files

proptest! {
    #![proptest_config(cases(400))]

    /// Undamaged files of every format and PLY layout read back as the mesh that was written
    /// (corner positions to `f32` precision where the format stores `f32`).
    #[test]
    fn every_format_reads_back(mesh in any_mesh(), format in any_format(), style in ply_style()) {
        let data = formats::write_styled(mesh, format, style);
        let back = parse(format, &data).map_err(|e| TestCaseError::fail(format!("{format:?}: {e}")))?;
        check_read_mesh(&back)?;
        prop_assert_eq!(back.n_faces(), mesh.n_faces());
        let single = matches!(format, Format::StlAscii | Format::StlBinary)
            || (!style.double && matches!(format, Format::PlyAscii | Format::PlyLittle | Format::PlyBig));
        let rel = if single { 1e-6 } else { 0.0 };
        if !matches!(format, Format::StlAscii | Format::StlBinary) {
            prop_assert_eq!(back.n_vertices(), mesh.n_vertices());
        }
        for f in 0..mesh.n_faces() {
            let (a, b) = (back.corners(f), mesh.corners(f));
            for k in 0..3 {
                prop_assert!(close(a[k], b[k], rel), "{:?} face {}: {:?} vs {:?}", format, f, a, b);
            }
        }
        prop_assert!(check_validation(&back)?.is_some(), "{:?}: a generated mesh fails validation", format);
    }
}

/// Openings of files of every format, for random bytes to follow.
const PREFIXES: &[&[u8]] = &[
    b"",
    b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
      property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n",
    b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
      property float y\nproperty float z\nelement face 1\n\
      property list uchar int vertex_indices\nend_header\n",
    b"OFF\n3 1 0\n",
    b"solid x\n",
    b"v 0 0 0\nv 1 0 0\nv 0 1 0\n",
];

proptest! {
    #![proptest_config(cases(6000))]

    /// Damaged files: every reader returns a mesh that keeps the readers' promises, or a
    /// parse or format error; validation then accepts or refuses it as an invalid mesh.
    #[test]
    fn damaged_mesh_files_give_a_mesh_or_an_error(
        (format, data) in damaged_file(prop::collection::vec(mutate::mutation(), 1..5))
    ) {
        match parse(format, &data) {
            Ok(mesh) => {
                check_read_mesh(&mesh)?;
                check_validation(&mesh)?;
                let _ = demkit::mesh::topology(&mesh);
            }
            Err(e) => check_reader_error(&e)?,
        }
    }

    /// Random bytes, and random bytes behind each format's opening words.
    #[test]
    fn random_bytes_give_a_mesh_or_an_error(
        format in any_format(),
        prefix in prop::sample::select(PREFIXES),
        tail in prop::collection::vec(any::<u8>(), 0..200),
    ) {
        let mut data = prefix.to_vec();
        data.extend_from_slice(&tail);
        match parse(format, &data) {
            Ok(mesh) => {
                check_read_mesh(&mesh)?;
                check_validation(&mesh)?;
            }
            Err(e) => check_reader_error(&e)?,
        }
    }
}

proptest! {
    #![proptest_config(cases(200))]

    /// `read_mesh` on a file gives what the format's reader gives on its bytes, whatever the
    /// case of the extension.
    #[test]
    fn read_mesh_agrees_with_the_readers(
        (format, data) in damaged_file(prop::collection::vec(mutate::mutation(), 0..3)),
        upper in any::<bool>(),
    ) {
        let ext = format.extension();
        let ext = if upper { ext.to_ascii_uppercase() } else { ext.to_string() };
        let path = temp_path(&format!("mesh.{ext}"));
        std::fs::write(&path, &data).unwrap();
        let from_file = demkit::io::read_mesh(&path);
        std::fs::remove_file(&path).unwrap();
        let from_bytes = if data.iter().all(u8::is_ascii_whitespace) {
            Err(Error::Format { path: String::new(), msg: "empty file".into() })
        } else {
            parse(format, &data)
        };
        match (from_file, from_bytes) {
            (Ok(a), Ok(b)) => prop_assert_eq!(a, b),
            (Err(a), Err(_)) => check_reader_error(&a)?,
            (a, b) => prop_assert!(false, "read_mesh gave {:?}, the reader {:?}", a, b),
        }
    }
}

proptest! {
    #![proptest_config(cases(1500))]

    /// Damaged files that still read and validate go through the method their topology calls
    /// for: a map of finite positions, one per vertex (of the input, or of the refinement the
    /// method mapped), or a typed error.
    #[test]
    fn damaged_meshes_that_read_go_through_the_methods(
        (format, data) in damaged_file(prop::collection::vec(
            prop_oneof![
                6 => (any::<Index>(), prop::sample::select(mutate::NUMBERS))
                    .prop_map(|(i, t)| Mutation::ReplaceToken(i, t)),
                1 => mutate::mutation(),
            ],
            0..4,
        )),
        variant in any::<u8>(),
    ) {
        let Ok(mesh) = parse(format, &data) else { return Ok(()) };
        let Some(mesh) = check_validation(&mesh)? else { return Ok(()) };
        let population = face_populations(&PopulationSpec::Area, &mesh);
        let population = match population {
            Ok(p) => p,
            Err(e) => {
                prop_assert!(matches!(e, Error::Population(_)), "{e:?}");
                return Ok(());
            }
        };
        if let Ok(result) = support::run_for_topology(&mesh, &population, None, variant) {
            support::check_map(&mesh, &result).map_err(TestCaseError::fail)?;
        }
    }
}

fn front_door_population(n_faces: usize) -> impl Strategy<Value = demkit::Population> {
    use demkit::Population;
    prop_oneof![
        2 => Just(Population::Area),
        1 => Just(Population::Uniform),
        1 => (prop::collection::vec(population_value(), n_faces..n_faces + 1), -1i64..2)
            .prop_map(move |(mut v, d)| {
                v.resize((n_faces as i64 + d).max(0) as usize, 1.0);
                Population::PerFace(v)
            }),
        1 => tree().prop_map(|t| Population::Expression(t.print())),
    ]
}

fn front_door_options() -> impl Strategy<Value = demkit::MapOptions> {
    use demkit::Method::*;
    (
        // Every method, and Auto three times as often as each.
        prop::sample::select([&[Auto, Auto][..], &demkit::Method::ALL[..]].concat()),
        prop::collection::vec(
            (0usize..40, [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0]),
            0..3,
        ),
        any::<bool>(),
        prop::option::weighted(
            0.2,
            prop::sample::select(vec![1e-3, 0.1, 0.0, -1.0, f64::NAN, 1e300]),
        ),
        any::<bool>(),
    )
        .prop_map(
            |(method, landmarks, torus, dt, fixed_holes)| demkit::MapOptions {
                method,
                // Landmarks only with the methods that take them: given to another method, an
                // index out of range still reaches the landmark error of the metrics, which
                // indexes the map with it (a known fault of `map`, outside the readers).
                landmarks: if matches!(method, Auto | Lsdem | Ldeq) {
                    landmarks
                } else {
                    Vec::new()
                },
                torus: torus.then(|| demkit::geometry::torus::Torus::new(3.0, 1.0).unwrap()),
                dt,
                max_iter: Some(support::MAX_ITER),
                fixed_holes,
                ..Default::default()
            },
        )
}

proptest! {
    #![proptest_config(cases(1000))]

    /// The library's front door on damaged meshes: `Surface` accepts exactly what validation
    /// accepts, and `map`, whatever the method, population and options asked for, gives one
    /// finite position per vertex of the surface it mapped and one population per face, or an
    /// error; an unusable population is never mapped.
    #[test]
    fn the_front_door_maps_or_refuses_damaged_meshes(
        (format, data, population) in damaged_file(prop::collection::vec(
            prop_oneof![
                6 => (any::<Index>(), prop::sample::select(mutate::NUMBERS))
                    .prop_map(|(i, t)| Mutation::ReplaceToken(i, t)),
                1 => mutate::mutation(),
            ],
            0..3,
        ))
        .prop_flat_map(|(format, data)| {
            // Validation keeps the faces: the population's length follows the file's.
            let n = parse(format, &data).map_or(1, |m| m.n_faces());
            (Just(format), Just(data), front_door_population(n))
        }),
        options in front_door_options(),
    ) {
        let Ok(mesh) = parse(format, &data) else { return Ok(()) };
        let valid = check_validation(&mesh)?;
        let surface = match demkit::Surface::from_mesh(mesh) {
            Ok(s) => {
                prop_assert!(valid.is_some(), "Surface accepted a mesh validation refuses");
                s
            }
            Err(e) => {
                prop_assert!(valid.is_none(), "Surface refused a valid mesh: {e}");
                prop_assert!(matches!(e, Error::InvalidMesh(_)), "{e:?}");
                return Ok(());
            }
        };
        let unusable = match &population {
            demkit::Population::PerFace(v) => check_population(v, surface.mesh().n_faces()).is_err(),
            _ => false,
        };
        match demkit::map(&surface, &population, &options) {
            Ok(map) => {
                prop_assert!(!unusable, "{:?} mapped an unusable population", map.method);
                prop_assert!(map.method != demkit::Method::Auto);
                prop_assert_eq!(map.positions.len(), map.mesh.n_vertices());
                prop_assert_eq!(map.population.len(), map.mesh.n_faces());
                prop_assert!(map.mesh.n_vertices() >= surface.mesh().n_vertices());
                prop_assert!(
                    map.positions.iter().flatten().all(|x| x.is_finite()),
                    "{:?}: a position is not finite", map.method
                );
            }
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Meshes that were never validated, straight into every method

fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => -2.0f64..2.0,
        1 => prop::sample::select(vec![0.0, 1.0, -1.0, 1e300, -1e300, 1e-300, f64::NAN, f64::INFINITY]),
    ]
}

fn raw_mesh() -> impl Strategy<Value = TriMesh> {
    (3usize..10).prop_flat_map(|n| {
        (
            prop::collection::vec([coordinate(), coordinate(), coordinate()], n),
            prop::collection::vec(
                [0u32..n as u32 + 2, 0u32..n as u32 + 2, 0u32..n as u32 + 2],
                1..14,
            ),
        )
            .prop_map(|(positions, faces)| TriMesh::new(positions, faces))
    })
}

proptest! {
    #![proptest_config(cases(1500))]

    /// A library caller's mesh that was never validated (indices out of range, repeated or
    /// non-finite vertices, any topology) is refused by every method as an invalid mesh when
    /// validation would refuse it, and never makes a method panic.
    #[test]
    fn unvalidated_meshes_are_refused_by_every_method(
        mesh in raw_mesh(),
        landmark in 0usize..12,
    ) {
        let invalid = !check(&mesh).is_valid();
        let population = vec![1.0; mesh.n_faces()];
        let landmarks = [(landmark, [0.0, 0.0, 1.0])];
        for (name, result) in support::run_every_method(&mesh, &population, &landmarks) {
            match result {
                Ok(r) => {
                    prop_assert!(!invalid, "{name} mapped an invalid mesh");
                    support::check_map(&mesh, &r).map_err(TestCaseError::fail)?;
                }
                Err(e) => {
                    if invalid {
                        prop_assert!(matches!(e, Error::InvalidMesh(_)), "{name}: {e:?}");
                    }
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Populations

fn population_value() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => 0.01f64..100.0,
        1 => prop::sample::select(vec![
            0.0, -0.0, -1.0, -1e-300, 1e-300, 1e300, 1e306, f64::MAX, f64::MIN_POSITIVE,
            5e-324, f64::NAN, f64::INFINITY, f64::NEG_INFINITY,
        ]),
    ]
}

/// A line a population file may hold besides its numbers.
const POPULATION_EXTRAS: &[&str] = &["", "   ", "# comment", "\t# indented comment"];
const POPULATION_GARBAGE: &[&str] = &["1 2", "abc", "1,5", "0x10", "--1", "1e", "\u{fffd}"];

proptest! {
    #![proptest_config(cases(400))]

    /// Population files: what is written is read back (comments and blank lines ignored), a
    /// line that is not one number is refused naming its line, and a population of the wrong
    /// length, or with a value that is not finite and positive, makes every method refuse it
    /// as an invalid population.
    #[test]
    fn population_files_are_read_and_checked(
        mesh in any_mesh(),
        delta in prop_oneof![6 => Just(0i64), 1 => -3i64..4],
        values in prop::collection::vec(population_value(), 0..200),
        extras in prop::collection::vec((any::<Index>(), prop::sample::select(POPULATION_EXTRAS)), 0..3),
        garbage in prop::option::weighted(0.2, (any::<Index>(), prop::sample::select(POPULATION_GARBAGE))),
        variant in any::<u8>(),
    ) {
        let n = (mesh.n_faces() as i64 + delta).max(0) as usize;
        let values: Vec<f64> = (0..n).map(|i| values.get(i).copied().unwrap_or(1.0)).collect();
        let mut lines: Vec<String> = values.iter().map(|v| format!("{v:e}")).collect();
        for (i, extra) in &extras {
            lines.insert(i.index(lines.len() + 1), extra.to_string());
        }
        let bad_line = garbage.map(|(i, g)| {
            let at = i.index(lines.len() + 1);
            lines.insert(at, g.to_string());
            at + 1
        });
        let path = temp_path("population.txt");
        std::fs::write(&path, lines.join("\n")).unwrap();
        let read = demkit::population::read_population_file(&path);
        let from_spec = face_populations(&PopulationSpec::File(path.clone()), mesh);
        std::fs::remove_file(&path).unwrap();
        if let Some(line) = bad_line {
            match &read {
                Err(Error::Parse { line: l, .. }) => prop_assert_eq!(*l, line),
                other => prop_assert!(false, "garbage on line {} gave {:?}", line, other),
            }
            prop_assert!(from_spec.is_err());
            return Ok(());
        }
        let read = read.map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(read.len(), values.len());
        for (a, b) in read.iter().zip(&values) {
            prop_assert!(a == b || (a.is_nan() && b.is_nan()), "{} read back as {}", b, a);
        }
        let usable = values.len() == mesh.n_faces()
            && values.iter().all(|v| v.is_finite() && *v > 0.0);
        prop_assert_eq!(check_population(&values, mesh.n_faces()).is_ok(), usable);
        match &from_spec {
            Ok(_) => prop_assert!(usable),
            Err(e) => prop_assert!(!usable && matches!(e, Error::Population(_)), "{:?}", e),
        }
        match support::run_for_topology(mesh, &values, None, variant) {
            Ok(r) => {
                prop_assert!(usable, "{} mapped the population {:?}", r.method, values);
                support::check_map(mesh, &r).map_err(TestCaseError::fail)?;
            }
            Err(e) => prop_assert!(
                usable || matches!(e, Error::Population(_)),
                "an unusable population gave {:?}", e
            ),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Landmarks

/// A field of a landmark line: an index-like or coordinate-like token, or garbage.
fn landmark_field(n: usize) -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (0..n + 3).prop_map(|i| i.to_string()),
        4 => (-1.5f64..1.5).prop_map(|x| format!("{x}")),
        1 => prop::sample::select(vec!["-1", "nan", "inf", "1e309", "18446744073709551616", "x", "0.5", "1e-3"])
            .prop_map(str::to_string),
    ]
}

proptest! {
    #![proptest_config(cases(1000))]

    /// Landmark files: what the reader accepts is in range, once per vertex and finite, one
    /// landmark per non-blank line; what it refuses is a parse, landmark or format error. Read
    /// landmarks go through the landmark method of the mesh's topology.
    #[test]
    fn landmark_files_are_read_and_checked(
        mesh in prop::sample::select(vec![4usize, 5, 6, 7]).prop_map(|i| &meshes()[i]),
        rows in prop::collection::vec(
            (
                0usize..10_000,
                any::<bool>(),
                prop::collection::vec(landmark_field(40), 2..4),
                prop::option::of(landmark_field(40)),
            ),
            0..5,
        ),
        blank in any::<bool>(),
        variant in any::<u8>(),
    ) {
        let n = mesh.n_vertices();
        let closed = demkit::mesh::topology(mesh).is_closed();
        let mut text = String::new();
        for (v, usable, rest, extra) in &rows {
            let v = v % (n + 3);
            text.push_str(&v.to_string());
            if *usable && v < n {
                // A target the method can take: the vertex's direction on the unit sphere, or
                // a point inside the unit disk.
                let p = mesh.positions[v];
                if closed {
                    let r = p.iter().map(|x| x * x).sum::<f64>().sqrt();
                    text.push_str(&format!(" {} {} {}", p[0] / r, p[1] / r, p[2] / r));
                } else {
                    let a = v as f64;
                    text.push_str(&format!(" {} {}", 0.5 * a.cos(), 0.5 * a.sin()));
                }
            } else {
                for f in rest.iter().chain(extra) {
                    text.push(' ');
                    text.push_str(f);
                }
            }
            text.push('\n');
            if blank {
                text.push_str("# note\n\n");
            }
        }
        match demkit::io::landmarks::parse_landmarks(text.as_bytes(), "landmarks", n) {
            Ok(landmarks) => {
                prop_assert_eq!(landmarks.len(), rows.len());
                let mut seen = vec![false; n];
                for l in &landmarks {
                    prop_assert!(l.vertex < n);
                    prop_assert!(!std::mem::replace(&mut seen[l.vertex], true), "vertex {} twice", l.vertex);
                    prop_assert!(l.target.iter().all(|x| x.is_finite()));
                }
                let pairs: Vec<(usize, [f64; 3])> = landmarks.iter().map(|l| (l.vertex, l.target)).collect();
                let population = face_populations(&PopulationSpec::Area, mesh).unwrap();
                if let Ok(r) = support::run_for_topology(mesh, &population, Some(&pairs), variant) {
                    support::check_map(mesh, &r).map_err(TestCaseError::fail)?;
                }
            }
            Err(e) => prop_assert!(
                matches!(e, Error::Parse { .. } | Error::Landmarks(_) | Error::Format { .. }),
                "{e:?}"
            ),
        }
    }

    /// Landmarks handed to the methods directly, bypassing the reader: an index out of range
    /// or a vertex given twice is refused as invalid landmarks.
    #[test]
    fn landmark_methods_check_their_landmarks(
        mesh in prop::sample::select(vec![4usize, 6]).prop_map(|i| &meshes()[i]),
        indices in prop::collection::vec(0usize..30, 0..4),
        far in prop::sample::select(vec![0usize, usize::MAX, 1 << 40]),
    ) {
        let n = mesh.n_vertices();
        // On the unit sphere for a closed mesh, inside the unit disk for one with holes.
        let target = if demkit::mesh::topology(mesh).is_closed() { [0.0, 0.0, 1.0] } else { [0.1, 0.0, 0.0] };
        let mut landmarks: Vec<(usize, [f64; 3])> = indices.iter().map(|&v| (v, target)).collect();
        if far != 0 {
            landmarks.push((far, target));
        }
        let mut sorted: Vec<usize> = landmarks.iter().map(|l| l.0).collect();
        sorted.sort_unstable();
        let bad = landmarks.is_empty()
            || sorted.windows(2).any(|w| w[0] == w[1])
            || sorted.iter().any(|&v| v >= n);
        let population = vec![1.0; mesh.n_faces()];
        let result = support::run_for_topology(mesh, &population, Some(&landmarks), 0);
        if bad {
            prop_assert!(matches!(result, Err(Error::Landmarks(_))), "{:?} gave {:?}", landmarks, result.map(|r| r.method));
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Expressions

/// An expression tree, printed fully parenthesised and evaluated independently of
/// [`demkit::expr`].
#[derive(Debug, Clone)]
enum Tree {
    Num(f64),
    Var(usize),
    Neg(Box<Tree>),
    Bin(&'static str, Box<Tree>, Box<Tree>),
    Call(&'static str, Vec<Tree>),
}

const VARIABLES: [&str; 4] = ["x", "y", "z", "area"];

impl Tree {
    fn print(&self) -> String {
        match self {
            Tree::Num(v) => format!("{v:?}"),
            Tree::Var(i) => VARIABLES[*i].to_string(),
            Tree::Neg(a) => format!("(-{})", a.print()),
            Tree::Bin(op, a, b) => format!("({}{op}{})", a.print(), b.print()),
            Tree::Call(f, args) => {
                let args: Vec<String> = args.iter().map(Tree::print).collect();
                format!("{f}({})", args.join(", "))
            }
        }
    }

    fn eval(&self, vars: &[f64; 4]) -> f64 {
        let t = |c: bool| if c { 1.0 } else { 0.0 };
        match self {
            Tree::Num(v) => *v,
            Tree::Var(i) => vars[*i],
            Tree::Neg(a) => -a.eval(vars),
            Tree::Bin(op, a, b) => {
                let (a, b) = (a.eval(vars), b.eval(vars));
                match *op {
                    "+" => a + b,
                    "-" => a - b,
                    "*" => a * b,
                    "/" => a / b,
                    "^" => a.powf(b),
                    "<" => t(a < b),
                    ">" => t(a > b),
                    "<=" => t(a <= b),
                    ">=" => t(a >= b),
                    "==" => t(a == b),
                    _ => t(a != b),
                }
            }
            Tree::Call(f, args) => {
                let v: Vec<f64> = args.iter().map(|a| a.eval(vars)).collect();
                match *f {
                    "abs" => v[0].abs(),
                    "sqrt" => v[0].sqrt(),
                    "exp" => v[0].exp(),
                    "log" => v[0].ln(),
                    "sin" => v[0].sin(),
                    "floor" => v[0].floor(),
                    "atan2" => v[0].atan2(v[1]),
                    "hypot" => v[0].hypot(v[1]),
                    "min" => v[1..].iter().fold(v[0], |m, &x| m.min(x)),
                    "max" => v[1..].iter().fold(v[0], |m, &x| m.max(x)),
                    _ => {
                        if v[0] != 0.0 {
                            v[1]
                        } else {
                            v[2]
                        }
                    }
                }
            }
        }
    }
}

fn tree() -> impl Strategy<Value = Tree> {
    let leaf = prop_oneof![
        (0.0f64..100.0).prop_map(Tree::Num),
        prop::sample::select(vec![0.0, 0.5, 2.0, 1e300, 1e-300]).prop_map(Tree::Num),
        (0usize..4).prop_map(Tree::Var),
    ];
    leaf.prop_recursive(5, 40, 3, |inner| {
        prop_oneof![
            inner.clone().prop_map(|a| Tree::Neg(Box::new(a))),
            (
                prop::sample::select(vec![
                    "+", "-", "*", "/", "^", "<", ">", "<=", ">=", "==", "!="
                ]),
                inner.clone(),
                inner.clone(),
            )
                .prop_map(|(op, a, b)| Tree::Bin(op, Box::new(a), Box::new(b))),
            (
                prop::sample::select(vec!["abs", "sqrt", "exp", "log", "sin", "floor"]),
                inner.clone()
            )
                .prop_map(|(f, a)| Tree::Call(f, vec![a])),
            (
                prop::sample::select(vec!["atan2", "hypot"]),
                inner.clone(),
                inner.clone()
            )
                .prop_map(|(f, a, b)| Tree::Call(f, vec![a, b])),
            (
                prop::sample::select(vec!["min", "max"]),
                prop::collection::vec(inner.clone(), 2..4)
            )
                .prop_map(|(f, args)| Tree::Call(f, args)),
            (inner.clone(), inner.clone(), inner)
                .prop_map(|(c, a, b)| Tree::Call("if", vec![c, a, b])),
        ]
    })
}

/// Pieces random expressions are assembled from: every token of the language, and mistakes.
const EXPR_PIECES: &[&str] = &[
    "x",
    "y",
    "z",
    "area",
    "pi",
    "e",
    "tau",
    "w",
    "1",
    "2.5",
    ".5",
    "1e3",
    "1e-3",
    "2e",
    "1e400",
    "0",
    "+",
    "-",
    "*",
    "/",
    "^",
    "**",
    "(",
    ")",
    ",",
    "<",
    ">",
    "<=",
    ">=",
    "==",
    "!=",
    "=",
    "!",
    "abs",
    "sqrt",
    "exp",
    "log",
    "atan2",
    "min",
    "max",
    "if",
    "pow",
    "hypot",
    "sign",
    "nope",
    " ",
    "\u{e9}",
    "\u{1F600}",
    "_",
    "1.2.3",
    "..",
    "$",
];

proptest! {
    #![proptest_config(cases(1000))]

    /// Well-formed expressions compile, and evaluate to what the tree they print evaluates to
    /// (bit for bit, NaN for NaN).
    #[test]
    fn printed_expressions_compile_and_agree(
        t in tree(),
        vars in [-3.0f64..3.0, -3.0f64..3.0, -3.0f64..3.0, 0.0f64..1.0],
    ) {
        let source = t.print();
        let e = Expr::compile(&source, &VARIABLES)
            .map_err(|e| TestCaseError::fail(format!("'{source}': {e}")))?;
        let (got, want) = (e.eval(&vars), t.eval(&vars));
        prop_assert!(
            got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
            "'{}' at {:?}: {} instead of {}", source, vars, got, want
        );
    }
}

proptest! {
    #![proptest_config(cases(4000))]

    /// Any text, and any sequence of the language's tokens: an expression that evaluates, or
    /// an error whose column lies within the text (or one past its end).
    #[test]
    fn any_text_compiles_or_names_a_column(
        source in prop_oneof![
            "\\PC{0,30}",
            prop::collection::vec(prop::sample::select(EXPR_PIECES), 0..16).prop_map(|p| p.concat()),
        ],
        vars in [any::<f64>(), any::<f64>(), any::<f64>(), any::<f64>()],
    ) {
        match Expr::compile(&source, &VARIABLES) {
            Ok(e) => {
                let _ = e.eval(&vars);
                let _ = e.as_constant();
            }
            Err(e) => {
                let len = source.chars().count();
                prop_assert!(e.column >= 1 && e.column <= len + 1, "'{}': column {} of {}", source, e.column, len);
                prop_assert!(!e.to_string().is_empty());
            }
        }
    }

    /// Deep nesting is refused, not a stack overflow.
    #[test]
    fn deep_nesting_is_refused(
        depth in 150usize..5000,
        open in prop::sample::select(vec!["(", "-", "abs(", "2^", "min(1,", "if(1,2,"]),
    ) {
        let source = format!("{}1{}", open.repeat(depth), ")".repeat(depth * open.matches('(').count()));
        if let Ok(e) = Expr::compile(&source, &VARIABLES) {
            prop_assert!(depth <= 200, "depth {} compiled", depth);
            let _ = e.eval(&[0.0; 4]);
        }
    }
}

proptest! {
    #![proptest_config(cases(1500))]

    /// A population expression gives every face a finite positive population, or an invalid
    /// population error (a bad expression, a value not finite and positive, naming the face).
    #[test]
    fn population_expressions_give_values_or_a_population_error(
        mesh in any_mesh(),
        source in prop_oneof![
            tree().prop_map(|t| t.print()),
            prop::collection::vec(prop::sample::select(EXPR_PIECES), 1..10).prop_map(|p| p.concat()),
        ],
    ) {
        match face_populations(&PopulationSpec::Expr(source.clone()), mesh) {
            Ok(values) => {
                prop_assert_eq!(values.len(), mesh.n_faces());
                prop_assert!(values.iter().all(|v| v.is_finite() && *v > 0.0), "'{}' gave {:?}", source, values);
            }
            Err(e) => prop_assert!(matches!(e, Error::Population(_)), "'{}' gave {:?}", source, e),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// GeoJSON regions

/// A property value: a positive number, a number as text, or one the reader must refuse.
fn geo_value() -> impl Strategy<Value = serde_json::Value> {
    use serde_json::{Value, json};
    prop_oneof![
        6 => (0.1f64..100.0).prop_map(|v| json!(v)),
        1 => (0.1f64..100.0).prop_map(|v| json!(v.to_string())),
        1 => prop::sample::select(vec![
            json!(0), json!(-1.5), json!("NaN"), json!("inf"), json!("abc"), json!(1e308),
            Value::Null, json!(true), json!([1]), json!({"v": 1}),
        ]),
    ]
}

/// A ring around `(cx, cy)`: `n` points at radius `r`, with a jitter in angle and radius.
fn ring(cx: f64, cy: f64, r: f64, jitter: &[f64], close: bool, ccw: bool) -> Vec<[f64; 2]> {
    let n = jitter.len().max(1);
    let mut pts: Vec<[f64; 2]> = (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * (k as f64 + 0.3 * jitter[k]) / n as f64;
            let rr = r * (1.0 + 0.2 * jitter[k]);
            [cx + rr * a.cos(), cy + rr * a.sin()]
        })
        .collect();
    if !ccw {
        pts.reverse();
    }
    if close {
        pts.push(pts[0]);
    }
    pts
}

#[derive(Debug, Clone)]
struct FeatureSpec {
    jitter: Vec<f64>,
    hole: Option<Vec<f64>>,
    multi: bool,
    value: serde_json::Value,
    ccw: bool,
}

fn feature_spec() -> impl Strategy<Value = FeatureSpec> {
    (
        prop::collection::vec(-1.0f64..1.0, 3..12),
        prop::option::weighted(0.4, prop::collection::vec(-1.0f64..1.0, 3..6)),
        any::<bool>(),
        geo_value(),
        any::<bool>(),
    )
        .prop_map(|(jitter, hole, multi, value, ccw)| FeatureSpec {
            jitter,
            hole,
            multi,
            value,
            ccw,
        })
}

/// A FeatureCollection of up to six regions on a 3×2 lattice (disjoint as generated), each a
/// jittered star-shaped polygon with an optional hole, as pretty-printed text, and whether
/// every value is one the reader accepts.
fn geojson_text(features: &[FeatureSpec]) -> (String, bool) {
    use serde_json::json;
    let mut list = Vec::new();
    let mut all_valid = true;
    for (i, f) in features.iter().enumerate() {
        let (cx, cy) = ((i % 3) as f64 * 3.0, (i / 3) as f64 * 3.0);
        let mut rings = vec![ring(cx, cy, 1.0, &f.jitter, true, f.ccw)];
        // A hole of radius at most 0.24 lies inside an exterior of eight points or more.
        if let Some(h) = f.hole.as_ref().filter(|_| f.jitter.len() >= 8) {
            rings.push(ring(cx, cy, 0.2, h, true, !f.ccw));
        }
        let geometry = if f.multi {
            json!({"type": "MultiPolygon", "coordinates": [rings]})
        } else {
            json!({"type": "Polygon", "coordinates": rings})
        };
        let value = f
            .value
            .as_f64()
            .or_else(|| f.value.as_str().and_then(|s| s.parse::<f64>().ok()));
        all_valid &= value.is_some_and(|v| v > 0.0 && v.is_finite());
        list.push(json!({
            "type": "Feature",
            "properties": {"name": format!("r{i}"), "value": f.value},
            "geometry": geometry,
        }));
    }
    let fc = json!({"type": "FeatureCollection", "features": list});
    (serde_json::to_string_pretty(&fc).unwrap(), all_valid)
}

proptest! {
    #![proptest_config(cases(1000))]

    /// GeoJSON: undamaged collections of disjoint regions with positive values are read and
    /// built into a region set; damaged ones give regions keeping the reader's promises or a
    /// format error naming the file.
    #[test]
    fn geojson_gives_regions_or_a_format_error(
        features in prop::collection::vec(feature_spec(), 1..7),
        mutations in prop::collection::vec(mutate::mutation(), 0..3),
    ) {
        let (text, all_valid) = geojson_text(&features);
        let mut data = text.clone().into_bytes();
        for m in &mutations {
            mutate::apply(&mut data, m);
        }
        let damaged = data != text.as_bytes();
        let text = String::from_utf8_lossy(&data);
        match parse_regions(&text, "value", "regions.geojson") {
            Ok((fc, raw)) => {
                prop_assert_eq!(raw.len(), fc.features.len());
                for r in &raw {
                    prop_assert!(r.value.is_finite() && r.value > 0.0);
                    prop_assert!(!r.polygons.is_empty());
                    prop_assert!(r.polygons.iter().flatten().flatten().all(|p| p[0].is_finite() && p[1].is_finite()));
                }
                match RegionSet::build(&raw, "regions.geojson") {
                    Ok(set) => {
                        prop_assert_eq!(set.regions.len(), raw.len());
                        for r in &set.regions {
                            for &i in r.polygons.iter().flatten().flatten() {
                                prop_assert!(i < set.points.len());
                            }
                        }
                    }
                    Err(e) => {
                        prop_assert!(damaged, "undamaged regions refused: {e}");
                        prop_assert!(matches!(e, Error::Format { .. }), "{e:?}");
                    }
                }
            }
            Err(e) => {
                prop_assert!(damaged || !all_valid, "undamaged regions refused: {e}");
                prop_assert!(matches!(e, Error::Format { .. }), "{e:?}");
            }
        }
    }
}

proptest! {
    #![proptest_config(cases(100))]

    /// Collections of disjoint regions with positive values are read and built, and go through
    /// the planar or the spherical cartogram (positions as degrees): every region gets a
    /// positive output area, or the run gives a typed error.
    #[test]
    fn cartograms_of_random_regions_run(
        features in prop::collection::vec(feature_spec(), 1..4),
        sphere in any::<bool>(),
    ) {
        let features: Vec<FeatureSpec> = features
            .into_iter()
            .enumerate()
            .map(|(k, f)| FeatureSpec { value: serde_json::json!(1.0 + k as f64), ..f })
            .collect();
        let (text, all_valid) = geojson_text(&features);
        prop_assert!(all_valid);
        let (_, raw) = parse_regions(&text, "value", "regions.geojson")
            .map_err(|e| TestCaseError::fail(e.to_string()))?;
        let set = RegionSet::build(&raw, "regions.geojson")
            .map_err(|e| TestCaseError::fail(e.to_string()))?;
        let config = cartogram::Config {
            max_iter: Some(support::MAX_ITER),
            rounds: 1,
            ..Default::default()
        };
        let result = if sphere {
            cartogram::sphere::run(&set, &config, "regions.geojson", &mut |_| {})
        } else {
            cartogram::planar::run(&set, &config, "regions.geojson", &mut |_| {})
        };
        if let Ok(c) = result {
            prop_assert_eq!(c.regions.len(), set.regions.len());
            prop_assert!(c.regions.iter().all(|r| r.output_area.is_finite() && r.output_area > 0.0));
        }
    }
}

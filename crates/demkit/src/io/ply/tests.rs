use super::*;
use crate::Error;

#[test]
fn data_beyond_the_declared_elements_is_an_error_naming_its_line() {
    let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n";
    match parse_ply(text.as_bytes(), "t.ply") {
        Err(Error::Parse { line, msg, .. }) => {
            assert_eq!(line, 14, "{msg}");
            assert!(msg.contains("after the elements"), "{msg}");
        }
        other => panic!("{other:?}"),
    }
}
use crate::io::test_util::data_dir;

/// A value of a given PLY type, for building test files.
#[derive(Clone, Copy)]
enum V {
    I8(i8),
    U8(u8),
    I16(i16),
    U16(u16),
    I32(i32),
    U32(u32),
    F32(f32),
    F64(f64),
}

#[derive(Clone, Copy, PartialEq)]
enum Enc {
    Ascii,
    Le,
    Be,
}

impl Enc {
    fn name(self) -> &'static str {
        match self {
            Enc::Ascii => "ascii",
            Enc::Le => "binary_little_endian",
            Enc::Be => "binary_big_endian",
        }
    }
}

const ALL: [Enc; 3] = [Enc::Ascii, Enc::Le, Enc::Be];

/// A PLY file from header lines (between `format` and `end_header`) and items of values.
fn build(enc: Enc, header: &str, items: &[Vec<V>]) -> Vec<u8> {
    let mut out = format!("ply\nformat {} 1.0\n{header}end_header\n", enc.name()).into_bytes();
    for item in items {
        let mut text = Vec::new();
        for &v in item {
            if enc == Enc::Ascii {
                text.push(match v {
                    V::I8(x) => x.to_string(),
                    V::U8(x) => x.to_string(),
                    V::I16(x) => x.to_string(),
                    V::U16(x) => x.to_string(),
                    V::I32(x) => x.to_string(),
                    V::U32(x) => x.to_string(),
                    V::F32(x) => x.to_string(),
                    V::F64(x) => x.to_string(),
                });
                continue;
            }
            let le = enc == Enc::Le;
            macro_rules! bytes {
                ($x:expr) => {
                    if le {
                        $x.to_le_bytes().to_vec()
                    } else {
                        $x.to_be_bytes().to_vec()
                    }
                };
            }
            out.extend(match v {
                V::I8(x) => bytes!(x),
                V::U8(x) => bytes!(x),
                V::I16(x) => bytes!(x),
                V::U16(x) => bytes!(x),
                V::I32(x) => bytes!(x),
                V::U32(x) => bytes!(x),
                V::F32(x) => bytes!(x),
                V::F64(x) => bytes!(x),
            });
        }
        if enc == Enc::Ascii {
            out.extend(text.join(" ").into_bytes());
            out.push(b'\n');
        }
    }
    out
}

/// The test writer: `mesh` in any encoding, with the same layout as [`write_ply`].
fn write_with(enc: Enc, mesh: &TriMesh) -> Vec<u8> {
    let header = format!(
        "element vertex {}\nproperty double x\nproperty double y\nproperty double z\n\
         element face {}\nproperty list uchar int vertex_indices\n",
        mesh.positions.len(),
        mesh.faces.len()
    );
    let mut items: Vec<Vec<V>> = mesh
        .positions
        .iter()
        .map(|p| p.map(V::F64).to_vec())
        .collect();
    for f in &mesh.faces {
        items.push(vec![
            V::U8(3),
            V::I32(f[0] as i32),
            V::I32(f[1] as i32),
            V::I32(f[2] as i32),
        ]);
    }
    build(enc, &header, &items)
}

fn sample() -> TriMesh {
    TriMesh::new(
        vec![
            [0.1, -2.0 / 3.0, 1e-300],
            [std::f64::consts::PI, 1e300, -0.0],
            [123_456_789.123_456_79, 5e-324, 7.0],
            [1.0, 2.0, 3.0],
        ],
        vec![[0, 1, 2], [2, 1, 3]],
    )
}

fn parse(data: &[u8]) -> Result<TriMesh> {
    parse_ply(data, "t.ply")
}

fn bits(m: &TriMesh) -> Vec<[u64; 3]> {
    m.positions.iter().map(|p| p.map(f64::to_bits)).collect()
}

#[test]
fn round_trip_binary_little_endian() {
    let m = sample();
    let mut buf = Vec::new();
    write_ply(&mut buf, &m).unwrap();
    let back = parse(&buf).unwrap();
    assert_eq!(back.faces, m.faces);
    assert_eq!(bits(&back), bits(&m));
    // The writer and the test writer agree byte for byte (apart from the comment).
    let comment = b"comment written by demkit\n";
    let at = buf
        .windows(comment.len())
        .position(|w| w == comment)
        .unwrap();
    buf.drain(at..at + comment.len());
    assert_eq!(buf, write_with(Enc::Le, &m));
}

#[test]
fn round_trip_all_encodings() {
    let m = sample();
    for enc in ALL {
        let back = parse(&write_with(enc, &m)).unwrap();
        assert_eq!(back.faces, m.faces, "{}", enc.name());
        assert_eq!(bits(&back), bits(&m), "{}", enc.name());
    }
}

/// A unit square with extra properties and elements of every kind to skip.
fn decorated(enc: Enc, face_list: &str) -> Vec<u8> {
    let header = format!(
        "comment made by hand\nobj_info test\n\
         element material 1\nproperty list uchar float weights\nproperty uchar id\n\
         element vertex 4\nproperty float nx\nproperty float x\nproperty list ushort short \
         tags\nproperty float y\nproperty uchar red\nproperty float z\nproperty int8 flag\n\
         element face 2\nproperty uchar kind\nproperty {face_list}\n\
         property list uint uint16 extra\n\
         element edge 1\nproperty int vertex1\nproperty int vertex2\n"
    );
    let vertex = |x: f32, y: f32, tags: &[i16]| {
        let mut v = vec![V::F32(0.5), V::F32(x), V::U16(tags.len() as u16)];
        v.extend(tags.iter().map(|&t| V::I16(t)));
        v.extend([V::F32(y), V::U8(200), V::F32(0.0), V::I8(-1)]);
        v
    };
    let face = |f: [u32; 3]| {
        let mut v = vec![V::U8(7)];
        v.push(match face_list {
            l if l.contains("uint8 ") => V::U8(3),
            _ => V::I32(3),
        });
        for i in f {
            v.push(if face_list.ends_with("uint16 vertex_index") {
                V::U16(i as u16)
            } else {
                V::U32(i)
            });
        }
        v.extend([V::U32(2), V::U16(9), V::U16(9)]);
        v
    };
    let items = vec![
        vec![V::U8(2), V::F32(1.0), V::F32(2.0), V::U8(5)],
        vertex(0.0, 0.0, &[]),
        vertex(1.0, 0.0, &[1, 2, 3]),
        vertex(1.0, 1.0, &[4]),
        vertex(0.0, 1.0, &[]),
        face([0, 1, 2]),
        face([0, 2, 3]),
        vec![V::I32(0), V::I32(1)],
    ];
    build(enc, &header, &items)
}

#[test]
fn skips_other_properties_and_elements() {
    let square = TriMesh::new(
        vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
        vec![[0, 1, 2], [0, 2, 3]],
    );
    for enc in ALL {
        for list in [
            "list int uint vertex_indices",
            "list uint8 uint16 vertex_index",
        ] {
            let m = parse(&decorated(enc, list)).unwrap_or_else(|e| panic!("{list}: {e}"));
            assert_eq!(m, square, "{} {list}", enc.name());
        }
    }
}

#[test]
fn crlf_header_and_ascii_body() {
    let text = "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\n\
                property float y\r\nproperty float z\r\nelement face 1\r\n\
                property list uchar int vertex_indices\r\nend_header\r\n\
                0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n";
    assert_eq!(parse(text.as_bytes()).unwrap().faces, vec![[0, 1, 2]]);
}

fn format_msg(r: Result<TriMesh>) -> String {
    match r {
        Err(Error::Format { msg, .. }) => msg,
        other => panic!("expected a format error, got {other:?}"),
    }
}

fn parse_msg(r: Result<TriMesh>) -> (usize, String) {
    match r {
        Err(Error::Parse { line, msg, .. }) => (line, msg),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

#[test]
fn truncated_binary() {
    for enc in [Enc::Le, Enc::Be] {
        let full = write_with(enc, &sample());
        for (cut, place) in [
            (1, "face 1 of 2"),
            (13, "face 1 of 2"),
            (14, "face 0 of 2"),
            (60, "vertex 2 of 4"),
        ] {
            let msg = format_msg(parse(&full[..full.len() - cut]));
            assert_eq!(msg, format!("file is truncated: it ends in {place}"));
        }
        let header_end = full.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
        let msg = format_msg(parse(&full[..header_end + 30]));
        assert!(msg.contains("vertex 1 of 4"), "{msg}");
    }
    let ascii = write_with(Enc::Ascii, &sample());
    let msg = format_msg(parse(&ascii[..ascii.len() - 5]));
    assert_eq!(msg, "file is truncated: it ends in face 1 of 2");
}

#[test]
fn quads_are_rejected_naming_the_face() {
    let header = "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
                  element face 2\nproperty list uchar int vertex_indices\n";
    let mut items: Vec<Vec<V>> = (0..4)
        .map(|i| vec![V::F32(i as f32), V::F32(0.5 * i as f32), V::F32(0.0)])
        .collect();
    items.push(vec![V::U8(3), V::I32(0), V::I32(1), V::I32(2)]);
    items.push(vec![V::U8(4), V::I32(0), V::I32(1), V::I32(2), V::I32(3)]);
    let expected =
        "face 1 has 4 vertices: only triangles are supported (triangulate the mesh first)";
    assert_eq!(format_msg(parse(&build(Enc::Le, header, &items))), expected);
    assert_eq!(format_msg(parse(&build(Enc::Be, header, &items))), expected);
    assert_eq!(
        parse_msg(parse(&build(Enc::Ascii, header, &items))),
        (15, expected.to_string())
    );
}

#[test]
fn bad_indices_and_coordinates() {
    let header = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                  element face 1\nproperty list uchar int vertex_indices\n";
    let verts: Vec<Vec<V>> = (0..3)
        .map(|i| vec![V::F32(i as f32), V::F32((i % 2) as f32), V::F32(0.0)])
        .collect();
    let with_face = |f: [i32; 3]| {
        let mut items = verts.clone();
        items.push(vec![V::U8(3), V::I32(f[0]), V::I32(f[1]), V::I32(f[2])]);
        items
    };
    let msg = format_msg(parse(&build(Enc::Le, header, &with_face([0, 1, 3]))));
    assert_eq!(
        msg,
        "face 0 uses vertex 3, which is out of range (the file has 3 vertices)"
    );
    let (line, msg) = parse_msg(parse(&build(Enc::Ascii, header, &with_face([0, 5, 1]))));
    assert_eq!(line, 13);
    assert!(msg.contains("vertex 5, which is out of range"), "{msg}");
    let msg = format_msg(parse(&build(Enc::Be, header, &with_face([0, -1, 1]))));
    assert_eq!(msg, "face 0 has an invalid vertex index -1");

    let mut items = with_face([0, 1, 2]);
    items[1][1] = V::F32(f32::NAN);
    assert_eq!(
        format_msg(parse(&build(Enc::Le, header, &items))),
        "vertex 1 has a non-finite coordinate"
    );
    let (line, msg) = parse_msg(parse(&build(Enc::Ascii, header, &items)));
    assert_eq!(
        (line, msg.as_str()),
        (11, "vertex 1 has a non-finite coordinate")
    );

    let text = String::from_utf8(build(Enc::Ascii, header, &with_face([0, 1, 2])))
        .unwrap()
        .replace("\n2 0 0\n", "\n2 abc 0\n");
    let (line, msg) = parse_msg(parse(text.as_bytes()));
    assert_eq!((line, msg.as_str()), (12, "cannot read 'abc' as a number"));
}

#[test]
fn malformed_headers() {
    assert!(format_msg(parse(b"plx\n")).contains("not a PLY file"));
    assert!(format_msg(parse(b"ply\nformat ascii 1.0\nelement vertex 0\n")).contains("end_header"));
    assert!(format_msg(parse(b"ply\nelement vertex 0\nend_header\n")).contains("'format'"));
    let (line, msg) = parse_msg(parse(b"ply\nformat ascii 2.0\nend_header\n"));
    assert_eq!(line, 2);
    assert!(msg.contains("version 1.0"), "{msg}");
    let (line, msg) = parse_msg(parse(
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n",
    ));
    assert_eq!(line, 4);
    assert!(msg.contains("'float128'"), "{msg}");
    let (line, _) = parse_msg(parse(
        b"ply\nformat ascii 1.0\nproperty float x\nend_header\n",
    ));
    assert_eq!(line, 3);
    let (line, _) = parse_msg(parse(
        b"ply\nformat ascii 1.0\nelement vertex many\nend_header\n",
    ));
    assert_eq!(line, 3);
    let (line, _) = parse_msg(parse(b"ply\nformat ascii 1.0\nbogus\nend_header\n"));
    assert_eq!(line, 3);
    let msg = format_msg(parse(
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
    ));
    assert!(msg.contains("no property 'z'"), "{msg}");
    let msg = format_msg(parse(
        b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
          property float z\nelement face 0\nproperty int vertex_indices\nend_header\n",
    ));
    assert!(msg.contains("no list property 'vertex_indices'"), "{msg}");
    let msg = format_msg(parse(
        b"ply\nformat ascii 1.0\nelement face 0\nend_header\n",
    ));
    assert!(msg.contains("one 'vertex' element"), "{msg}");
}

#[test]
fn huge_counts_do_not_allocate() {
    let data = b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n\
                 property float x\nproperty float y\nproperty float z\nelement face 1\n\
                 property list uchar int vertex_indices\nend_header\n";
    assert!(format_msg(parse(data)).starts_with("file is truncated"));
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn real_mesh_round_trip() {
    let m = crate::io::read_mesh(&data_dir().join("open/human_face.obj")).unwrap();
    let mut buf = Vec::new();
    write_ply(&mut buf, &m).unwrap();
    assert_eq!(parse(&buf).unwrap(), m);
    assert_eq!(parse(&write_with(Enc::Ascii, &m)).unwrap(), m);
}

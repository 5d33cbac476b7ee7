//! Inputs that once made a reader or parser hang, panic or break its promises, found by the
//! fuzz targets in `fuzz/` and by the property tests (`tests/properties.rs`). Each test names
//! the fault and checks the behaviour that replaced it.

use demkit::io::{obj, off, ply, stl};
use demkit::{Error, TriMesh};
use std::sync::mpsc;
use std::time::Duration;

/// Runs `f` on another thread and fails if it takes longer than `seconds` (a hang would
/// otherwise stop the whole test run).
fn within<T: Send + 'static>(seconds: u64, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(Duration::from_secs(seconds))
        .unwrap_or_else(|_| panic!("no answer within {seconds} s"))
}

fn triangle() -> TriMesh {
    TriMesh::new(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        vec![[0, 1, 2]],
    )
}

const PLY_HEADER_START: &str = "ply\nformat {FORMAT} 1.0\nelement vertex 3\nproperty float x\n\
                                property float y\nproperty float z\n";

/// A PLY element without properties takes no bytes, so its count says nothing about the data;
/// the reader used to count up to it item by item, and a count near 2^63 never ended.
#[test]
fn ply_element_without_properties_and_a_huge_count_is_skipped() {
    for (format, body) in [
        ("ascii", b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n".to_vec()),
        ("binary_little_endian", {
            let mut b = Vec::new();
            for x in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
                b.extend_from_slice(&x.to_le_bytes());
            }
            b.push(3);
            for v in [0i32, 1, 2] {
                b.extend_from_slice(&v.to_le_bytes());
            }
            b
        }),
    ] {
        let mut data = PLY_HEADER_START.replace("{FORMAT}", format).into_bytes();
        data.extend_from_slice(
            b"element nothing 9000000000000000000\nelement face 1\n\
              property list uchar int vertex_indices\nelement nothing_either 5\nend_header\n",
        );
        data.extend_from_slice(&body);
        let mesh = within(10, move || ply::parse_ply(&data, "t.ply"));
        assert_eq!(mesh.unwrap(), triangle(), "{format}");
    }
}

/// A count far beyond what the data holds is refused as truncated without reserving memory
/// for it (the reservation is bounded by the bytes the items could take).
#[test]
fn ply_huge_counts_are_truncation_errors() {
    for format in ["ascii", "binary_big_endian"] {
        let mut data = PLY_HEADER_START
            .replace("{FORMAT}", format)
            .replace("vertex 3", "vertex 4611686018427387903")
            .into_bytes();
        data.extend_from_slice(
            b"element face 4611686018427387903\nproperty list uchar int vertex_indices\n\
              end_header\n0 0 0\n",
        );
        match within(10, move || ply::parse_ply(&data, "t.ply")) {
            Err(Error::Format { msg, .. }) => assert!(msg.contains("truncated"), "{msg}"),
            other => panic!("{format}: {other:?}"),
        }
    }
}

/// Every reader refuses an empty or whitespace-only input with an error, never a panic.
#[test]
fn empty_inputs_are_errors() {
    for data in [&b""[..], b"\n", b" \r\n\t"] {
        for result in [
            obj::parse_obj(data, "t"),
            off::parse_off(data, "t"),
            ply::parse_ply(data, "t"),
            stl::parse_stl(data, "t"),
        ] {
            assert!(
                matches!(result, Err(Error::Format { .. } | Error::Parse { .. })),
                "{result:?}"
            );
        }
    }
}

//! Writers for every mesh format demkit reads, with the variations a reader must cope with
//! (PLY encodings, scalar types and extra properties; ascii and binary STL). The library only
//! writes OBJ and binary PLY; these produce the other inputs for the property tests and the
//! fuzzers' seed corpora.

#![allow(dead_code)]

use demkit::TriMesh;

/// A mesh file format, with the encoding variant where the format has several.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ (the library's writer).
    Obj,
    /// PLY, ascii.
    PlyAscii,
    /// PLY, binary little-endian.
    PlyLittle,
    /// PLY, binary big-endian.
    PlyBig,
    /// OFF.
    Off,
    /// STL, ascii.
    StlAscii,
    /// STL, binary.
    StlBinary,
}

impl Format {
    /// Every format.
    pub const ALL: [Format; 7] = [
        Format::Obj,
        Format::PlyAscii,
        Format::PlyLittle,
        Format::PlyBig,
        Format::Off,
        Format::StlAscii,
        Format::StlBinary,
    ];

    /// The file extension [`demkit::io::read_mesh`] chooses the reader by.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Obj => "obj",
            Format::PlyAscii | Format::PlyLittle | Format::PlyBig => "ply",
            Format::Off => "off",
            Format::StlAscii | Format::StlBinary => "stl",
        }
    }

    /// True for the formats whose body is binary data.
    pub fn is_binary(self) -> bool {
        matches!(self, Format::PlyLittle | Format::PlyBig | Format::StlBinary)
    }
}

/// Layout choices for a PLY file beyond its encoding.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PlyStyle {
    /// Coordinates as `double` (else `float`).
    pub double: bool,
    /// The index type of the face list: 0 `int`, 1 `uint`, 2 `ushort` (when it fits), 3 `uchar`
    /// (when it fits).
    pub index_type: u8,
    /// Adds per-vertex colours, a per-face list of texture coordinates and an `edge` element
    /// the reader must skip.
    pub extras: bool,
}

impl Default for PlyStyle {
    fn default() -> Self {
        Self {
            double: true,
            index_type: 0,
            extras: false,
        }
    }
}

/// `mesh` in `format` with the default PLY layout.
pub fn write(mesh: &TriMesh, format: Format) -> Vec<u8> {
    write_styled(mesh, format, PlyStyle::default())
}

/// `mesh` in `format`; `style` applies to the PLY formats only.
pub fn write_styled(mesh: &TriMesh, format: Format, style: PlyStyle) -> Vec<u8> {
    match format {
        Format::Obj => {
            let mut out = Vec::new();
            demkit::io::obj::write_obj(&mut out, mesh).expect("writing to memory");
            out
        }
        Format::PlyAscii => ply(mesh, None, style),
        Format::PlyLittle => ply(mesh, Some(false), style),
        Format::PlyBig => ply(mesh, Some(true), style),
        Format::Off => off(mesh),
        Format::StlAscii => stl_ascii(mesh),
        Format::StlBinary => stl_binary(mesh),
    }
}

/// OFF text: header, counts, one vertex and one face per line.
pub fn off(mesh: &TriMesh) -> Vec<u8> {
    let mut s = format!("OFF\n{} {} 0\n", mesh.positions.len(), mesh.faces.len());
    for p in &mesh.positions {
        s.push_str(&format!("{} {} {}\n", p[0], p[1], p[2]));
    }
    for f in &mesh.faces {
        s.push_str(&format!("3 {} {} {}\n", f[0], f[1], f[2]));
    }
    s.into_bytes()
}

fn normal(c: [[f64; 3]; 3]) -> [f64; 3] {
    let u: [f64; 3] = std::array::from_fn(|k| c[1][k] - c[0][k]);
    let v: [f64; 3] = std::array::from_fn(|k| c[2][k] - c[0][k]);
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len > 0.0 {
        n.map(|x| x / len)
    } else {
        [0.0; 3]
    }
}

/// Ascii STL: one `facet` per face with its normal and three corners.
pub fn stl_ascii(mesh: &TriMesh) -> Vec<u8> {
    let mut s = String::from("solid generated\n");
    for f in 0..mesh.faces.len() {
        let c = mesh.corners(f);
        let n = normal(c);
        s.push_str(&format!(
            "  facet normal {} {} {}\n    outer loop\n",
            n[0], n[1], n[2]
        ));
        for p in c {
            s.push_str(&format!("      vertex {} {} {}\n", p[0], p[1], p[2]));
        }
        s.push_str("    endloop\n  endfacet\n");
    }
    s.push_str("endsolid generated\n");
    s.into_bytes()
}

/// Binary STL: an 80-byte header, the triangle count, 50 bytes per triangle (`f32` values).
pub fn stl_binary(mesh: &TriMesh) -> Vec<u8> {
    let mut out = vec![0u8; 80];
    out[..9].copy_from_slice(b"generated");
    out.extend_from_slice(&(mesh.faces.len() as u32).to_le_bytes());
    for f in 0..mesh.faces.len() {
        let c = mesh.corners(f);
        for x in normal(c).into_iter().chain(c.into_iter().flatten()) {
            out.extend_from_slice(&(x as f32).to_le_bytes());
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

/// PLY: ascii when `big_endian` is `None`, else binary of that byte order.
pub fn ply(mesh: &TriMesh, big_endian: Option<bool>, style: PlyStyle) -> Vec<u8> {
    let n = mesh.positions.len();
    let index_type = match style.index_type {
        2 if n <= u16::MAX as usize => "ushort",
        3 if n <= u8::MAX as usize => "uchar",
        1 => "uint",
        _ => "int",
    };
    let coord_type = if style.double { "double" } else { "float" };
    let format = match big_endian {
        None => "ascii",
        Some(false) => "binary_little_endian",
        Some(true) => "binary_big_endian",
    };
    let mut h = format!("ply\nformat {format} 1.0\ncomment generated\nelement vertex {n}\n");
    for axis in ["x", "y", "z"] {
        h.push_str(&format!("property {coord_type} {axis}\n"));
    }
    if style.extras {
        h.push_str("property uchar red\nproperty uchar green\nproperty uchar blue\n");
    }
    h.push_str(&format!("element face {}\n", mesh.faces.len()));
    h.push_str(&format!(
        "property list uchar {index_type} vertex_indices\n"
    ));
    if style.extras {
        h.push_str("property list uchar float texcoord\nelement edge 1\n");
        h.push_str("property int vertex1\nproperty int vertex2\n");
    }
    h.push_str("end_header\n");
    let mut out = h.into_bytes();
    let Some(big) = big_endian else {
        let mut s = String::new();
        for p in &mesh.positions {
            if style.double {
                s.push_str(&format!("{} {} {}", p[0], p[1], p[2]));
            } else {
                s.push_str(&format!("{} {} {}", p[0] as f32, p[1] as f32, p[2] as f32));
            }
            if style.extras {
                s.push_str(" 200 100 0");
            }
            s.push('\n');
        }
        for f in &mesh.faces {
            s.push_str(&format!("3 {} {} {}", f[0], f[1], f[2]));
            if style.extras {
                s.push_str(" 2 0.5 0.25");
            }
            s.push('\n');
        }
        if style.extras {
            s.push_str("0 1\n");
        }
        out.extend_from_slice(s.as_bytes());
        return out;
    };
    let put = |bytes: &mut Vec<u8>, le: &[u8]| {
        if big {
            bytes.extend(le.iter().rev());
        } else {
            bytes.extend_from_slice(le);
        }
    };
    for p in &mesh.positions {
        for &x in p {
            if style.double {
                put(&mut out, &x.to_le_bytes());
            } else {
                put(&mut out, &(x as f32).to_le_bytes());
            }
        }
        if style.extras {
            out.extend_from_slice(&[200, 100, 0]);
        }
    }
    for f in &mesh.faces {
        out.push(3);
        for &v in f {
            match index_type {
                "uchar" => out.push(v as u8),
                "ushort" => put(&mut out, &(v as u16).to_le_bytes()),
                _ => put(&mut out, &v.to_le_bytes()),
            }
        }
        if style.extras {
            out.push(2);
            put(&mut out, &0.5f32.to_le_bytes());
            put(&mut out, &0.25f32.to_le_bytes());
        }
    }
    if style.extras {
        put(&mut out, &0i32.to_le_bytes());
        put(&mut out, &1i32.to_le_bytes());
    }
    out
}

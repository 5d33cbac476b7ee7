//! `demkit generate`: synthetic meshes made by demkit itself.

use crate::Failure;
use crate::args::{GenerateArgs, GenerateKind};
use demkit::generate as g;

/// Writes the requested mesh to `--out`.
pub fn run(a: &GenerateArgs) -> Result<u8, Failure> {
    let out = a
        .out
        .as_ref()
        .ok_or_else(|| Failure::input("generate needs --out FILE (.obj or .ply)"))?;
    crate::map::check_output_extension(out)?;
    crate::paths::check(&[], &[crate::paths::named("--out", out)])?;
    let mesh = generated(&a.kind)?;
    demkit::io::write_mesh(out, &mesh)?;
    Ok(0)
}

/// The library's names of `generate`'s parameters and the flags that set them.
const GENERATE_FLAGS: [(&str, &str); 19] = [
    ("nx", "--nx"),
    ("ny", "--ny"),
    ("width", "--width"),
    ("height", "--height"),
    ("sides", "--sides"),
    ("rings", "--rings"),
    ("n", "--n"),
    ("inner_r", "--inner"),
    ("outer_r", "--outer"),
    ("n_radial", "--radial"),
    ("n_angular", "--angular"),
    ("resolution", "--resolution"),
    ("subdivisions", "--subdivisions"),
    ("n_lat", "--lat"),
    ("n_lon", "--lon"),
    ("big_r", "--R"),
    ("small_r", "--r"),
    ("n_major", "--major"),
    ("n_minor", "--minor"),
];

/// The error's message with `generate`'s parameters named by their flags, word by word
/// ("inner_r must be positive" → "--inner must be positive"); other errors as they are.
fn with_generate_flags(e: demkit::Error) -> Failure {
    let argument = matches!(e, demkit::Error::Argument(_));
    let mut f = Failure::from(e);
    if argument {
        let mut out = String::with_capacity(f.message.len());
        let mut word = String::new();
        let flush = |word: &mut String, out: &mut String| {
            let w = std::mem::take(word);
            out.push_str(
                GENERATE_FLAGS
                    .iter()
                    .find(|(p, _)| *p == w)
                    .map_or(w.as_str(), |(_, flag)| flag),
            );
        };
        for c in f.message.chars() {
            if c.is_alphanumeric() || c == '_' {
                word.push(c);
            } else {
                flush(&mut word, &mut out);
                out.push(c);
            }
        }
        flush(&mut word, &mut out);
        f.message = out;
    }
    f
}

/// The mesh `kind` asks for.
fn generated(kind: &GenerateKind) -> Result<demkit::TriMesh, Failure> {
    let holes = match kind {
        GenerateKind::DiskHoles { holes, .. } | GenerateKind::RectHoles { holes, .. } => holes
            .iter()
            .map(|h| parse_hole(h))
            .collect::<Result<Vec<_>, _>>()?,
        _ => Vec::new(),
    };
    let made = match kind {
        GenerateKind::Grid {
            nx,
            ny,
            width,
            height,
        } => g::square_grid(*nx, *ny, *width, *height),
        GenerateKind::Polygon { sides, rings } => g::regular_polygon(*sides, *rings),
        GenerateKind::Peaks { n } => g::peaks(*n),
        GenerateKind::Gaussian { n } => g::gaussian(*n),
        GenerateKind::Annulus {
            inner,
            outer,
            radial,
            angular,
        } => g::annulus(*inner, *outer, *radial, *angular),
        GenerateKind::DiskHoles { resolution, .. } => g::disk_with_holes(&holes, *resolution),
        GenerateKind::RectHoles {
            width,
            height,
            resolution,
            ..
        } => g::rectangle_with_holes(*width, *height, &holes, *resolution),
        GenerateKind::Icosphere { subdivisions } => g::icosphere(*subdivisions),
        GenerateKind::UvSphere { lat, lon } => g::uv_sphere(*lat, *lon),
        GenerateKind::Torus {
            big_r,
            small_r,
            major,
            minor,
        } => g::torus(*big_r, *small_r, *major, *minor),
    };
    made.map_err(with_generate_flags)
}

fn parse_hole(s: &str) -> Result<(f64, f64, f64), Failure> {
    let v: Vec<Option<f64>> = s.split(':').map(|x| x.trim().parse::<f64>().ok()).collect();
    match v.as_slice() {
        [Some(cx), Some(cy), Some(r)] => Ok((*cx, *cy, *r)),
        _ => Err(Failure::input(format!(
            "--hole '{s}' must be CX:CY:R with three numbers"
        ))),
    }
}

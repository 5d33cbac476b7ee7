//! Writes the seed corpora of the fuzz targets into the folder given as argument (one
//! sub-folder per target), from small meshes made by `demkit::generate` in every format and
//! layout, and from short expressions, GeoJSON collections and landmark files. Nothing is
//! copied from outside the repository.

#[path = "../../crates/demkit/tests/support/formats.rs"]
mod formats;

use formats::{Format, PlyStyle};
use std::path::Path;

fn main() {
    let root = std::env::args().nth(1).unwrap_or_else(|| "corpus".into());
    let root = Path::new(&root);
    use demkit::generate::*;
    let meshes = [
        ("grid", square_grid(2, 2, 1.0, 1.0).unwrap()),
        ("polygon", regular_polygon(5, 1).unwrap()),
        ("peaks", peaks(2).unwrap()),
        ("annulus", annulus(0.4, 1.0, 1, 6).unwrap()),
        ("icosphere", icosphere(0).unwrap()),
        ("torus", torus(3.0, 1.0, 4, 3).unwrap()),
    ];
    let mut count = 0;
    let mut put = |target: &str, name: &str, data: &[u8]| {
        let dir = root.join(target);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join(name), data).unwrap();
        count += 1;
    };
    for (name, mesh) in &meshes {
        for format in Format::ALL {
            let target = format!("mesh_{}", format.extension());
            let styles: &[PlyStyle] = match format {
                Format::PlyAscii | Format::PlyLittle | Format::PlyBig => &[
                    PlyStyle {
                        double: true,
                        index_type: 0,
                        extras: false,
                    },
                    PlyStyle {
                        double: false,
                        index_type: 3,
                        extras: true,
                    },
                    PlyStyle {
                        double: false,
                        index_type: 2,
                        extras: false,
                    },
                ],
                _ => &[PlyStyle {
                    double: true,
                    index_type: 0,
                    extras: false,
                }],
            };
            for (k, style) in styles.iter().enumerate() {
                let data = formats::write_styled(mesh, format, *style);
                put(&target, &format!("{name}-{format:?}-{k}"), &data);
            }
        }
    }
    // OBJ statements the writer does not produce.
    put(
        "mesh_obj",
        "statements",
        b"# c\no x\nmtllib a.mtl\nv 0 0 0 1\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\ng a\ns 1\n\
          usemtl m\nf 1/1/1 2/1/1 3/1/1\nf -3//1 -2//1 -1//1\n",
    );
    put(
        "mesh_off",
        "variants",
        b"# c\nCOFF 3 1 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n3 0 1 2 255 0 0\n",
    );

    let expressions = [
        "2.2-abs(x)-abs(y)",
        "area*(1+3*(x>0))",
        "5+((x-50)+(y-50))/50",
        "1+exp(-((x-50)^2+(y-50)^2)/1000)",
        "2.5+sin(pi*(x-50)/25)",
        "1.5+sin(pi*x/25)*sin(pi*y/25)",
        "area*(1+4.5*(z+1))",
        "if(x<=0.5, min(1, y, z), max(2, atan2(y, x)))",
        "-2^-1**2 + hypot(x, y) / sqrt(area) - log10(1e3) + floor(tau) != e",
        "sign(x)*cbrt(y) >= round(1.5e-3)",
    ];
    for (k, e) in expressions.iter().enumerate() {
        put("expr", &format!("e{k}"), e.as_bytes());
    }

    let square = |x: f64, y: f64| {
        format!(
            "[[{x},{y}],[{},{y}],[{},{}],[{x},{}],[{x},{y}]]",
            x + 1.0,
            x + 1.0,
            y + 1.0,
            y + 1.0
        )
    };
    let collections = [
        format!(
            r#"{{"type":"FeatureCollection","features":[{{"type":"Feature","properties":{{"name":"a","value":2}},"geometry":{{"type":"Polygon","coordinates":[{}]}}}},{{"type":"Feature","id":7,"properties":{{"value":"1.5"}},"geometry":{{"type":"Polygon","coordinates":[{}]}}}}]}}"#,
            square(0.0, 0.0),
            square(1.0, 0.0)
        ),
        format!(
            r#"{{"type":"FeatureCollection","features":[{{"type":"Feature","properties":{{"value":1}},"geometry":{{"type":"MultiPolygon","coordinates":[[{},[[0.25,0.25],[0.25,0.75],[0.75,0.75],[0.75,0.25],[0.25,0.25]]],[{}]]}}}}]}}"#,
            square(0.0, 0.0),
            square(3.0, 0.0)
        ),
        format!(
            r#"{{"type":"FeatureCollection","bbox":[0,0,2,1],"features":[{{"type":"Feature","properties":{{"NAME":"x","value":3.5}},"geometry":{{"type":"Polygon","coordinates":[{}]}}}},{{"type":"Feature","properties":{{"value":1}},"geometry":{{"type":"Point","coordinates":[0,0]}}}}]}}"#,
            square(0.0, 0.0)
        ),
    ];
    for (k, c) in collections.iter().enumerate() {
        put("geojson", &format!("g{k}"), c.as_bytes());
    }

    // Landmark files: the first byte is the mesh's vertex count.
    put(
        "landmarks",
        "l0",
        b"\x0c0 0 0.6 0.8\n11 0.8 0 0.6\n# c\n\n5 -0.6 0.8 0\n",
    );
    put("landmarks", "l1", b"\x183 0.1 0.2\n7 -0.25 0\n");
    put("landmarks", "l2", b"\x100\n15\n3 # c\n");
    println!("wrote {count} seed files under {}", root.display());
}

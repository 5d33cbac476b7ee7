//! End-to-end tests of `demkit cartogram` (DEM paper §6.1): grids and irregular regions made
//! here as GeoJSON, the output checked for validity (simple rings, the input's ring
//! structure), no overlaps, no gaps (shared borders identical), and areas proportional to the
//! values; and the refusals.

mod common;

use common::Scratch;
use serde_json::{Value, json};

type Ring = Vec<[f64; 2]>;

/// A closed GeoJSON ring.
fn ring(points: &[[f64; 2]]) -> Value {
    let mut v: Vec<Value> = points.iter().map(|p| json!([p[0], p[1]])).collect();
    v.push(json!([points[0][0], points[0][1]]));
    Value::Array(v)
}

fn square(x: f64, y: f64, s: f64) -> Vec<[f64; 2]> {
    vec![[x, y], [x + s, y], [x + s, y + s], [x, y + s]]
}

fn feature(name: &str, value: f64, geometry: Value) -> Value {
    json!({"type": "Feature", "properties": {"name": name, "pop": value}, "geometry": geometry})
}

/// An n×n grid of unit squares: the centre square has a square hole (a lake), the squares
/// (0, 0) and (n−1, n−1) are one MultiPolygon, values spread over 1..10.
fn grid(n: usize) -> Value {
    let mut features = Vec::new();
    let mut k = 0;
    for i in 0..n {
        for j in 0..n {
            if (i, j) == (n - 1, n - 1) {
                continue;
            }
            let value = 1.0 + ((k * 7) % 10) as f64;
            k += 1;
            let (x, y) = (i as f64, j as f64);
            let g = if (i, j) == (0, 0) {
                let last = (n - 1) as f64;
                json!({"type": "MultiPolygon", "coordinates": [
                    [ring(&square(x, y, 1.0))], [ring(&square(last, last, 1.0))]]})
            } else if (i, j) == (n / 2, n / 2) {
                let mut hole = square(x + 0.3, y + 0.3, 0.4);
                hole.reverse();
                json!({"type": "Polygon", "coordinates": [ring(&square(x, y, 1.0)), ring(&hole)]})
            } else {
                json!({"type": "Polygon", "coordinates": [ring(&square(x, y, 1.0))]})
            };
            features.push(feature(&format!("r{i}_{j}"), value, g));
        }
    }
    json!({"type": "FeatureCollection", "features": features})
}

/// A deterministic pseudo-random sequence in [0, 1).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// An n×n grid with jittered corners (each shared by up to four cells) and every edge bent
/// at a shared midpoint: irregular country-like cells, values over 1..10 (log-uniform).
fn irregular(n: usize, seed: u64) -> Value {
    let mut rng = Lcg(seed);
    let mut corner = vec![[0.0; 2]; (n + 1) * (n + 1)];
    for i in 0..=n {
        for j in 0..=n {
            let jx = if i == 0 || i == n {
                0.0
            } else {
                0.6 * rng.next() - 0.3
            };
            let jy = if j == 0 || j == n {
                0.0
            } else {
                0.6 * rng.next() - 0.3
            };
            corner[i * (n + 1) + j] = [i as f64 + jx, j as f64 + jy];
        }
    }
    let mut mids = std::collections::HashMap::new();
    let mut features = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let cs = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let mut pts = Vec::new();
            for k in 0..4 {
                let (a, b) = (cs[k], cs[(k + 1) % 4]);
                let (pa, pb) = (corner[a.0 * (n + 1) + a.1], corner[b.0 * (n + 1) + b.1]);
                let key = if a < b { (a, b) } else { (b, a) };
                let off = 0.2 * rng.next() - 0.1;
                let m = *mids.entry(key).or_insert_with(|| {
                    let d = [pb[0] - pa[0], pb[1] - pa[1]];
                    [
                        0.5 * (pa[0] + pb[0]) - off * d[1],
                        0.5 * (pa[1] + pb[1]) + off * d[0],
                    ]
                });
                pts.push(pa);
                pts.push(m);
            }
            let value = 10f64.powf(rng.next());
            let g = json!({"type": "Polygon", "coordinates": [ring(&pts)]});
            features.push(feature(&format!("c{i}_{j}"), value, g));
        }
    }
    json!({"type": "FeatureCollection", "features": features})
}

/// A feature's polygons as rings without the closing point.
fn polygons(f: &Value) -> Vec<Vec<Ring>> {
    let g = &f["geometry"];
    let coords = &g["coordinates"];
    let polys: Vec<&Value> = match g["type"].as_str().unwrap() {
        "Polygon" => vec![coords],
        "MultiPolygon" => coords.as_array().unwrap().iter().collect(),
        t => panic!("unexpected geometry {t}"),
    };
    polys
        .into_iter()
        .map(|p| {
            p.as_array()
                .unwrap()
                .iter()
                .map(|r| {
                    let pts: Ring = r
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|q| [q[0].as_f64().unwrap(), q[1].as_f64().unwrap()])
                        .collect();
                    assert_eq!(pts.first(), pts.last(), "ring not closed");
                    pts[..pts.len() - 1].to_vec()
                })
                .collect()
        })
        .collect()
}

fn ring_area(r: &[[f64; 2]]) -> f64 {
    (0..r.len())
        .map(|i| {
            let (p, q) = (r[i], r[(i + 1) % r.len()]);
            p[0] * q[1] - p[1] * q[0]
        })
        .sum::<f64>()
        / 2.0
}

fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

fn inside(rings: &[Ring], c: [f64; 2]) -> bool {
    let mut odd = false;
    for r in rings {
        for i in 0..r.len() {
            let (a, b) = (r[i], r[(i + 1) % r.len()]);
            if (a[1] > c[1]) != (b[1] > c[1])
                && a[0] + (c[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]) > c[0]
            {
                odd = !odd;
            }
        }
    }
    odd
}

fn key(p: [f64; 2]) -> (u64, u64) {
    (p[0].to_bits(), p[1].to_bits())
}

/// The figures the acceptance asks for.
#[derive(Debug)]
struct Figures {
    median: f64,
    worst: f64,
    /// Every region's share error |A_i/ΣA − v_i/Σv| / (v_i/Σv), signed.
    share_errors: Vec<f64>,
    crossings: usize,
    contained: usize,
    boundary_loops: usize,
    gap_area: f64,
}

/// Checks the output against the input: same features, properties and ring structure; rings
/// oriented (exterior counter-clockwise, holes clockwise) without repeated vertices; counts
/// crossing edges and regions inside others; the loops of edges used by one ring only (the
/// union's boundary); area/value errors relative to the mean ratio.
fn figures(input: &Value, output: &Value) -> Figures {
    let fin = input["features"].as_array().unwrap();
    let fout = output["features"].as_array().unwrap();
    assert_eq!(fin.len(), fout.len());
    let mut regions = Vec::new();
    let mut ratios = Vec::new();
    for (a, b) in fin.iter().zip(fout) {
        assert_eq!(a["properties"], b["properties"]);
        assert_eq!(a["geometry"]["type"], b["geometry"]["type"]);
        let (pa, pb) = (polygons(a), polygons(b));
        assert_eq!(pa.len(), pb.len());
        let mut area = 0.0;
        for (ra, rb) in pa.iter().zip(&pb) {
            assert_eq!(ra.len(), rb.len(), "ring count");
            for (j, r) in rb.iter().enumerate() {
                let s = ring_area(r);
                assert!(if j == 0 { s > 0.0 } else { s < 0.0 }, "ring orientation");
                let mut keys: Vec<_> = r.iter().map(|&p| key(p)).collect();
                keys.sort();
                keys.dedup();
                assert_eq!(keys.len(), r.len(), "a ring repeats a vertex");
                area += s;
            }
        }
        ratios.push(area / a["properties"]["pop"].as_f64().unwrap());
        regions.push(pb);
    }
    // Edges (undirected, by exact coordinates) and how many ring sides use them.
    type EdgeKey = ((u64, u64), (u64, u64));
    let mut uses: std::collections::HashMap<EdgeKey, ([f64; 2], [f64; 2], usize)> =
        Default::default();
    for r in regions.iter().flatten().flatten() {
        for i in 0..r.len() {
            let (p, q) = (r[i], r[(i + 1) % r.len()]);
            let (kp, kq) = (key(p), key(q));
            let k = if kp < kq { (kp, kq) } else { (kq, kp) };
            uses.entry(k).or_insert((p, q, 0)).2 += 1;
        }
    }
    let edges: Vec<_> = uses.values().copied().collect();
    assert!(
        edges.iter().all(|e| e.2 <= 2),
        "an edge used by three rings"
    );
    let mut crossings = 0;
    for i in 0..edges.len() {
        for j in i + 1..edges.len() {
            let ((a, b, _), (c, d, _)) = (edges[i], edges[j]);
            if a == c || a == d || b == c || b == d {
                continue;
            }
            if orient(a, b, c) * orient(a, b, d) <= 0.0 && orient(c, d, a) * orient(c, d, b) <= 0.0
            {
                crossings += 1;
            }
        }
    }
    // A point just inside each polygon must lie in no other region.
    let mut contained = 0;
    for (ri, polys) in regions.iter().enumerate() {
        for rings in polys {
            let r = &rings[0];
            let (a, b) = (r[0], r[1]);
            let d = [b[0] - a[0], b[1] - a[1]];
            let eps = 1e-6;
            let p = [
                0.5 * (a[0] + b[0]) - eps * d[1],
                0.5 * (a[1] + b[1]) + eps * d[0],
            ];
            assert!(inside(rings, p));
            for (rj, other) in regions.iter().enumerate() {
                if rj != ri && other.iter().any(|o| inside(o, p)) {
                    contained += 1;
                }
            }
        }
    }
    // Loops of single-use edges (union–find over their end points).
    let single: Vec<_> = edges.iter().filter(|e| e.2 == 1).collect();
    let mut id = std::collections::HashMap::new();
    let mut parent: Vec<usize> = Vec::new();
    fn find(parent: &mut [usize], x: usize) -> usize {
        let mut x = x;
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    for e in &single {
        for p in [e.0, e.1] {
            id.entry(key(p)).or_insert_with(|| {
                parent.push(parent.len());
                parent.len() - 1
            });
        }
        let (x, y) = (id[&key(e.0)], id[&key(e.1)]);
        let (rx, ry) = (find(&mut parent, x), find(&mut parent, y));
        parent[rx] = ry;
    }
    let boundary_loops = (0..parent.len())
        .filter(|&x| find(&mut parent, x) == x)
        .count();
    // Area enclosed by the union's boundary (oriented by the rings) minus the regions' areas.
    let total: f64 = regions
        .iter()
        .flatten()
        .flatten()
        .map(|r| ring_area(r))
        .sum();
    let mut enclosed = 0.0;
    for r in regions.iter().flatten().flatten() {
        for i in 0..r.len() {
            let (p, q) = (r[i], r[(i + 1) % r.len()]);
            let (kp, kq) = (key(p), key(q));
            let k = if kp < kq { (kp, kq) } else { (kq, kp) };
            if uses[&k].2 == 1 {
                enclosed += 0.5 * (p[0] * q[1] - p[1] * q[0]);
            }
        }
    }
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    let mut err: Vec<f64> = ratios.iter().map(|r| (r / mean - 1.0).abs()).collect();
    err.sort_by(f64::total_cmp);
    // Share errors: ratio_i / (ΣA / Σv) − 1.
    let values: Vec<f64> = fin
        .iter()
        .map(|f| f["properties"]["pop"].as_f64().unwrap())
        .collect();
    let area_total: f64 = ratios.iter().zip(&values).map(|(r, v)| r * v).sum();
    let value_total: f64 = values.iter().sum();
    let share_errors = ratios
        .iter()
        .map(|r| r / (area_total / value_total) - 1.0)
        .collect();
    Figures {
        median: err[err.len() / 2],
        worst: err[err.len() - 1],
        share_errors,
        crossings,
        contained,
        boundary_loops,
        gap_area: (enclosed - total).abs() / total,
    }
}

/// Every position of a FeatureCollection mapped by `f`.
fn map_positions(v: &Value, f: &dyn Fn([f64; 2]) -> [f64; 2]) -> Value {
    match v {
        Value::Array(a) if a.len() == 2 && a.iter().all(Value::is_number) => {
            let p = f([a[0].as_f64().unwrap(), a[1].as_f64().unwrap()]);
            json!([p[0], p[1]])
        }
        Value::Array(a) => Value::Array(a.iter().map(|x| map_positions(x, f)).collect()),
        Value::Object(o) => Value::Object(
            o.iter()
                .map(|(k, x)| {
                    let x = if k == "properties" {
                        x.clone()
                    } else {
                        map_positions(x, f)
                    };
                    (k.clone(), x)
                })
                .collect(),
        ),
        other => other.clone(),
    }
}

fn run_cartogram(s: &Scratch, input: &Value, extra: &[&str]) -> (Value, Value) {
    s.write("in.geojson", input.to_string());
    let mut args = vec![
        "cartogram",
        "in.geojson",
        "--value",
        "pop",
        "--out",
        "out.geojson",
        "--svg",
        "out.svg",
        "--report",
        "r.json",
        "--quiet",
    ];
    args.extend_from_slice(extra);
    s.ok(&args);
    let out: Value = serde_json::from_str(&s.read("out.geojson")).unwrap();
    let report: Value = serde_json::from_str(&s.read("r.json")).unwrap();
    (out, report)
}

#[test]
fn grid_with_a_hole_and_a_multipolygon_meets_the_acceptance_figures() {
    let s = Scratch::new("carto_grid");
    let input = grid(5);
    let (out, report) = run_cartogram(&s, &input, &[]);
    let f = figures(&input, &out);
    eprintln!("{f:?}");
    assert_eq!(f.crossings, 0, "{f:?}");
    assert_eq!(f.contained, 0, "{f:?}");
    // The outer boundary and the lake's shore, nothing else: borders are shared exactly.
    assert_eq!(f.boundary_loops, 2, "{f:?}");
    assert!(f.gap_area < 1e-9, "{f:?}");
    assert!(f.median <= 0.05 && f.worst <= 0.15, "{f:?}");
    assert_eq!(report["flipped_triangles"], 0);
    assert_eq!(report["invalid_polygons"], 0);
    assert_eq!(report["regions"].as_array().unwrap().len(), 24);
    assert!(report.get("ratio_error_worst").is_none());
    for (r, e) in report["regions"]
        .as_array()
        .unwrap()
        .iter()
        .zip(&f.share_errors)
    {
        assert!((r["error"].as_f64().unwrap() - e).abs() < 1e-9, "{r} {e}");
        assert!(r.get("ratio_error").is_none());
    }
    let svg = s.read("out.svg");
    assert_eq!(svg.matches("<path").count(), 24);
}

#[test]
fn irregular_regions_with_vertices_shared_by_four_meet_the_same_figures() {
    let s = Scratch::new("carto_irregular");
    let input = irregular(9, 7);
    let (out, _) = run_cartogram(&s, &input, &[]);
    let f = figures(&input, &out);
    eprintln!("{f:?}");
    assert_eq!(
        (f.crossings, f.contained, f.boundary_loops),
        (0, 0, 1),
        "{f:?}"
    );
    assert!(f.gap_area < 1e-9, "{f:?}");
    assert!(f.median <= 0.05 && f.worst <= 0.15, "{f:?}");
}

#[test]
fn sphere_grid_in_degrees_meets_the_figures_on_the_globe() {
    let s = Scratch::new("carto_sphere");
    // The acceptance grid as 10° cells from 20° W to 30° E and 5° N to 55° N.
    let input = map_positions(&grid(5), &|p| [10.0 * p[0] - 20.0, 10.0 * p[1] + 5.0]);
    let (out, report) = run_cartogram(&s, &input, &["--sphere"]);
    assert_eq!(report["method"], "flow_sphere");
    assert_eq!(report["flipped_triangles"], 0);
    // Lambert's cylindrical projection (longitude in radians, sine of latitude) keeps areas:
    // the planar figures of the projected rings are those on the globe.
    let lambert = |p: [f64; 2]| [p[0].to_radians(), p[1].to_radians().sin()];
    let f = figures(
        &map_positions(&input, &lambert),
        &map_positions(&out, &lambert),
    );
    eprintln!("{f:?}");
    assert_eq!(
        (f.crossings, f.contained, f.boundary_loops),
        (0, 0, 2),
        "{f:?}"
    );
    assert!(f.gap_area < 1e-9, "{f:?}");
    assert!(f.median <= 0.05 && f.worst <= 0.15, "{f:?}");
    // Still where it was: every output position within 20° of the grid.
    let text = s.read("out.geojson");
    let back: Value = serde_json::from_str(&text).unwrap();
    map_positions(&back, &|p| {
        assert!(
            (-40.0..=50.0).contains(&p[0]) && (-15.0..=75.0).contains(&p[1]),
            "{p:?}"
        );
        p
    });
}

#[test]
fn refusals_exit_2_naming_the_feature() {
    let s = Scratch::new("carto_refuse");
    let base = grid(3);
    let with = |k: usize, prop: Value| {
        let mut v = base.clone();
        v["features"][k]["properties"]["pop"] = prop;
        v
    };
    let mut point = base.clone();
    point["features"][1]["geometry"] = json!({"type": "Point", "coordinates": [0.5, 0.5]});
    let mut bow = base.clone();
    bow["features"][3]["geometry"] = json!({"type": "Polygon", "coordinates":
        [ring(&[[1.0, 0.0], [2.0, 1.0], [2.0, 0.0], [1.0, 0.5]])]});
    let mut overlap = base.clone();
    overlap["features"][4]["geometry"] =
        json!({"type": "Polygon", "coordinates": [ring(&square(0.5, 0.5, 1.0))]});
    let cases: Vec<(Value, &str)> = vec![
        (
            with(1, json!(-3)),
            "feature 1 (name 'r0_1'): its value 'pop' = -3 is negative",
        ),
        (
            with(2, json!("many")),
            "feature 2 (name 'r0_2'): its value 'pop' = \"many\" is not a number",
        ),
        (with(2, json!("NaN")), "is not finite"),
        (point, "feature 1 (name 'r0_1'): its geometry is a Point"),
        (bow, "feature 3 (name 'r1_0'): its boundary crosses itself"),
        (overlap, "overlaps"),
        (
            json!({"type": "Feature", "properties": {}, "geometry": null}),
            "not a FeatureCollection",
        ),
    ];
    for (input, want) in cases {
        s.write("bad.geojson", input.to_string());
        let out = s.run(&[
            "cartogram",
            "bad.geojson",
            "--value",
            "pop",
            "--out",
            "o.geojson",
        ]);
        out.assert_code(2);
        let line = out.stderr.trim();
        assert!(
            line.starts_with("error: ") && line.contains(want),
            "{line} / {want}"
        );
        assert_eq!(line.lines().count(), 1, "{line}");
    }
    // Latitudes beyond the pole with --sphere.
    let mut polar = base.clone();
    polar["features"][0]["geometry"] = json!({"type": "Polygon", "coordinates": [ring(&[[0.0, 80.0], [10.0, 80.0], [10.0, 95.0]])]});
    s.write("polar.geojson", polar.to_string());
    let out = s.run(&[
        "cartogram",
        "polar.geojson",
        "--value",
        "pop",
        "--out",
        "o.geojson",
        "--sphere",
    ]);
    out.assert_code(2);
    assert!(
        out.stderr.contains("latitude 95 is outside [-90, 90]"),
        "{}",
        out.stderr
    );
    // Output names that would not hold what is written there.
    s.write("good.geojson", base.to_string());
    let e = s
        .run(&[
            "cartogram",
            "good.geojson",
            "--value",
            "pop",
            "--out",
            "o.obj",
        ])
        .input_error();
    assert!(e.contains(".geojson"), "{e}");
    let e = s
        .run(&[
            "cartogram",
            "good.geojson",
            "--value",
            "pop",
            "--out",
            "o.geojson",
            "--svg",
            "o.png",
        ])
        .input_error();
    assert!(e.contains(".svg"), "{e}");
}

/// An nx × ny grid of touching unit squares with values over 1..10 (log-uniform), the shape
/// of a choropleth map of many small regions.
fn many_squares(nx: usize, ny: usize) -> Value {
    let mut rng = Lcg(11);
    let mut features = Vec::with_capacity(nx * ny);
    for i in 0..nx {
        for j in 0..ny {
            let g = json!({"type": "Polygon",
                "coordinates": [ring(&square(i as f64, j as f64, 1.0))]});
            features.push(feature(&format!("s{i}_{j}"), 10f64.powf(rng.next()), g));
        }
    }
    json!({"type": "FeatureCollection", "features": features})
}

/// Runs a cartogram of `input` with `extra` arguments; returns the report and the seconds.
fn timed_cartogram(s: &Scratch, input: &Value, extra: &[&str]) -> (Value, f64) {
    s.write("many.geojson", input.to_string());
    let mut args = vec![
        "cartogram",
        "many.geojson",
        "--value",
        "pop",
        "--out",
        "many-out.geojson",
        "--report",
        "many.json",
        "--quiet",
    ];
    args.extend_from_slice(extra);
    let t0 = std::time::Instant::now();
    s.ok(&args);
    let seconds = t0.elapsed().as_secs_f64();
    (serde_json::from_str(&s.read("many.json")).unwrap(), seconds)
}

#[test]
fn four_hundred_squares_reach_their_shares_within_one_percent() {
    let s = Scratch::new("carto_cap");
    // 400 squares with values over 1..10: the flow on its default grid brings every share
    // within 1 % of its target (exit 0 says so), with the shares summing to 1.
    let input = many_squares(20, 20);
    let (report, seconds) = timed_cartogram(&s, &input, &[]);
    eprintln!(
        "{seconds:.1} s, grid {}, mean {} max {}",
        report["grid"], report["error_mean"], report["error_max"]
    );
    assert_eq!(report["converged"], true);
    assert_eq!(report["grid"][0], 1024);
    assert_eq!(report["flipped_triangles"], 0);
    let max = report["error_max"].as_f64().unwrap();
    assert!(max <= 0.01, "{max}");
    let (median, worst) = median_and_worst_share_error(&report);
    assert!(median < 0.02, "{median}");
    assert!(worst < 0.15, "{worst}");
    let regions = report["regions"].as_array().unwrap();
    let target: f64 = regions
        .iter()
        .map(|r| r["target_share"].as_f64().unwrap())
        .sum();
    let reached: f64 = regions
        .iter()
        .map(|r| r["output_share"].as_f64().unwrap())
        .sum();
    assert!((target - 1.0).abs() < 1e-9 && (reached - 1.0).abs() < 1e-9);
    // Each region's error is the relative error of its share.
    for r in regions {
        let (t, o) = (
            r["target_share"].as_f64().unwrap(),
            r["output_share"].as_f64().unwrap(),
        );
        assert!((r["error"].as_f64().unwrap() - (o / t - 1.0)).abs() < 1e-9);
    }
}

#[test]
#[ignore = "heavy: 10 000 regions (about 6 s in release on a 2-core machine)"]
fn ten_thousand_regions_reach_their_shares() {
    let s = Scratch::new("carto_10k");
    let input = many_squares(100, 100);
    let (report, seconds) = timed_cartogram(&s, &input, &[]);
    let faces = report["mesh"]["faces"].as_u64().unwrap();
    let (median, worst) = median_and_worst_share_error(&report);
    eprintln!(
        "{faces} faces, {seconds:.1} s, {} iterations in {} rounds, median {median} worst {worst}",
        report["iterations"], report["rounds"],
    );
    assert_eq!(faces, 0, "the flow has no mesh");
    assert_eq!(report["grid"][0], 1024);
    assert!(report["error_max"].as_f64().unwrap() < 0.3);
    assert_eq!(report["flipped_triangles"], 0);
    assert_eq!(report["regions"].as_array().unwrap().len(), 10_000);
    assert!(median < 0.05, "{median}");
    assert!(worst < 0.3, "{worst}");
}

/// The median and largest |share error| over all regions of a report.
fn median_and_worst_share_error(report: &Value) -> (f64, f64) {
    let mut e: Vec<f64> = report["regions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["error"].as_f64().unwrap().abs())
        .collect();
    e.sort_by(f64::total_cmp);
    (e[e.len() / 2], e[e.len() - 1])
}

#[test]
fn bad_controls_are_refused_up_front_naming_the_option() {
    let s = Scratch::new("carto_controls");
    s.write("g.geojson", grid(3).to_string());
    let run = |extra: &[&str]| {
        let mut args = vec![
            "cartogram",
            "g.geojson",
            "--value",
            "pop",
            "--out",
            "o.geojson",
        ];
        args.extend_from_slice(extra);
        s.run(&args)
    };
    let t0 = std::time::Instant::now();
    run(&["--grid", "100"]).input_error_naming(&["--grid", "power of two", "got 100"]);
    run(&["--grid", "8"]).input_error_naming(&["--grid", "got 8"]);
    run(&["--grid", "16384"]).input_error_naming(&["--grid", "got 16384"]);
    run(&["--grid", "-4"]).input_error_naming(&["--grid"]);
    run(&["--max-error", "0"]).input_error_naming(&["--max-error", "got 0"]);
    run(&["--max-error", "-0.1"]).input_error_naming(&["--max-error"]);
    run(&["--max-error", "NaN"]).input_error_naming(&["--max-error"]);
    run(&["--time-limit", "-1"]).input_error_naming(&["--time-limit", "got -1"]);
    run(&["--time-limit", "inf"]).input_error_naming(&["--time-limit"]);
    // The mesh of the former engine is gone, and its option with it.
    run(&["--faces", "20000"]).input_error_naming(&["--faces"]);
    eprintln!("ten refusals in {:.2} s", t0.elapsed().as_secs_f64());
    assert!(!s.path("o.geojson").exists());
}

/// Checks a cartogram of the 5×5 grid scaled by `k`: exit 0, the output in the input's units
/// (it covers about the same box), and, brought back to unit size, the acceptance figures.
fn scaled_grid_works(k: f64, label: &str) {
    let s = Scratch::new(label);
    let unit = grid(5);
    let input = map_positions(&unit, &|p| [k * p[0], k * p[1]]);
    let (out, report) = run_cartogram(&s, &input, &[]);
    assert_eq!(report["flipped_triangles"], 0);
    let bounds = std::cell::Cell::new(([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]));
    map_positions(&out, &|p| {
        assert!(p[0].is_finite() && p[1].is_finite(), "{p:?}");
        p
    });
    let back = map_positions(&out, &|p| [p[0] / k, p[1] / k]);
    map_positions(&back, &|p| {
        let (mut lo, mut hi) = bounds.get();
        for c in 0..2 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
        bounds.set((lo, hi));
        p
    });
    let (lo, hi) = bounds.get();
    // The unit grid spans [0, 5]²; its cartogram stays near that box.
    assert!(
        lo[0] > -2.0 && lo[1] > -2.0 && hi[0] < 7.0 && hi[1] < 7.0,
        "{lo:?} {hi:?}"
    );
    let f = figures(&unit, &back);
    eprintln!("{k:e}: {f:?}");
    assert_eq!(
        (f.crossings, f.contained, f.boundary_loops),
        (0, 0, 2),
        "{f:?}"
    );
    assert!(f.median <= 0.05 && f.worst <= 0.15, "{f:?}");
    for (r, e) in report["regions"]
        .as_array()
        .unwrap()
        .iter()
        .zip(&f.share_errors)
    {
        let reported = r["error"].as_f64().unwrap();
        assert!((reported - e).abs() < 1e-6, "{reported} vs {e}");
    }
}

#[test]
fn squares_of_side_1e300_are_computed_like_unit_squares() {
    scaled_grid_works(1e300, "carto_1e300");
}

#[test]
fn squares_of_side_1e_300_are_computed_like_unit_squares() {
    scaled_grid_works(1e-300, "carto_1e-300");
}

/// The 3×3 grid (8 features) with a join key `code` (`C0`…`C7`) on every feature.
fn keyed_grid() -> Value {
    let mut v = grid(3);
    for (k, f) in v["features"].as_array_mut().unwrap().iter_mut().enumerate() {
        f["properties"]["code"] = json!(format!("C{k}"));
    }
    v
}

/// Runs `demkit cartogram in.geojson ARGS --out o.geojson --report r.json --grid 64`.
fn run_small(s: &Scratch, args: &[&str]) -> common::Output {
    let mut all = vec!["cartogram", "in.geojson"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--out", "o.geojson", "--report", "r.json", "--grid", "64"]);
    s.run(&all)
}

fn report_values(s: &Scratch) -> Vec<f64> {
    let report: Value = serde_json::from_str(&s.read("r.json")).unwrap();
    report["regions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["value"].as_f64().unwrap())
        .collect()
}

#[test]
fn values_from_a_csv_are_joined_on_a_key() {
    let s = Scratch::new("carto_csv");
    s.write("in.geojson", keyed_grid().to_string());
    // Rows in another order than the features, one row for no feature.
    let mut csv = String::from("code,people\n");
    for k in (0..8).rev() {
        csv.push_str(&format!("C{k},{}\n", 10 * (k + 1)));
    }
    csv.push_str("ZZ,5\n");
    s.write("v.csv", &csv);
    let out = run_small(&s, &["--values", "v.csv", "--key", "code"]);
    out.assert_code(0);
    let want: Vec<f64> = (0..8).map(|k| 10.0 * (k + 1) as f64).collect();
    assert_eq!(report_values(&s), want);
    assert!(
        out.stderr
            .contains("1 rows match no feature's 'code': 'ZZ'"),
        "{}",
        out.stderr
    );
    // With more columns, --value names the one to use.
    let mut csv = String::from("name,code,gdp,people\n");
    for k in 0..8 {
        csv.push_str(&format!("n{k},C{k},1,{}\n", k + 1));
    }
    s.write("w.csv", &csv);
    run_small(
        &s,
        &[
            "--values", "w.csv", "--key", "code", "--value", "people", "--quiet",
        ],
    )
    .assert_code(0);
    assert_eq!(
        report_values(&s),
        (1..=8).map(f64::from).collect::<Vec<_>>()
    );
    // Refusals name the file and the line.
    let cases: Vec<(&str, &[&str], Vec<&str>)> = vec![
        (
            "id,people\nC0,1\n",
            &[],
            vec!["bad.csv:1:", "no column 'code' (--key)"],
        ),
        (
            "code,a,b\nC0,1,2\n",
            &[],
            vec!["bad.csv:1:", "2 columns besides 'code'", "--value"],
        ),
        (
            "code,people\nC0,1\n",
            &["--value", "pop"],
            vec!["no column 'pop' (--value)"],
        ),
        (
            "code,people\nC0,1\nC1,lots\n",
            &[],
            vec![
                "bad.csv:3:",
                "'C1': the value 'people' = 'lots' is not a number",
            ],
        ),
        (
            "code,people\nC0,1\nC1,2\nC0,3\n",
            &[],
            vec!["bad.csv:4:", "the key 'C0' is repeated (first on line 2)"],
        ),
        ("code,people\nC0,-1\n", &[], vec!["bad.csv:2:", "negative"]),
    ];
    for (text, extra, needles) in cases {
        s.write("bad.csv", text);
        let mut args = vec!["--values", "bad.csv", "--key", "code"];
        args.extend_from_slice(extra);
        run_small(&s, &args).input_error_naming(&needles);
    }
    // --key needs --values and the other way round; the CSV may not be an output.
    run_small(&s, &["--value", "pop", "--key", "code"]).input_error_naming(&["--values"]);
    run_small(&s, &["--values", "v.csv"]).input_error_naming(&["--key"]);
    s.run(&[
        "cartogram",
        "in.geojson",
        "--values",
        "v.csv",
        "--key",
        "code",
        "--out",
        "o.geojson",
        "--report",
        "v.csv",
    ])
    .input_error_naming(&["--report v.csv would replace the input --values"]);
    assert!(s.read("v.csv").starts_with("code,people"));
    s.run(&[
        "cartogram",
        "in.geojson",
        "--values",
        "nowhere.csv",
        "--key",
        "code",
        "--out",
        "o.geojson",
    ])
    .input_error_naming(&["nowhere.csv"]);
}

#[test]
fn missing_and_zero_values_are_completed_with_a_warning_naming_the_regions() {
    let s = Scratch::new("carto_missing");
    let mut input = grid(3);
    // Feature 2 has no value, feature 5 a null one, feature 7 a zero; the others 1..10.
    input["features"][2]["properties"]
        .as_object_mut()
        .unwrap()
        .remove("pop");
    input["features"][5]["properties"]["pop"] = Value::Null;
    input["features"][7]["properties"]["pop"] = json!(0);
    s.write("in.geojson", input.to_string());
    // The point is the values: an accuracy the coarse grid meets for the tiny zero region.
    let out = run_small(&s, &["--value", "pop", "--max-error", "0.05"]);
    out.assert_code(0);
    assert!(
        out.stderr.contains(
            "2 regions have no value and get the mean density (value per area) of the others: \
             feature 2 (name 'r0_2'), feature 5 (name 'r1_2')"
        ),
        "{}",
        out.stderr
    );
    assert!(
        out.stderr.contains(
            "1 regions have the value 0 and get 0.2 times the smallest positive value: \
             feature 7 (name 'r2_1')"
        ),
        "{}",
        out.stderr
    );
    let values = report_values(&s);
    let given: Vec<f64> = [0, 1, 3, 4, 6]
        .iter()
        .map(|&k| input["features"][k]["properties"]["pop"].as_f64().unwrap())
        .collect();
    // Their areas: feature 0 is two unit squares, feature 4 a unit square with a lake of
    // 0.4 × 0.4. The missing ones (unit squares) get the mean density; zero a fifth of the least.
    let area_given = 2.0 + 1.0 + 1.0 + 0.84 + 1.0;
    let mean = given.iter().sum::<f64>() / area_given;
    let least = given.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!(
        (values[2] - mean).abs() < 1e-9 && (values[5] - mean).abs() < 1e-9,
        "{values:?}"
    );
    assert!((values[7] - 0.2 * least).abs() < 1e-12, "{values:?}");
    // No positive value at all: refused.
    let mut none = grid(3);
    for f in none["features"].as_array_mut().unwrap() {
        f["properties"]["pop"] = json!(0);
    }
    s.write("in.geojson", none.to_string());
    run_small(&s, &["--value", "pop"]).input_error_naming(&["no region has a positive value"]);
    run_small(&s, &["--value", "typo"]).input_error_naming(&["no region has a value"]);
    // Negative and NaN values stay refused, naming the feature.
    let mut neg = grid(3);
    neg["features"][4]["properties"]["pop"] = json!("NaN");
    s.write("in.geojson", neg.to_string());
    run_small(&s, &["--value", "pop"])
        .input_error_naming(&["feature 4 (name 'r1_1')", "not finite"]);
}

/// The 3×3 grid as 10° cells from 10° W, 40° N.
fn degree_grid() -> Value {
    map_positions(&grid(3), &|p| [10.0 * p[0] - 10.0, 10.0 * p[1] + 40.0])
}

fn bounds(v: &Value) -> ([f64; 2], [f64; 2]) {
    let b = std::cell::Cell::new(([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]));
    map_positions(v, &|p| {
        let (mut lo, mut hi) = b.get();
        for c in 0..2 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
        b.set((lo, hi));
        p
    });
    b.get()
}

#[test]
fn project_computes_in_equal_earth_and_writes_km_or_degrees() {
    let s = Scratch::new("carto_project");
    s.write("in.geojson", degree_grid().to_string());
    // Without --project or --sphere, degrees get a warning naming both.
    let out = run_small(&s, &["--value", "pop"]);
    assert!(
        out.stderr.contains("look like longitude/latitude degrees")
            && out.stderr.contains("--project")
            && out.stderr.contains("--sphere"),
        "{}",
        out.stderr
    );
    let out = run_small(&s, &["--value", "pop", "--project"]);
    out.assert_code(0);
    assert!(!out.stderr.contains("look like"), "{}", out.stderr);
    let km: Value = serde_json::from_str(&s.read("o.geojson")).unwrap();
    let (lo, hi) = bounds(&km);
    // 30° of longitude at 40–70° N is some 1 500–2 600 km wide in Equal Earth.
    assert!(hi[0] - lo[0] > 1000.0 && hi[1] > 4000.0, "{lo:?} {hi:?}");
    let report: Value = serde_json::from_str(&s.read("r.json")).unwrap();
    assert!(report["error_max"].as_f64().unwrap() <= 0.01);
    assert_eq!(report["invalid_polygons"], 0);
    // Input areas are those on the globe, in km²: feature 1 is the 10° cell at 50–60° N.
    let r = 6371.0f64;
    let cell = r * r * 10f64.to_radians() * (60f64.to_radians().sin() - 50f64.to_radians().sin());
    let a0 = report["regions"][1]["input_area"].as_f64().unwrap();
    assert!((a0 / cell - 1.0).abs() < 1e-3, "{a0} vs {cell}");
    // Back in degrees: near where the grid was; shares measured in Equal Earth.
    run_small(
        &s,
        &["--value", "pop", "--project", "--output-lonlat", "--quiet"],
    )
    .assert_code(0);
    let deg: Value = serde_json::from_str(&s.read("o.geojson")).unwrap();
    let (lo, hi) = bounds(&deg);
    assert!(
        lo[0] > -25.0 && hi[0] < 35.0 && lo[1] > 30.0 && hi[1] < 80.0,
        "{lo:?} {hi:?}"
    );
    // Option combinations and latitudes beyond the poles.
    run_small(&s, &["--value", "pop", "--output-lonlat"]).input_error_naming(&["--project"]);
    run_small(&s, &["--value", "pop", "--project", "--sphere"]).input_error_naming(&["--sphere"]);
    let polar = map_positions(&grid(3), &|p| [p[0], 40.0 * p[1]]);
    s.write("in.geojson", polar.to_string());
    run_small(&s, &["--value", "pop", "--project"])
        .input_error_naming(&["latitude 120 is outside [-90, 90]", "--project"]);
}

#[test]
fn controls_take_effect() {
    let s = Scratch::new("carto_control_effect");
    s.write("in.geojson", grid(3).to_string());
    let read = || -> Value { serde_json::from_str(&s.read("r.json")).unwrap() };
    // The grid asked for is the grid used.
    run_small(&s, &["--value", "pop", "--quiet"]).assert_code(0);
    assert_eq!(read()["grid"][0], 64);
    // A loose accuracy is met sooner; the report keeps what was asked.
    run_small(&s, &["--value", "pop", "--quiet", "--max-error", "0.5"]).assert_code(0);
    let loose = read();
    assert_eq!(loose["max_error"], 0.5);
    assert!(loose["error_max"].as_f64().unwrap() <= 0.5);
    // No time for a round: exit 3 with the reason, outputs still written.
    let out = run_small(&s, &["--value", "pop", "--time-limit", "0"]);
    out.assert_code(3);
    assert!(out.stderr.contains("time limit"), "{}", out.stderr);
    let r = read();
    assert_eq!(r["converged"], false);
    assert!(r["notes"].to_string().contains("time limit"), "{r}");
    assert!(s.path("o.geojson").exists());
}

#[test]
fn pictures_are_coloured_with_a_legend() {
    let s = Scratch::new("carto_pictures");
    s.write("in.geojson", grid(3).to_string());
    let out = run_small(
        &s,
        &[
            "--value", "pop", "--quiet", "--svg", "o.svg", "--png", "o.png", "--size", "200",
        ],
    );
    out.assert_code(0);
    let svg = s.read("o.svg");
    assert_eq!(svg.matches("<path").count(), 8);
    assert!(svg.contains(">density</text>"), "{svg}");
    let png = tiny_skia::Pixmap::decode_png(&s.read_bytes("o.png")).unwrap();
    assert_eq!(png.width(), 200);
    // Colours by share error: the legend says so.
    run_small(
        &s,
        &[
            "--value", "pop", "--quiet", "--svg", "o.svg", "--color", "error",
        ],
    )
    .assert_code(0);
    assert!(s.read("o.svg").contains(">share error</text>"));
    // Refusals before any work: names, sizes, the same file twice.
    run_small(&s, &["--value", "pop", "--png", "o.svg"]).input_error_naming(&[".png"]);
    run_small(&s, &["--value", "pop", "--png", "p.png", "--size", "10"])
        .input_error_naming(&["--size"]);
    run_small(&s, &["--value", "pop", "--png", "r.json"]).input_error_naming(&[".png"]);
    run_small(
        &s,
        &[
            "--value", "pop", "--svg", "o.svg", "--png", "o.png", "--color", "rainbow",
        ],
    )
    .input_error_naming(&["--color"]);
    s.run(&[
        "cartogram",
        "in.geojson",
        "--value",
        "pop",
        "--out",
        "o.geojson",
        "--png",
        "x.png",
        "--report",
        "./x.png",
    ])
    .input_error_naming(&["--png and --report"]);
}

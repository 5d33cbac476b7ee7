use super::super::geojson::RawRegion;
use super::*;
use std::collections::HashSet;

fn square(x: f64, y: f64, s: f64) -> Vec<[f64; 2]> {
    vec![[x, y], [x + s, y], [x + s, y + s], [x, y + s]]
}

fn raw(polygons: Vec<Vec<Vec<[f64; 2]>>>, label: &str) -> RawRegion {
    RawRegion {
        label: label.into(),
        value: 1.0,
        multi: false,
        polygons,
    }
}

fn res(base_faces: usize) -> Resolution {
    Resolution {
        base_faces,
        polygon_faces: 100,
        max_faces: 1_000_000,
    }
}

fn area(p: &[[f64; 2]], f: [u32; 3]) -> f64 {
    let [a, b, c] = f.map(|v| p[v as usize]);
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

#[test]
fn faces_tile_regions_and_sea_exactly() {
    // A 3×3 square with a 1×1 hole, and a unit square beside it.
    let a = raw(
        vec![vec![square(0.0, 0.0, 3.0), square(1.0, 1.0, 1.0)]],
        "A",
    );
    let b = raw(vec![vec![square(3.0, 0.0, 1.0)]], "B");
    let set = RegionSet::build(&[a, b], "t").unwrap();
    let m = RegionMesh::build(&set, &res(2000), "t").unwrap();
    assert!(
        m.faces.len() > 1000 && m.faces.len() < 4000,
        "{}",
        m.faces.len()
    );
    // Areas in input units (the mesh is in the set's normalised frame).
    let input: Vec<[f64; 2]> = m.points.iter().map(|&p| set.frame.to_input(p)).collect();
    let mut per = [0.0; 3];
    for (f, r) in m.faces.iter().zip(&m.face_region) {
        let a = area(&input, *f);
        assert!(a > 0.0);
        per[r.map_or(2, |r| r)] += a;
    }
    assert!(
        (per[0] - 8.0).abs() < 1e-9 && (per[1] - 1.0).abs() < 1e-9,
        "{per:?}"
    );
    // Frame: 4 × 3 box with a margin of 0.8 on each side.
    assert!((per[0] + per[1] + per[2] - 5.6 * 4.6).abs() < 1e-9);
    // The shared edge (3,0)–(3,1) is a chain of mesh edges with the same points both ways.
    let ring_a = &set.regions[0].polygons[0][0];
    let dense = m.dense_ring(ring_a);
    assert!(dense.len() > 30);
    for w in dense.windows(2) {
        let has = m.faces.iter().any(|f| {
            (0..3).any(|k| {
                let (p, q) = (f[k] as usize, f[(k + 1) % 3] as usize);
                (p, q) == (w[0], w[1]) || (p, q) == (w[1], w[0])
            })
        });
        assert!(has, "ring piece {w:?} is not a mesh edge");
    }
}

#[test]
fn subdivision_follows_the_spacing() {
    let mut points = vec![[0.0, 0.0], [1.0, 0.0]];
    let mut segs = Vec::new();
    // Constant spacing 0.3 on a unit segment: three pieces of 1/3.
    let chain = subdivide(&mut points, 0, 1, &|_| 0.3, &mut segs);
    assert_eq!(chain.len(), 2);
    assert!((points[2][0] - 1.0 / 3.0).abs() < 1e-12 && (points[3][0] - 2.0 / 3.0).abs() < 1e-12);
    assert_eq!(segs, vec![[0, 2], [2, 3], [3, 1]]);
    // Spacing growing away from x = 0: pieces grow along the segment.
    let chain = subdivide(&mut points, 0, 1, &|p| 0.01 + 0.5 * p[0], &mut segs);
    let xs: Vec<f64> = chain.iter().map(|&v| points[v][0]).collect();
    assert!(xs.len() > 5 && xs.len() < 20, "{xs:?}");
    assert!(xs.windows(3).all(|w| w[2] - w[1] > w[1] - w[0]), "{xs:?}");
}

#[test]
fn a_small_region_gets_a_finer_mesh() {
    // A 0.05-wide square in the corner of a 4×4 block: at the block's spacing it would be
    // two triangles; the graded spacing gives it about MIN_POLYGON_FACES.
    let big = vec![
        [0.05, 0.0],
        [4.0, 0.0],
        [4.0, 4.0],
        [0.0, 4.0],
        [0.0, 0.05],
        [0.05, 0.05],
    ];
    let a = raw(vec![vec![big]], "big");
    let b = raw(vec![vec![square(0.0, 0.0, 0.05)]], "small");
    let set = RegionSet::build(&[a, b], "t").unwrap();
    let m = RegionMesh::build(&set, &res(2000), "t").unwrap();
    let n_small = m.face_region.iter().filter(|r| **r == Some(1)).count();
    assert!((50..400).contains(&n_small), "{n_small}");
    let small_area: f64 = m
        .faces
        .iter()
        .zip(&m.face_region)
        .filter(|(_, r)| **r == Some(1))
        .map(|(f, _)| set.frame.area_to_input(area(&m.points, *f)))
        .sum();
    assert!((small_area - 0.0025).abs() < 1e-12);
    let plain = RegionSet::build(&[raw(vec![vec![square(0.0, 0.0, 4.0)]], "big")], "t").unwrap();
    let n_plain = RegionMesh::build(&plain, &res(2000), "t")
        .unwrap()
        .faces
        .len();
    assert!(
        m.faces.len() < n_plain + 1000,
        "{} vs {n_plain}",
        m.faces.len()
    );
}

/// An n × n grid of unit squares.
fn squares(n: usize) -> RegionSet {
    let raws: Vec<RawRegion> = (0..n * n)
        .map(|i| raw(vec![vec![square((i / n) as f64, (i % n) as f64, 1.0)]], "s"))
        .collect();
    RegionSet::build(&raws, "t").unwrap()
}

#[test]
fn many_small_regions_share_the_cap_and_every_face_sees_its_region() {
    // 900 squares asking for 100 faces each (90 000) under a cap of 30 000.
    let set = squares(30);
    let r = Resolution {
        base_faces: 2000,
        polygon_faces: 100,
        max_faces: 30_000,
    };
    let m = RegionMesh::build(&set, &r, "t").unwrap();
    assert!(
        m.faces.len() as f64 <= CAP_SLACK * 30_000.0 && m.faces.len() > 15_000,
        "{} {:?}",
        m.faces.len(),
        m.plan
    );
    assert!(m.plan.polygon_faces < 100.0 && m.plan.polygon_faces >= MIN_POLYGON_FACES);
    // Every square has faces, and a vertex of its own inside.
    let mut faces = vec![0; set.regions.len()];
    let mut inner = vec![false; set.regions.len()];
    let on_ring: HashSet<u64> = (0..set.regions.len())
        .flat_map(|r| m.dense_ring(&set.regions[r].polygons[0][0]))
        .map(|v| v as u64)
        .collect();
    for (f, r) in m.faces.iter().zip(&m.face_region) {
        if let Some(r) = r {
            faces[*r] += 1;
            inner[*r] |= f.iter().any(|&v| !on_ring.contains(&(v as u64)));
        }
    }
    assert!(faces.iter().all(|&n| n >= 4), "{faces:?}");
    assert!(inner.iter().all(|&x| x));
    // Asking for more than the cap allows never places more than the cap's points, and the
    // same input gives the same mesh.
    let again = RegionMesh::build(&set, &r, "t").unwrap();
    assert_eq!(again.faces, m.faces);
}

#[test]
fn a_region_inside_another_is_an_overlap() {
    let a = raw(vec![vec![square(0.0, 0.0, 3.0)]], "feature 0");
    let b = raw(vec![vec![square(1.0, 1.0, 1.0)]], "feature 1");
    let set = RegionSet::build(&[a, b], "t").unwrap();
    let e = RegionMesh::build(&set, &res(500), "t")
        .unwrap_err()
        .to_string();
    assert!(e.contains("feature 0 overlaps feature 1"), "{e}");
}

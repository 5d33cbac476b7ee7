//! The cartogram's mesh: the regions and the sea around them triangulated as one disk (DEM
//! paper §6.1 with GN's sea, §3): a rectangle some margin beyond the regions' bounding box is
//! filled with points at a spacing that follows the regions' sizes, every region edge is split
//! into pieces about as long as the local spacing and kept as a chain of constrained edges,
//! and the constrained Delaunay triangulation of it all is taken. Every face then lies in
//! exactly one region or in the sea (gaps, lakes inside holes, the outside).
//!
//! The spacing ([`Resolution`]): a base spacing `h` over the frame, and every polygon that
//! would get fewer than `k` faces at `h` (a *small* polygon) gets its own spacing
//! `s = √(2 A / k)`: a hexagonal lattice of spacing `s` inside it and its edges split at `s`.
//! Around small polygons, in the sea and in larger polygons, the spacing grows back to `h`
//! along a graded quadtree ([`Sizing`]). The work and the mesh therefore follow the number of
//! polygons and their sizes, and the cap [`Resolution::max_faces`] bounds both: with many
//! small polygons `k` is lowered until the mesh fits.

mod assign;
mod sizing;

use super::buckets::Buckets;
use super::regions::{RegionSet, bbox, max2, min2};
use crate::geometry::segment::segment_distance;
use crate::mesh::triangulate::{constrained_delaunay, inside_loops};
use crate::{Error, Result};
pub(super) use assign::assign_faces;
use sizing::Sizing;
use std::collections::HashMap;

/// The sea's margin around the regions, as a fraction of their bounding box's larger side.
const MARGIN: f64 = 0.2;

/// Points closer than this fraction of the local spacing to a region edge or the frame are
/// left out (the edge's own points are there).
const CLEARANCE: f64 = 0.5;

/// Outside a small polygon, next to it, the spacing is at most this many times the polygon's
/// own (and grows from there): the sea and larger neighbours need no more points than that to
/// follow the polygon, and a sea between many small islands would otherwise cost as much as
/// the islands themselves.
const HALO: f64 = 2.0;

/// The cap lowers the faces per small polygon no further than this: below, a polygon has too
/// few points of its own for the map to resize it (measured on grids of squares: 4 faces
/// each leave regions 100 % off, 13 faces 10 %), so the base spacing is coarsened instead and
/// the mesh may end above the cap.
const MIN_POLYGON_FACES: f64 = 8.0;

/// Regions with fewer faces than this get a point inside every face that has none (see
/// [`triangulate`]).
const FEW_FACES: usize = 40;

/// Inside a small polygon, where the graded spacing is finer than this fraction of the
/// polygon's own (next to a much smaller neighbour), the graded points replace the polygon's.
const FINER: f64 = 0.7;

/// A mesh up to this factor over the cap is accepted (the cap is a size, not a limit).
pub(crate) const CAP_SLACK: f64 = 1.1;

/// A small polygon's inner points keep this fraction of its spacing away from its edges.
const INNER_CLEARANCE: f64 = 0.4;

/// The finest spacing is the base spacing over 2^this (the quadtree's deepest level).
const MAX_LEVEL: usize = 6;

/// How many cells (of its own level) around a cell that exists must exist at the level above:
/// 1 keeps neighbouring cells within a factor 2 of each other, so the spacing grows by about
/// 0.7 per unit distance away from a small polygon.
const GRADING_RING: i64 = 1;

/// A triangulation has about this many faces per point.
const FACES_PER_POINT: f64 = 2.0;

/// A polygon whose bounding box is more than this many times its area is thin: its lattice
/// would be cleared away by its own edges, so it gets none (its edges' points and the graded
/// spacing around them fill it).
const THIN: f64 = 16.0;

/// How fine the mesh is and how large it may grow.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resolution {
    /// About this many faces would fill the frame at the base spacing (where no polygon asks
    /// for finer).
    pub base_faces: usize,
    /// Every polygon gets about this many faces where the cap allows.
    pub polygon_faces: usize,
    /// The cap: when the mesh would have more faces, `polygon_faces` is lowered and then the
    /// base spacing coarsened until it fits, as far as the regions' own vertices allow (the
    /// mesh has every one of them).
    pub max_faces: usize,
}

/// How the mesh's size was settled under a [`Resolution`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plan {
    /// The base spacing (in the regions' normalised frame).
    pub h: f64,
    /// The faces each small polygon was given.
    pub polygon_faces: f64,
    /// The faces expected (about twice the points placed).
    pub faces: usize,
}

/// A triangulated disk containing the regions.
#[derive(Debug, Clone)]
pub struct RegionMesh {
    /// Mesh vertices: first the regions' vertices ([`RegionSet::points`], same indices), then the
    /// points added on region edges, on the frame and inside.
    pub points: Vec<[f64; 2]>,
    /// Counter-clockwise faces.
    pub faces: Vec<[u32; 3]>,
    /// The region each face lies in (`None`: the sea).
    pub face_region: Vec<Option<usize>>,
    /// How the mesh's size was settled.
    pub plan: Plan,
    /// For every region edge `[a, b]` with `a < b`, the mesh vertices added on it, from `a` to `b`.
    chains: HashMap<[usize; 2], Vec<usize>>,
}

/// The frame: the regions' bounding box with the sea's margin.
fn frame(set: &RegionSet) -> ([f64; 2], [f64; 2]) {
    let (lo, hi) = bbox(set.points.iter().copied());
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let m = MARGIN * size;
    ([lo[0] - m, lo[1] - m], [hi[0] + m, hi[1] + m])
}

/// The spacing of a hexagonal lattice with about `faces` faces over `area` (2/(√3 h²) points
/// per unit area, about twice as many faces as points).
fn lattice_spacing(area: f64, faces: f64) -> f64 {
    (4.0 * area / (3f64.sqrt() * faces.max(16.0))).sqrt()
}

/// Points of a hexagonal lattice of spacing `h` per unit area.
fn lattice_density(h: f64) -> f64 {
    2.0 / (3f64.sqrt() * h * h)
}

/// One polygon of the set, as the spacing sees it.
struct Piece {
    /// Rings as vertex indices (exterior first).
    rings: Vec<Vec<usize>>,
    area: f64,
    lo: [f64; 2],
    hi: [f64; 2],
    perimeter: f64,
}

/// The regions' geometry the mesh is laid out on, computed once.
struct Ground<'a> {
    set: &'a RegionSet,
    edges: Vec<([usize; 2], Vec<usize>)>,
    pieces: Vec<Piece>,
    /// Which pieces use each edge.
    edge_pieces: HashMap<[usize; 2], Vec<usize>>,
    /// The edges bucketed by their bounding boxes.
    edge_grid: Buckets,
    lo: [f64; 2],
    hi: [f64; 2],
}

impl<'a> Ground<'a> {
    fn new(set: &'a RegionSet) -> Self {
        let edges = set.edges();
        let (lo, hi) = frame(set);
        let mut pieces = Vec::new();
        let mut edge_pieces: HashMap<[usize; 2], Vec<usize>> = HashMap::new();
        for region in &set.regions {
            for rings in &region.polygons {
                let coords: Vec<Vec<[f64; 2]>> = rings
                    .iter()
                    .map(|r| r.iter().map(|&v| set.points[v]).collect())
                    .collect();
                let (plo, phi) = bbox(coords[0].iter().copied());
                let mut perimeter = 0.0;
                for ring in rings {
                    for i in 0..ring.len() {
                        let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
                        perimeter += distance(set.points[a], set.points[b]);
                        let owners = edge_pieces.entry([a.min(b), a.max(b)]).or_default();
                        if owners.last() != Some(&pieces.len()) {
                            owners.push(pieces.len());
                        }
                    }
                }
                pieces.push(Piece {
                    rings: rings.clone(),
                    area: super::regions::polygon_area(&coords).abs(),
                    lo: plo,
                    hi: phi,
                    perimeter,
                });
            }
        }
        let mut edge_grid = Buckets::new(lo, hi, edges.len());
        for (i, ([a, b], _)) in edges.iter().enumerate() {
            let (pa, pb) = (set.points[*a], set.points[*b]);
            edge_grid.add_box(min2(pa, pb, 0.0), max2(pa, pb, 0.0), i);
        }
        Ground {
            set,
            edges,
            pieces,
            edge_pieces,
            edge_grid,
            lo,
            hi,
        }
    }

    fn frame_area(&self) -> f64 {
        (self.hi[0] - self.lo[0]) * (self.hi[1] - self.lo[1])
    }

    /// The spacing of each piece at base spacing `h` and `k` faces per polygon: `Some(s)`,
    /// `s = √(2 A / k)`, for a small one (`s < h`). However small the polygon, its points cost
    /// about `k`; only the graded zone around it stops at the quadtree's finest level.
    fn spacings(&self, h: f64, k: f64) -> Vec<Option<f64>> {
        self.pieces
            .iter()
            .map(|p| {
                let s = (2.0 * p.area / k).sqrt();
                (s < h).then_some(s)
            })
            .collect()
    }

    fn is_thin(&self, piece: usize) -> bool {
        let p = &self.pieces[piece];
        (p.hi[0] - p.lo[0]) * (p.hi[1] - p.lo[1]) > THIN * p.area
    }

    /// About the points a layout at `h` and `k` would place, counted without placing them:
    /// the lattice of every small piece less the band its edges clear, the points on its
    /// edges (each shared by two pieces), the base lattice over the rest of the frame and the
    /// region vertices (the graded zones around small pieces are left out).
    fn count_points(&self, h: f64, k: f64) -> f64 {
        let spacing = self.spacings(h, k);
        let mut points = self.set.points.len() as f64;
        let mut small_area = 0.0;
        for (p, s) in self.pieces.iter().zip(&spacing) {
            if let Some(s) = s {
                let inner = (p.area - CLEARANCE * s * p.perimeter).max(0.0);
                points += inner * lattice_density(*s) + 0.5 * p.perimeter / s;
                small_area += p.area;
            }
        }
        points + (self.frame_area() - small_area).max(0.0) * lattice_density(h)
    }

    /// True when `p` is at least `clear` away from every region edge and from the frame.
    fn clear_of_edges(&self, p: [f64; 2], clear: f64) -> bool {
        let (lo, hi) = (self.lo, self.hi);
        if p[0] - lo[0] < clear
            || hi[0] - p[0] < clear
            || p[1] - lo[1] < clear
            || hi[1] - p[1] < clear
        {
            return false;
        }
        let pts = &self.set.points;
        let mut near = false;
        self.edge_grid.visit(
            [p[0] - clear, p[1] - clear],
            [p[0] + clear, p[1] + clear],
            |i| {
                if !near {
                    let [a, b] = self.edges[i].0;
                    near = segment_distance(p, pts[a], pts[b]).0 < clear;
                }
            },
        );
        !near
    }

    /// About `m` points spread over `piece`, at least `clear` from every edge: a hexagonal
    /// lattice centred on the piece's bounding box, its spacing adjusted (a few tries) until
    /// the count kept is `m` or the nearest found; the centre of the box alone when no lattice
    /// point is kept (nothing when that is outside the piece or too near an edge).
    fn inner_points(&self, piece: &Piece, m: usize, clear: f64) -> Vec<[f64; 2]> {
        let pts = &self.set.points;
        let centre = [
            0.5 * (piece.lo[0] + piece.hi[0]),
            0.5 * (piece.lo[1] + piece.hi[1]),
        ];
        let keep =
            |p: [f64; 2]| inside_loops(pts, &piece.rings, p) && self.clear_of_edges(p, clear);
        let lattice = |sigma: f64| {
            let dy = 0.5 * 3f64.sqrt() * sigma;
            let rows = ((0.5 * (piece.hi[1] - piece.lo[1])) / dy).ceil() as i64;
            let cols = ((0.5 * (piece.hi[0] - piece.lo[0])) / sigma).ceil() as i64 + 1;
            let mut out = Vec::new();
            for j in -rows..=rows {
                let shift = if j % 2 == 0 { 0.0 } else { 0.5 * sigma };
                for i in -cols..=cols {
                    let p = [
                        centre[0] + i as f64 * sigma + shift,
                        centre[1] + j as f64 * dy,
                    ];
                    if p[0] >= piece.lo[0] && p[0] <= piece.hi[0] && keep(p) {
                        out.push(p);
                    }
                }
            }
            out
        };
        let mut sigma = (2.0 * piece.area / (3f64.sqrt() * m as f64)).sqrt();
        let mut best: Vec<[f64; 2]> = Vec::new();
        for _ in 0..6 {
            let found = lattice(sigma);
            let off = |v: &Vec<[f64; 2]>| (v.len() as f64 - m as f64).abs();
            if best.is_empty() || (!found.is_empty() && off(&found) < off(&best)) {
                best = found.clone();
            }
            if found.len() == m {
                break;
            }
            sigma *= if found.is_empty() {
                0.7
            } else {
                (found.len() as f64 / m as f64).sqrt().clamp(0.7, 1.4)
            };
        }
        if best.is_empty() && keep(centre) {
            best.push(centre);
        }
        best
    }

    /// Places the mesh's points and constrained segments at base spacing `h` and `k` faces per
    /// small polygon, or `None` as soon as more than `limit` points are placed.
    fn layout(&self, h: f64, k: f64, limit: usize) -> Option<Layout> {
        let set = self.set;
        let spacing = self.spacings(h, k);
        let sizing = Sizing::new(self, &spacing, h);
        // The spacing along an edge: the finest of its small pieces', or the graded one.
        let mut edge_spacing: HashMap<[usize; 2], f64> = HashMap::new();
        for (key, owners) in &self.edge_pieces {
            if let Some(s) = owners
                .iter()
                .filter_map(|&q| spacing[q])
                .min_by(f64::total_cmp)
            {
                edge_spacing.insert(*key, s);
            }
        }
        let mut points = set.points.clone();
        let mut segments: Vec<[usize; 2]> = Vec::new();
        let mut chains = HashMap::new();
        for ([a, b], _) in &self.edges {
            let chain = match edge_spacing.get(&[*a, *b]) {
                Some(&s) => subdivide(&mut points, *a, *b, &|_| s, &mut segments),
                None => subdivide(&mut points, *a, *b, &|p| sizing.at(p), &mut segments),
            };
            chains.insert([*a, *b], chain);
            if points.len() > limit {
                return None;
            }
        }
        let (flo, fhi) = (self.lo, self.hi);
        let corners = [flo, [fhi[0], flo[1]], fhi, [flo[0], fhi[1]]];
        let c0 = points.len();
        points.extend_from_slice(&corners);
        for k in 0..4 {
            subdivide(&mut points, c0 + k, c0 + (k + 1) % 4, &|_| h, &mut segments);
        }
        let on_edges = points.len();

        // Small pieces with a lattice of their own; other points stay out of them.
        let mut latticed = Buckets::new(flo, fhi, self.pieces.len());
        for (q, s) in spacing.iter().enumerate() {
            if s.is_some() && !self.is_thin(q) {
                latticed.add_box(self.pieces[q].lo, self.pieces[q].hi, q);
            }
        }
        // A graded point of spacing `side` at `p` is left to the small piece containing it
        // unless the piece's own points are coarser there (next to a much smaller neighbour).
        let graded_here = |p: [f64; 2], side: f64| {
            let mut inside = false;
            latticed.visit(p, p, |q| {
                inside = inside
                    || (spacing[q].is_some_and(|s| side >= FINER * s)
                        && inside_loops(&set.points, &self.pieces[q].rings, p));
            });
            !inside
        };
        // A hexagonal lattice where the quadtree is at the base spacing.
        let dy = 0.5 * 3f64.sqrt() * h;
        let rows = ((fhi[1] - flo[1]) / dy).floor() as usize;
        for j in 1..=rows {
            let y = flo[1] + j as f64 * dy;
            let shift = if j % 2 == 0 { 0.0 } else { 0.5 * h };
            let mut x = flo[0] + shift;
            while x < fhi[0] {
                let p = [x, y];
                x += h;
                if sizing.at(p) >= h && self.clear_of_edges(p, CLEARANCE * h) && graded_here(p, h) {
                    points.push(p);
                }
            }
            if points.len() > limit {
                return None;
            }
        }
        // A point at the centre of every finer cell.
        for (c, s) in sizing.fine_cells() {
            if self.clear_of_edges(c, CLEARANCE * s) && graded_here(c, s) {
                points.push(c);
            }
        }
        if points.len() > limit {
            return None;
        }
        // Every small piece's own points inside it: as many as make about k faces with the
        // points on its edges (a triangulation of b boundary and m inner points has
        // b + 2m − 2 faces), at least one.
        for (q, s) in spacing.iter().enumerate() {
            let Some(s) = *s else { continue };
            if self.is_thin(q) {
                continue;
            }
            let piece = &self.pieces[q];
            let boundary = piece.perimeter / s;
            let m = ((k - boundary + 2.0) / 2.0).round().max(1.0) as usize;
            points.extend(
                self.inner_points(piece, m, INNER_CLEARANCE * s)
                    .into_iter()
                    .filter(|&p| sizing.at(p) >= FINER * s),
            );
            if points.len() > limit {
                return None;
            }
        }
        Some(Layout {
            points,
            segments,
            chains,
            on_edges,
        })
    }
}

/// Points and constrained segments before the triangulation.
struct Layout {
    points: Vec<[f64; 2]>,
    segments: Vec<[usize; 2]>,
    chains: HashMap<[usize; 2], Vec<usize>>,
    /// The points before this index lie on region edges or the frame.
    on_edges: usize,
}

/// A triangulated layout: the points (the layout's and those added inside blind faces), the
/// faces and their regions.
struct Meshed {
    points: Vec<[f64; 2]>,
    faces: Vec<[u32; 3]>,
    face_region: Vec<Option<usize>>,
}

/// The constrained Delaunay triangulation of `layout`, with every region face whose corners
/// all lie on edges or the frame split by a point inside it, and the region of every face.
///
/// A vertex's density averages its faces, so a face with no vertex inside its region takes
/// its density from the neighbours only and the map cannot resize it with its region (a small
/// polygon's corners, thin parts). In a region of fewer than [`FEW_FACES`] faces such *blind*
/// faces are a large part of it: they get their centroid as a point, and the points are
/// triangulated again (measured on 2500 squares of 8 faces: the worst region 99 % off
/// without, 8 % with). In larger regions they are a few corners, and the small faces the
/// split would make only shorten the map's steps.
fn triangulate(
    set: &RegionSet,
    polygons: &[(usize, Vec<Vec<usize>>)],
    layout: &Layout,
    path: &str,
) -> Result<Meshed> {
    let mut points = layout.points.clone();
    let mut t = constrained_delaunay(&points, &layout.segments)?;
    let mut face_region = assign_faces(set, polygons, &set.points, &t.points, &t.faces, path)?;
    let mut region_faces = vec![0usize; set.regions.len()];
    for r in face_region.iter().flatten() {
        region_faces[*r] += 1;
    }
    let blind: Vec<[f64; 2]> = t
        .faces
        .iter()
        .zip(&face_region)
        .filter(|(f, r)| {
            r.is_some_and(|r| region_faces[r] < FEW_FACES)
                && f.iter().all(|&v| (v as usize) < layout.on_edges)
        })
        .map(|(f, _)| {
            let [a, b, c] = f.map(|v| t.points[v as usize]);
            [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0]
        })
        .collect();
    if !blind.is_empty() {
        points.extend(blind);
        t = constrained_delaunay(&points, &layout.segments)?;
        face_region = assign_faces(set, polygons, &set.points, &t.points, &t.faces, path)?;
    }
    Ok(Meshed {
        points: t.points,
        faces: t.faces,
        face_region,
    })
}

/// Settles the mesh under `resolution` and triangulates it: the asked `k` and base spacing if
/// the mesh fits the cap, otherwise `k` lowered (down to [`MIN_POLYGON_FACES`]) and then the
/// base spacing coarsened, by steps, until it fits or nothing coarser is left. A layout is
/// abandoned as soon as it places more points than the cap allows, so every try costs at most
/// the cap's work; the coarsest mesh is estimated first and refused when it would exceed
/// [`super::MAX_FACES`].
fn settle(
    ground: &Ground,
    polygons: &[(usize, Vec<Vec<usize>>)],
    resolution: &Resolution,
    path: &str,
) -> Result<(Plan, Layout, Meshed)> {
    let cap = resolution.max_faces as f64;
    let cap_points = (cap / FACES_PER_POINT).max(1.0);
    let mut h = lattice_spacing(ground.frame_area(), resolution.base_faces as f64);
    let mut k = resolution.polygon_faces.max(1) as f64;
    let coarsest = (ground.hi[0] - ground.lo[0]).max(ground.hi[1] - ground.lo[1]);
    let k_floor = MIN_POLYGON_FACES.min(k);
    let least = FACES_PER_POINT * ground.count_points(coarsest, k_floor);
    if least > super::MAX_FACES as f64 {
        return Err(super::mesh_too_large(ground.set, least, path));
    }
    let most_points = super::MAX_FACES as f64 / FACES_PER_POINT;
    let shrink = |h: &mut f64, k: &mut f64, factor: f64| {
        if *k > k_floor {
            *k = (*k * factor).max(k_floor);
        } else {
            *h /= factor.sqrt();
        }
    };
    // Skip what the count already rules out.
    for _ in 0..64 {
        let n = ground.count_points(h, k);
        if n <= cap_points || h > coarsest {
            break;
        }
        shrink(&mut h, &mut k, (0.95 * cap_points / n).max(0.05));
    }
    loop {
        let floor = h > coarsest;
        let limit = if floor { most_points } else { cap_points } as usize;
        let Some(layout) = ground.layout(h, k, limit) else {
            if floor {
                return Err(super::mesh_too_large(ground.set, f64::INFINITY, path));
            }
            shrink(&mut h, &mut k, 0.7);
            continue;
        };
        let meshed = triangulate(ground.set, polygons, &layout, path)?;
        let faces = meshed.faces.len() as f64;
        if faces <= CAP_SLACK * cap || floor {
            let plan = Plan {
                h,
                polygon_faces: k,
                faces: meshed.faces.len(),
            };
            return Ok((plan, layout, meshed));
        }
        shrink(&mut h, &mut k, (0.95 * cap / faces).clamp(0.05, 0.9));
    }
}

impl RegionMesh {
    /// Triangulates `set` and its sea at the resolution `resolution` (see [`Resolution`]);
    /// `path` names the file in messages.
    ///
    /// Errors: [`Error::Format`] when even the coarsest mesh of the regions would exceed
    /// [`super::MAX_FACES`] (refused before anything is laid out, with the estimate),
    /// when two regions (or two polygons of one region) overlap without their edges crossing
    /// (one inside the other, or the same polygon twice), or a region ends up with no face;
    /// the triangulation's own errors.
    pub fn build(set: &RegionSet, resolution: &Resolution, path: &str) -> Result<RegionMesh> {
        let ground = Ground::new(set);
        let polygons: Vec<(usize, Vec<Vec<usize>>)> = set
            .regions
            .iter()
            .enumerate()
            .flat_map(|(r, region)| region.polygons.iter().map(move |p| (r, p.clone())))
            .collect();
        let (plan, layout, meshed) = settle(&ground, &polygons, resolution, path)?;
        let mut has_face = vec![false; set.regions.len()];
        for r in meshed.face_region.iter().flatten() {
            has_face[*r] = true;
        }
        if let Some(r) = has_face.iter().position(|&x| !x) {
            return Err(Error::Format {
                path: path.to_string(),
                msg: format!("{}: the region encloses no area", set.regions[r].label),
            });
        }
        Ok(RegionMesh {
            points: meshed.points,
            faces: meshed.faces,
            face_region: meshed.face_region,
            plan,
            chains: layout.chains,
        })
    }

    /// The mesh vertices along a ring of region vertices: every ring vertex followed by the
    /// vertices added on its edge to the next one.
    pub fn dense_ring(&self, ring: &[usize]) -> Vec<usize> {
        let mut out = Vec::with_capacity(ring.len());
        for i in 0..ring.len() {
            let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
            out.push(a);
            if let Some(mid) = self.chains.get(&[a.min(b), a.max(b)]) {
                if a < b {
                    out.extend(mid.iter().copied());
                } else {
                    out.extend(mid.iter().rev().copied());
                }
            }
        }
        out
    }
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt()
}

/// Splits the segment `a`–`b` into pieces about as long as the spacing wanted along it
/// (`spacing`, evaluated at both ends of each piece), stretched evenly to end at `b`: adds the
/// inner points to `points`, the pieces to `segments`, and returns the inner points' indices
/// from `a` to `b`.
fn subdivide(
    points: &mut Vec<[f64; 2]>,
    a: usize,
    b: usize,
    spacing: &dyn Fn([f64; 2]) -> f64,
    segments: &mut Vec<[usize; 2]>,
) -> Vec<usize> {
    let (pa, pb) = (points[a], points[b]);
    let len = ((pb[0] - pa[0]).powi(2) + (pb[1] - pa[1]).powi(2)).sqrt();
    let at = |t: f64| [pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1])];
    // Parameters of the piece ends, greedily; then scaled so that the last one is exactly 1.
    let mut ts = vec![0.0];
    let mut t = 0.0;
    while t < 1.0 {
        let mut step = spacing(at(t)) / len;
        for _ in 0..2 {
            step = step.min(spacing(at((t + step).min(1.0))) / len);
        }
        t += step.max(1e-9);
        ts.push(t);
    }
    // When the last piece overshoots by more than half its length, stretch instead of shrink.
    let n = ts.len();
    if n > 2 && ts[n - 1] - 1.0 > 0.5 * (ts[n - 1] - ts[n - 2]) {
        ts.pop();
    }
    let last = *ts.last().unwrap_or(&1.0);
    let mut chain = Vec::with_capacity(ts.len());
    let mut prev = a;
    for &t in &ts[1..ts.len() - 1] {
        points.push(at(t / last));
        let v = points.len() - 1;
        segments.push([prev, v]);
        chain.push(v);
        prev = v;
    }
    segments.push([prev, b]);
    chain
}

#[cfg(test)]
mod tests;

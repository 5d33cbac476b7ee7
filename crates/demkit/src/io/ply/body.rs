//! The body: the vertex and face elements read from a [`Source`], the others skipped.

use super::header::{Element, Header, Property};
use super::source::{ReadError, Source};
use crate::io::{format_error, number_error, parse_error};
use crate::{Result, TriMesh};

/// What the reader does with each property of an element.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Role {
    Coordinate(usize),
    Indices,
    Skip,
}

/// Reads the body the header describes into a mesh, checking indices, coordinates and that
/// nothing follows the last element.
pub(super) fn read_body<S: Source>(
    header: &Header,
    src: &mut S,
    body_len: usize,
    path: &str,
) -> Result<TriMesh> {
    let vertex_elements = header
        .elements
        .iter()
        .filter(|e| e.name == "vertex")
        .count();
    let face_elements = header.elements.iter().filter(|e| e.name == "face").count();
    if vertex_elements != 1 || face_elements > 1 {
        return Err(format_error(
            path,
            &format!(
                "a PLY mesh needs one 'vertex' element and at most one 'face' element (found \
                 {vertex_elements} and {face_elements})"
            ),
        ));
    }
    // Error at the current position: with the line for ascii, for the file otherwise.
    let located = |src: &S, msg: String| error_at(path, src.line(), msg);
    let read_error = |src: &S, e: ReadError, element: &Element, item: usize| match e {
        ReadError::End => format_error(
            path,
            &format!(
                "file is truncated: it ends in {} {item} of {}",
                element.name, element.count
            ),
        ),
        ReadError::Bad(token) => number_error(path, src.line().unwrap_or(0), &token),
    };

    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut faces: Vec<[u32; 3]> = Vec::new();
    // (largest index, its face, its line) to check against the vertex count at the end.
    let mut max_index: Option<(u32, usize, Option<usize>)> = None;
    for element in &header.elements {
        let roles: Vec<Role> = roles(element, path)?;
        let is_vertex = element.name == "vertex";
        let is_face = element.name == "face";
        // An element without properties takes no bytes: there is nothing to read, however
        // many items it declares (and counting up to a huge count would never end).
        if element.properties.is_empty() {
            continue;
        }
        // Never trust the count for allocation beyond what the data could hold: every item
        // takes at least `item_bytes`.
        let item_bytes: usize = element
            .properties
            .iter()
            .map(|p| match p {
                Property::Scalar(ty, _) | Property::List(ty, _, _) => src.min_bytes(*ty),
            })
            .sum();
        let capacity = element.count.min(body_len / item_bytes.max(1));
        if is_vertex {
            positions.reserve(capacity);
        } else if is_face {
            faces.reserve(capacity);
        }
        for item in 0..element.count {
            let mut p = [0.0f64; 3];
            let mut face = [0u32; 3];
            for (property, &role) in element.properties.iter().zip(&roles) {
                match property {
                    Property::Scalar(ty, _) => {
                        let x = src
                            .next(*ty)
                            .map_err(|e| read_error(src, e, element, item))?;
                        if let Role::Coordinate(k) = role {
                            p[k] = x;
                        }
                    }
                    Property::List(count_ty, item_ty, _) => {
                        let n = src
                            .next(*count_ty)
                            .map_err(|e| read_error(src, e, element, item))?;
                        if !(n >= 0.0 && n.fract() == 0.0) {
                            return Err(located(
                                src,
                                format!("{} {item}: invalid list length {n}", element.name),
                            ));
                        }
                        let n = n as usize;
                        if role != Role::Indices {
                            src.skip(*item_ty, n)
                                .map_err(|e| read_error(src, e, element, item))?;
                            continue;
                        }
                        if n != 3 {
                            return Err(located(
                                src,
                                format!(
                                    "face {item} has {n} vertices: only triangles are \
                                     supported (triangulate the mesh first)"
                                ),
                            ));
                        }
                        for slot in &mut face {
                            let v = src
                                .next(*item_ty)
                                .map_err(|e| read_error(src, e, element, item))?;
                            if !(v >= 0.0 && v.fract() == 0.0 && v <= u32::MAX as f64) {
                                return Err(located(
                                    src,
                                    format!("face {item} has an invalid vertex index {v}"),
                                ));
                            }
                            *slot = v as u32;
                            if max_index.is_none_or(|(m, _, _)| *slot > m) {
                                max_index = Some((*slot, item, src.line()));
                            }
                        }
                    }
                }
            }
            if is_vertex {
                if !p.iter().all(|x| x.is_finite()) {
                    return Err(located(
                        src,
                        format!("vertex {item} has a non-finite coordinate"),
                    ));
                }
                positions.push(p);
            } else if is_face {
                faces.push(face);
            }
        }
    }
    if let Some((m, face, line)) = max_index
        && m as usize >= positions.len()
    {
        let msg = format!(
            "face {face} uses vertex {m}, which is out of range (the file has {} vertices)",
            positions.len()
        );
        return Err(error_at(path, line, msg));
    }
    if let Some(line) = src.trailing() {
        let msg = "data after the elements the header declares (is a count wrong?)";
        return Err(error_at(path, line, msg.to_string()));
    }
    if faces.is_empty() {
        return Err(format_error(path, "no faces"));
    }
    Ok(TriMesh::new(positions, faces))
}

/// An error at `line` (ascii data) or, without a line (binary data), about the whole file.
fn error_at(path: &str, line: Option<usize>, msg: String) -> crate::Error {
    match line {
        Some(line) => parse_error(path, line, msg),
        None => format_error(path, &msg),
    }
}

/// The role of every property of `element`; checks the vertex and face elements have what
/// the reader needs.
fn roles(element: &Element, path: &str) -> Result<Vec<Role>> {
    let props = &element.properties;
    let mut roles = vec![Role::Skip; props.len()];
    if element.name == "vertex" {
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            let found = props.iter().position(|p| p.name() == *axis);
            match found.map(|i| (i, &props[i])) {
                Some((i, Property::Scalar(..))) => roles[i] = Role::Coordinate(k),
                Some((_, Property::List(..))) => {
                    return Err(format_error(
                        path,
                        &format!("PLY vertex property '{axis}' is a list, not a number"),
                    ));
                }
                None => {
                    return Err(format_error(
                        path,
                        &format!("PLY vertex element has no property '{axis}'"),
                    ));
                }
            }
        }
    } else if element.name == "face" {
        let found = props
            .iter()
            .position(|p| matches!(p, Property::List(..)) && p.name() == "vertex_indices")
            .or_else(|| {
                props
                    .iter()
                    .position(|p| matches!(p, Property::List(..)) && p.name() == "vertex_index")
            });
        match found {
            Some(i) => roles[i] = Role::Indices,
            None => {
                return Err(format_error(
                    path,
                    "PLY face element has no list property 'vertex_indices' (or 'vertex_index')",
                ));
            }
        }
    }
    Ok(roles)
}

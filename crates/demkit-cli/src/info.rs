//! `demkit info`: counts, topology and validation findings of a mesh.

use crate::Failure;
use crate::args::InfoArgs;
use demkit::mesh::topology::topology;
use demkit::mesh::validate::check;

/// Prints the mesh summary; exit code 0 when the file could be read (findings are listed).
pub fn run(a: &InfoArgs) -> Result<u8, Failure> {
    let mesh = demkit::io::read_mesh(&a.mesh)?;
    let findings = check(&mesh);
    // Topology needs indices in range; skip it when the faces are broken.
    let indices_ok = mesh
        .faces
        .iter()
        .all(|f| f.iter().all(|&v| (v as usize) < mesh.n_vertices()));
    let topo = indices_ok.then(|| topology(&mesh));
    let area: f64 = if indices_ok {
        demkit::geometry::face_areas(&mesh.positions, &mesh.faces)
            .iter()
            .sum()
    } else {
        f64::NAN
    };
    let kind = topo
        .as_ref()
        .map(|t| describe(t.boundary_loops.len(), t.genus, t.components))
        .unwrap_or("unknown");
    if a.json {
        let v = serde_json::json!({
            "file": a.mesh.display().to_string(),
            "vertices": mesh.n_vertices(),
            "faces": mesh.n_faces(),
            "edges": topo.as_ref().map(|t| t.n_edges),
            "boundaries": topo.as_ref().map(|t| t.boundary_loops.len()),
            "boundary_lengths": topo.as_ref().map(|t| t.boundary_loops.iter().map(|l| l.len()).collect::<Vec<_>>()),
            "euler_characteristic": topo.as_ref().map(|t| t.euler_characteristic),
            "genus": topo.as_ref().map(|t| t.genus),
            "components": topo.as_ref().map(|t| t.components),
            "area": area,
            "kind": kind,
            "method": suggested_method(kind),
            "valid": findings.errors.is_empty(),
            "errors": findings.errors,
            "warnings": findings.warnings,
        });
        println!("{}", serde_json::to_string_pretty(&v).unwrap_or_default());
    } else {
        println!("file:        {}", a.mesh.display());
        println!("vertices:    {}", mesh.n_vertices());
        println!("faces:       {}", mesh.n_faces());
        if let Some(t) = &topo {
            println!("edges:       {}", t.n_edges);
            let lens: Vec<String> = t
                .boundary_loops
                .iter()
                .map(|l| l.len().to_string())
                .collect();
            println!(
                "boundaries:  {}{}",
                t.boundary_loops.len(),
                if lens.is_empty() {
                    String::new()
                } else {
                    format!(" ({} vertices)", lens.join(", "))
                }
            );
            println!("euler char.: {}", t.euler_characteristic);
            println!("genus:       {}", t.genus);
            println!("components:  {}", t.components);
        }
        println!("area:        {area}");
        println!(
            "kind:        {kind}{}",
            suggested_method(kind)
                .map(|m| format!(" (method: {m})"))
                .unwrap_or_default()
        );
        if findings.errors.is_empty() {
            println!("valid:       yes");
        } else {
            println!("valid:       no");
        }
        for e in &findings.errors {
            println!("  error:   {e}");
        }
        for w in &findings.warnings {
            println!("  warning: {w}");
        }
    }
    Ok(0)
}

/// Names the topology class of a connected mesh.
pub fn describe(boundaries: usize, genus: i64, components: usize) -> &'static str {
    match (components, boundaries, genus) {
        (1, 1, 0) => "simply connected open surface (disk)",
        (1, b, 0) if b > 1 => "multiply connected open surface",
        (1, 0, 0) => "genus-0 closed surface",
        (1, 0, 1) => "genus-one closed surface",
        (1, _, _) => "surface of higher genus",
        _ => "several components",
    }
}

fn suggested_method(kind: &str) -> Option<&'static str> {
    match kind {
        "simply connected open surface (disk)" => Some("dem"),
        "multiply connected open surface" => Some("deq"),
        "genus-0 closed surface" => Some("sdem"),
        "genus-one closed surface" => Some("tdem"),
        _ => None,
    }
}

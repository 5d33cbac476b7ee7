//! The results of `demkit bench`: one record per case (also its JSON), the table printed on
//! stdout and the growth of time and memory along each ladder of sizes.

use serde::Serialize;
use std::fmt::Write;

/// The `time_s` of a map's report.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Times {
    /// The initial map.
    pub init: f64,
    /// The density-equalizing iteration.
    pub map: f64,
    /// The whole `demkit map` run: reading, validating, mapping, measuring and writing.
    pub total: f64,
}

/// What a case's report says (present when the map ran to its end).
#[derive(Debug, Clone, Serialize)]
pub struct Figures {
    /// The method that ran.
    pub method: String,
    /// Vertices of the mesh mapped.
    pub vertices: usize,
    /// Faces of the mesh mapped.
    pub faces: usize,
    /// The report's `converged`.
    pub converged: bool,
    /// The report's `stop_reason`.
    pub stop_reason: String,
    /// The report's `iterations`.
    pub iterations: usize,
    /// The report's `time_s`.
    pub time_s: Times,
    /// The report's `metrics.density_error_mean`.
    pub density_error_mean: f64,
    /// The report's `metrics.flipped_triangles`.
    pub flipped_triangles: usize,
    /// The report's `notes` (why a map did not converge, what was corrected).
    pub notes: Vec<String>,
}

/// One case's outcome.
#[derive(Debug, Clone, Serialize)]
pub struct CaseResult {
    /// The case's name.
    pub name: String,
    /// Its suite: `generated`, `data` (`--data`) or `scale` (`--scale`).
    pub suite: &'static str,
    /// How its mesh was made.
    pub mesh: String,
    /// Its population.
    pub population: String,
    /// The method asked for.
    pub method: String,
    /// The ladder of sizes it is part of (empty for none).
    #[serde(skip)]
    pub ladder: String,
    /// Seconds spent making the mesh (generating, subdividing) before the map.
    pub prepare_s: f64,
    /// Seconds of the `demkit map` process, start to exit.
    pub wall_s: f64,
    /// The map process's peak resident memory (Linux; none elsewhere).
    pub peak_memory_mib: Option<f64>,
    /// The system's 1-minute load average, the larger of those before and after the case
    /// (Linux): above the number of cores, other work shared the machine.
    pub load_average: Option<f64>,
    /// The map process's exit code (0; 3 not converged; 1 flipped triangles or a failure).
    pub exit_code: Option<i32>,
    /// The report's figures, when the map ran to its end.
    #[serde(flatten)]
    pub figures: Option<Figures>,
    /// Why the case has no figures.
    pub error: Option<String>,
}

impl CaseResult {
    /// True when the map ran to its end (converged or not).
    pub fn ran(&self) -> bool {
        self.figures.is_some()
    }

    /// The stopping reason as the table shows it: not converged and flipped maps said so.
    fn stop(&self) -> String {
        match &self.figures {
            None => "FAILED".into(),
            Some(f) if !f.converged => format!("{} (NOT CONVERGED)", f.stop_reason),
            Some(f) => f.stop_reason.clone(),
        }
    }

    /// The progress line's end: what the case gave, in one line.
    pub fn summary(&self) -> String {
        let memory = self
            .peak_memory_mib
            .map_or("peak memory unknown".into(), |m| format!("peak {m:.0} MiB"));
        match &self.figures {
            None => format!(
                "FAILED: {}",
                self.error.as_deref().unwrap_or("no report written")
            ),
            Some(f) => format!(
                "{}, {} faces, {:.2} s (init {:.2}, map {:.2}), {} iterations, {}, density error \
                 {:.4}, {} flipped, {memory}",
                f.method,
                f.faces,
                f.time_s.total,
                f.time_s.init,
                f.time_s.map,
                f.iterations,
                self.stop(),
                f.density_error_mean,
                f.flipped_triangles,
            ),
        }
    }
}

/// Rows of cells printed as an aligned Markdown table (numbers right-aligned).
fn markdown(header: &[&str], rows: &[Vec<String>]) -> String {
    let widths: Vec<usize> = (0..header.len())
        .map(|c| {
            rows.iter()
                .map(|r| r[c].chars().count())
                .chain([header[c].chars().count()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let numeric = |c: usize| {
        rows.iter()
            .all(|r| r[c].parse::<f64>().is_ok() || r[c] == "-")
    };
    let line = |cells: Vec<String>| {
        let mut s = String::from("|");
        for (c, cell) in cells.iter().enumerate() {
            let pad = widths[c].saturating_sub(cell.chars().count());
            if numeric(c) {
                let _ = write!(s, " {}{cell} |", " ".repeat(pad));
            } else {
                let _ = write!(s, " {cell}{} |", " ".repeat(pad));
            }
        }
        s.push('\n');
        s
    };
    let mut out = line(header.iter().map(|h| h.to_string()).collect());
    let rule = widths.iter().enumerate().map(|(c, &w)| {
        if numeric(c) {
            format!("{}:", "-".repeat(w.max(2) - 1))
        } else {
            "-".repeat(w.max(1))
        }
    });
    out.push_str(&line(rule.collect()));
    for r in rows {
        out.push_str(&line(r.clone()));
    }
    out
}

/// The table of every case, then the failures' messages.
pub fn results_table(results: &[CaseResult]) -> String {
    let dash = || "-".to_string();
    let rows: Vec<Vec<String>> = results
        .iter()
        .map(|r| {
            let memory = r.peak_memory_mib.map_or_else(dash, |m| format!("{m:.0}"));
            match &r.figures {
                Some(f) => vec![
                    r.name.clone(),
                    f.vertices.to_string(),
                    f.faces.to_string(),
                    f.method.clone(),
                    format!("{:.2}", f.time_s.init),
                    format!("{:.2}", f.time_s.map),
                    format!("{:.2}", f.time_s.total),
                    f.iterations.to_string(),
                    r.stop(),
                    format!("{:.4}", f.density_error_mean),
                    f.flipped_triangles.to_string(),
                    memory,
                ],
                None => {
                    let mut row = vec![r.name.clone(), dash(), dash(), r.method.clone()];
                    row.extend([dash(), dash(), dash(), dash(), r.stop(), dash(), dash()]);
                    row.push(memory);
                    row
                }
            }
        })
        .collect();
    let mut out = markdown(
        &[
            "case",
            "vertices",
            "faces",
            "method",
            "init s",
            "map s",
            "total s",
            "iterations",
            "stop",
            "density error",
            "flipped",
            "peak MiB",
        ],
        &rows,
    );
    for r in results {
        match &r.figures {
            None => {
                let error = r.error.as_deref().unwrap_or("no report written");
                let _ = write!(out, "\n{} failed: {error}\n", r.name);
            }
            Some(f) if !f.converged => {
                let mut why = format!("{} after {} iterations", f.stop_reason, f.iterations);
                for note in &f.notes {
                    why.push_str("; ");
                    why.push_str(note);
                }
                let _ = write!(out, "\n{} did not converge: {why}\n", r.name);
            }
            Some(_) => {}
        }
    }
    out
}

/// For every ladder with at least two sizes that ran: per size the faces, iterations, whole
/// time, time per iteration and peak memory, each figure with the exponent k of figure ∝
/// faces^k from the size before (time per iteration compares sizes whose iteration counts
/// differ). Empty when there is none.
pub fn growth_table(results: &[CaseResult]) -> String {
    let mut ladders: Vec<&str> = results
        .iter()
        .filter(|r| !r.ladder.is_empty())
        .map(|r| r.ladder.as_str())
        .collect();
    ladders.sort_unstable();
    ladders.dedup();
    let mut rows = Vec::new();
    for ladder in ladders {
        let mut rungs: Vec<(&CaseResult, &Figures)> = results
            .iter()
            .filter(|r| r.ladder == ladder)
            .filter_map(|r| Some((r, r.figures.as_ref()?)))
            .collect();
        if rungs.len() < 2 {
            continue;
        }
        rungs.sort_by_key(|(_, f)| f.faces);
        // Whole time, time per iteration, peak memory.
        let measures = |(r, f): (&CaseResult, &Figures)| {
            let per_iteration = (f.iterations > 0).then(|| f.time_s.map / f.iterations as f64);
            [Some(f.time_s.total), per_iteration, r.peak_memory_mib]
        };
        for (i, &(r, f)) in rungs.iter().enumerate() {
            let before = i
                .checked_sub(1)
                .map(|p| (rungs[p].1.faces, measures(rungs[p])));
            let mut row = vec![
                ladder.to_string(),
                r.name.clone(),
                f.faces.to_string(),
                f.iterations.to_string(),
            ];
            for (m, (value, decimals)) in measures((r, f)).into_iter().zip([2, 4, 0]).enumerate() {
                row.push(value.map_or_else(|| "-".into(), |v| format!("{v:.decimals$}")));
                let earlier = before.and_then(|(faces, e)| Some((faces, e[m]?)));
                row.push(match (earlier, value) {
                    (Some((faces, a)), Some(b)) if a > 0.0 && b > 0.0 && f.faces > faces => {
                        format!("{:.2}", (b / a).ln() / (f.faces as f64 / faces as f64).ln())
                    }
                    _ => "-".into(),
                });
            }
            rows.push(row);
        }
    }
    if rows.is_empty() {
        return String::new();
    }
    markdown(
        &[
            "ladder",
            "case",
            "faces",
            "iterations",
            "total s",
            "k",
            "map s/iteration",
            "k",
            "peak MiB",
            "k",
        ],
        &rows,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn result(name: &str, ladder: &str, faces: usize, total: f64, memory: f64) -> CaseResult {
        CaseResult {
            name: name.into(),
            suite: "generated",
            mesh: String::new(),
            population: "area".into(),
            method: "sdem".into(),
            ladder: ladder.into(),
            prepare_s: 0.0,
            wall_s: total,
            peak_memory_mib: Some(memory),
            load_average: None,
            exit_code: Some(0),
            figures: Some(Figures {
                method: "sdem".into(),
                vertices: faces / 2 + 2,
                faces,
                converged: true,
                stop_reason: "tolerance".into(),
                iterations: 7,
                time_s: Times {
                    init: 0.1,
                    map: total - 0.2,
                    total,
                },
                density_error_mean: 0.0123,
                flipped_triangles: 0,
                notes: vec!["the overlap correction was applied in 2 iterations".into()],
            }),
            error: None,
        }
    }

    #[test]
    fn the_growth_exponent_is_that_of_a_power_law() {
        let results = [
            result("big", "s", 4000, 16.0, 400.0),
            result("small", "s", 1000, 1.0, 100.0),
            result("alone", "", 10, 1.0, 1.0),
        ];
        let table = growth_table(&results);
        let rows: Vec<&str> = table.lines().skip(2).collect();
        assert_eq!(rows.len(), 2, "{table}");
        assert!(rows[0].contains("small"), "{table}");
        // Time ∝ F², memory ∝ F; 7 iterations each, 0.2 s outside them.
        let cells: Vec<&str> = rows[1].split('|').map(str::trim).collect();
        assert_eq!(
            cells[1..11],
            [
                "s", "big", "4000", "7", "16.00", "2.00", "2.2571", "2.15", "400", "1.00"
            ]
        );
    }

    #[test]
    fn failures_and_unconverged_maps_are_shown() {
        let mut stuck = result("stuck", "", 100, 1.0, 10.0);
        if let Some(f) = stuck.figures.as_mut() {
            f.converged = false;
            f.stop_reason = "max_iter".into();
        }
        let mut broken = result("broken", "", 100, 1.0, 10.0);
        broken.figures = None;
        broken.error = Some("invalid mesh: face 3".into());
        let table = results_table(&[stuck, broken]);
        assert!(table.contains("max_iter (NOT CONVERGED)"), "{table}");
        assert!(
            table.contains(
                "stuck did not converge: max_iter after 7 iterations; the overlap correction"
            ),
            "{table}"
        );
        assert!(table.contains("| FAILED "), "{table}");
        assert!(
            table.contains("broken failed: invalid mesh: face 3"),
            "{table}"
        );
        assert!(growth_table(&[result("a", "", 1, 1.0, 1.0)]).is_empty());
    }
}

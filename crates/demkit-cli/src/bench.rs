//! `demkit bench`: `demkit map` on a suite of cases ([`cases`]), each in a process of its own,
//! with per case the mesh's size, the method, the times (initial map, iteration, whole run),
//! the iterations and how they stopped, the density error, the flipped triangles and the peak
//! resident memory ([`table`]).
//!
//! Each case runs as `demkit bench-map` — `demkit map` that prints its own peak resident memory
//! (VmHWM of /proc/self/status, Linux) as it ends — so the memory is the map's alone, none of
//! the bench's, and a map that fails or is killed fails its case, not the bench. Meshes that
//! are made (generated, subdivided) are made by `demkit generate` and `demkit subdivide` in a
//! scratch directory under the system's temporary directory, removed case by case and at the
//! end; nothing is written beside the inputs.

mod cases;
mod table;

use crate::Failure;
use crate::args::{BenchArgs, MapArgs};
use cases::{Case, Population, Source, Target};
use serde::Serialize;
use serde_json::Value;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Instant;
use table::{CaseResult, Figures, Times};

/// `demkit bench-map` ends its stdout with this word, a space and its peak memory in KiB.
const PEAK_LINE: &str = "peak_rss_kib";

/// `demkit bench-map`: [`crate::map::run`], then the process's peak resident memory on stdout
/// (nothing where the system does not tell it).
pub fn map_with_peak_memory(a: &MapArgs) -> Result<u8, Failure> {
    let outcome = crate::map::run(a);
    if let Some(kib) = peak_rss_kib() {
        println!("{PEAK_LINE} {kib}");
    }
    outcome
}

/// The high-water mark of this process's resident memory, in KiB (Linux).
fn peak_rss_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find_map(|l| l.strip_prefix("VmHWM:"))?;
    line.trim().strip_suffix("kB")?.trim().parse().ok()
}

/// Runs the selected cases and prints their table (stdout) and a progress line per case
/// (stderr). Exit 0 when every case ran to its end, converged or not; 1 when some failed.
pub fn run(a: &BenchArgs) -> Result<u8, Failure> {
    if a.max_iter == Some(0) {
        return Err(Failure::input("--max-iter must be at least 1, got 0"));
    }
    let data = data_dir(a)?;
    let cases = selected(cases::suite(data.is_some(), a.scale), &a.filter)?;
    if a.list {
        for c in &cases {
            println!(
                "{}\t{}\t{}\t{}",
                c.name,
                c.method,
                c.mesh_description(),
                c.population_description()
            );
        }
        return Ok(0);
    }
    if let Some(json) = &a.json {
        crate::paths::check(&[], &[crate::paths::named("--json", json)])?;
    }
    if let Some((dir, label)) = &data {
        check_data_files(&cases, dir, label)?;
    } else if a.scale {
        eprintln!(
            "note: the real meshes' scale cases (the brain and the face subdivided) need --data \
             DIR or DEMKIT_DATA"
        );
    }
    let exe = std::env::current_exe().map_err(|e| Failure {
        code: 1,
        message: format!("cannot find the demkit executable to run the cases with: {e}"),
    })?;
    let data = data.map(|(dir, _)| dir);
    let scratch = Scratch::new()?;
    let mut results = Vec::with_capacity(cases.len());
    for (i, case) in cases.iter().enumerate() {
        eprint!("[{}/{}] {} ... ", i + 1, cases.len(), case.name);
        let load = load_average();
        let dir = scratch.dir.join(i.to_string());
        let mut result = match std::fs::create_dir(&dir) {
            Ok(()) => run_case(&exe, &dir, case, data.as_deref(), a.max_iter),
            Err(e) => failed(case, format!("cannot make {}: {e}", dir.display())),
        };
        let _ = std::fs::remove_dir_all(&dir);
        result.load_average = max_load(load, load_average());
        eprintln!("{}", result.summary());
        results.push(result);
    }
    print!("{}", table::results_table(&results));
    let growth = table::growth_table(&results);
    if !growth.is_empty() {
        println!(
            "\nGrowth with size (k: the exponent of time or memory ∝ faces^k from the size \
             before):\n"
        );
        print!("{growth}");
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let busiest = results
        .iter()
        .filter_map(|r| r.load_average)
        .reduce(f64::max);
    if let Some(load) = busiest.filter(|&l| l > cores as f64 + 0.5) {
        eprintln!(
            "note: the load average reached {load:.1} on {cores} cores: other work shared the \
             machine, so the times are longer than on an idle one"
        );
    }
    if let Some(json) = &a.json {
        let report = BenchReport {
            data: data.as_ref().map(|d| d.display().to_string()),
            scale: a.scale,
            max_iter: a.max_iter,
            cores,
            cases: &results,
        };
        crate::report::write_json(json, &report)?;
    }
    let failures = results.iter().filter(|r| !r.ran()).count();
    if failures > 0 {
        return Err(Failure {
            code: 1,
            message: format!("{failures} of {} cases failed", results.len()),
        });
    }
    Ok(0)
}

/// The system's 1-minute load average (Linux; none elsewhere).
fn load_average() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/loadavg").ok()?;
    text.split_whitespace().next()?.parse().ok()
}

/// The larger of two load averages, either of which may be unknown.
fn max_load(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.max(b)),
        (a, b) => a.or(b),
    }
}

/// `--json`: the options and every case's result.
#[derive(Serialize)]
struct BenchReport<'a> {
    data: Option<String>,
    scale: bool,
    max_iter: Option<usize>,
    cores: usize,
    cases: &'a [CaseResult],
}

/// The data directory (made absolute) and how it was named: `--data`, else `DEMKIT_DATA` when
/// set and not empty; none otherwise.
fn data_dir(a: &BenchArgs) -> Result<Option<(PathBuf, &'static str)>, Failure> {
    let (dir, label) = match (&a.data, std::env::var_os("DEMKIT_DATA")) {
        (Some(d), _) => (d.clone(), "--data"),
        (None, Some(d)) if !d.is_empty() => (PathBuf::from(d), "DEMKIT_DATA"),
        _ => return Ok(None),
    };
    let not_a_directory = || {
        Failure::input(format!(
            "{label} {}: no such directory (the papers' meshes: genus0/, genus1/, open/)",
            dir.display()
        ))
    };
    if !dir.is_dir() {
        return Err(not_a_directory());
    }
    let dir = std::fs::canonicalize(&dir).map_err(|_| not_a_directory())?;
    Ok(Some((dir, label)))
}

/// The cases whose name contains one of `filters` (all without filters); none is an error.
fn selected(cases: Vec<Case>, filters: &[String]) -> Result<Vec<Case>, Failure> {
    if filters.is_empty() {
        return Ok(cases);
    }
    let kept: Vec<Case> = cases
        .into_iter()
        .filter(|c| filters.iter().any(|f| c.name.contains(f.as_str())))
        .collect();
    if kept.is_empty() {
        return Err(Failure::input(format!(
            "--filter '{}' matches no case: `demkit bench --list` names them (--data DIR adds \
             the papers' meshes, --scale the large cases)",
            filters.join("', '")
        )));
    }
    Ok(kept)
}

/// Refuses (exit 2) a data directory without a file the selected cases read.
fn check_data_files(cases: &[Case], dir: &Path, label: &str) -> Result<(), Failure> {
    for case in cases {
        for file in case.data_files() {
            if !dir.join(&file).is_file() {
                return Err(Failure::input(format!(
                    "{label} {}: no {file} there (needed by the case {})",
                    dir.display(),
                    case.name
                )));
            }
        }
    }
    Ok(())
}

/// A scratch directory of this process under the system's temporary directory, removed with
/// everything in it when dropped.
struct Scratch {
    dir: PathBuf,
}

impl Scratch {
    fn new() -> Result<Self, Failure> {
        let base = std::env::temp_dir();
        let mut last_error = None;
        for n in 0..100 {
            let dir = base.join(format!("demkit-bench-{}-{n}", std::process::id()));
            match std::fs::create_dir(&dir) {
                Ok(()) => return Ok(Scratch { dir }),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => last_error = Some(e.to_string()),
            }
            break;
        }
        Err(Failure {
            code: 1,
            message: format!(
                "cannot make a scratch directory in {}: {}",
                base.display(),
                last_error.unwrap_or_else(|| "every name is taken".into())
            ),
        })
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// The mesh, population and torus `demkit map` is given for a case.
struct Inputs {
    mesh: PathBuf,
    population: Option<OsString>,
    torus: Option<String>,
}

/// A case without figures: it failed before or during its map.
fn failed(case: &Case, error: String) -> CaseResult {
    CaseResult {
        name: case.name.to_string(),
        suite: case.suite.name(),
        mesh: case.mesh_description(),
        population: case.population_description(),
        method: case.method.to_string(),
        ladder: case.ladder.to_string(),
        prepare_s: 0.0,
        wall_s: 0.0,
        peak_memory_mib: None,
        load_average: None,
        exit_code: None,
        figures: None,
        error: Some(error),
    }
}

/// Prepares the case's mesh in `dir`, maps it in a process of its own and reads its report.
fn run_case(
    exe: &Path,
    dir: &Path,
    case: &Case,
    data: Option<&Path>,
    max_iter: Option<usize>,
) -> CaseResult {
    let start = Instant::now();
    let inputs = prepare(exe, dir, case, data);
    let prepare_s = start.elapsed().as_secs_f64();
    let inputs = match inputs {
        Ok(i) => i,
        Err(e) => {
            let mut r = failed(case, format!("making the mesh: {e}"));
            r.prepare_s = prepare_s;
            return r;
        }
    };
    let report = dir.join("report.json");
    let mut command = Command::new(exe);
    command
        .arg("bench-map")
        .arg(&inputs.mesh)
        .arg("--out")
        .arg(dir.join("mapped.ply"))
        .arg("--report")
        .arg(&report)
        .args(["--quiet", "--method", case.method]);
    if let Some(p) = &inputs.population {
        command.arg("--population").arg(p);
    }
    if let Some(t) = &inputs.torus {
        command.arg("--torus").arg(t);
    }
    if let Some(n) = max_iter {
        command.arg("--max-iter").arg(n.to_string());
    }
    let start = Instant::now();
    let output = command.current_dir(dir).stdin(Stdio::null()).output();
    let wall_s = start.elapsed().as_secs_f64();
    let mut result = failed(case, String::new());
    result.prepare_s = prepare_s;
    result.wall_s = wall_s;
    let output = match output {
        Ok(o) => o,
        Err(e) => {
            result.error = Some(format!("cannot run {}: {e}", exe.display()));
            return result;
        }
    };
    result.exit_code = output.status.code();
    result.peak_memory_mib = String::from_utf8_lossy(&output.stdout)
        .lines()
        .rev()
        .find_map(|l| l.strip_prefix(PEAK_LINE)?.trim().parse::<f64>().ok())
        .map(|kib| kib / 1024.0);
    match read_report(&report) {
        Ok(figures) => {
            result.figures = Some(figures);
            result.error = None;
        }
        Err(e) => {
            result.error = Some(if report.exists() {
                e
            } else {
                failure_message(&output)
            })
        }
    }
    result
}

/// Makes the case's mesh (and split population) in `dir` and names its inputs.
fn prepare(exe: &Path, dir: &Path, case: &Case, data: Option<&Path>) -> Result<Inputs, String> {
    let in_data = |file: String| -> Result<PathBuf, String> {
        data.map(|d| d.join(&file))
            .ok_or_else(|| format!("{file} needs --data DIR"))
    };
    let name = match case.source {
        Source::Generated(_) => "",
        Source::Data(name) | Source::Subdivided(name, _, _) => name,
    };
    let mut population: Option<OsString> = match case.population {
        Population::Area => None,
        Population::Expression(e) => Some(e.into()),
        Population::DataFile => Some(in_data(format!("{name}.population.txt"))?.into()),
    };
    let mesh = match case.source {
        Source::Generated(args) => {
            let out = dir.join("mesh.ply");
            let mut all: Vec<OsString> = vec!["generate".into()];
            all.extend(args.iter().map(OsString::from));
            all.extend(["--out".into(), out.clone().into()]);
            tool(exe, dir, &all)?;
            out
        }
        Source::Data(_) => in_data(format!("{name}.obj"))?,
        Source::Subdivided(_, levels, parts) => {
            let out = dir.join("mesh.ply");
            let mut all: Vec<OsString> = vec![
                "subdivide".into(),
                in_data(format!("{name}.obj"))?.into(),
                "--levels".into(),
                levels.to_string().into(),
                "--parts".into(),
                parts.to_string().into(),
                "--out".into(),
                out.clone().into(),
                "--quiet".into(),
            ];
            if let (Population::DataFile, Some(file)) = (&case.population, &population) {
                let split = dir.join("population.txt");
                all.extend([
                    "--population".into(),
                    file.clone(),
                    "--population-out".into(),
                    split.clone().into(),
                ]);
                population = Some(split.into());
            }
            tool(exe, dir, &all)?;
            out
        }
    };
    let mesh = if case.holes.is_empty() {
        mesh
    } else {
        let out = dir.join("mesh-holes.ply");
        let mut all: Vec<OsString> = vec!["cut".into(), mesh.into(), "--planar".into()];
        for h in case.holes {
            all.extend(["--hole".into(), OsString::from(h)]);
        }
        all.extend(["--out".into(), out.clone().into(), "--quiet".into()]);
        tool(exe, dir, &all)?;
        out
    };
    let torus = match case.target {
        Target::None => None,
        Target::Radii(r) => Some(r.to_string()),
        Target::DataFile => Some(cases::read_torus_file(&in_data(format!(
            "{name}.torus.txt"
        ))?)?),
    };
    Ok(Inputs {
        mesh,
        population,
        torus,
    })
}

/// Runs `demkit ARGS` in `dir`; its error line when it fails.
fn tool(exe: &Path, dir: &Path, args: &[OsString]) -> Result<(), String> {
    let output = Command::new(exe)
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("cannot run {}: {e}", exe.display()))?;
    if output.status.success() {
        Ok(())
    } else {
        Err(failure_message(&output))
    }
}

/// Why a demkit process failed: its last `error:` line, or how it ended.
fn failure_message(output: &Output) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr);
    if let Some(line) = stderr.lines().rev().find_map(|l| l.strip_prefix("error: ")) {
        return line.to_string();
    }
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(signal) = output.status.signal() {
            return format!("killed by signal {signal} (9: out of memory?)");
        }
    }
    match output.status.code() {
        Some(code) => format!("exit code {code} and no report"),
        None => "ended without an exit code".into(),
    }
}

/// The figures of a `demkit map --report` file.
fn read_report(path: &Path) -> Result<Figures, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("no report: {e}"))?;
    let v: Value = serde_json::from_str(&text).map_err(|e| format!("unreadable report ({e})"))?;
    let missing = |p: &str| format!("the report has no {p}");
    let count = |p: &str| {
        v.pointer(p)
            .and_then(Value::as_u64)
            .map(|n| n as usize)
            .ok_or_else(|| missing(p))
    };
    let text_at = |p: &str| {
        v.pointer(p)
            .and_then(Value::as_str)
            .map(str::to_string)
            .ok_or_else(|| missing(p))
    };
    // NaN is written as null: shown as NaN, not refused.
    let number = |p: &str| v.pointer(p).and_then(Value::as_f64).unwrap_or(f64::NAN);
    Ok(Figures {
        method: text_at("/method")?,
        vertices: count("/input/vertices")?,
        faces: count("/input/faces")?,
        converged: v
            .pointer("/converged")
            .and_then(Value::as_bool)
            .ok_or_else(|| missing("/converged"))?,
        stop_reason: text_at("/stop_reason")?,
        iterations: count("/iterations")?,
        time_s: Times {
            init: number("/time_s/init"),
            map: number("/time_s/map"),
            total: number("/time_s/total"),
        },
        density_error_mean: number("/metrics/density_error_mean"),
        flipped_triangles: count("/metrics/flipped_triangles")?,
        notes: v
            .pointer("/notes")
            .and_then(Value::as_array)
            .map(|notes| {
                notes
                    .iter()
                    .filter_map(|n| Some(n.as_str()?.to_string()))
                    .collect()
            })
            .unwrap_or_default(),
    })
}

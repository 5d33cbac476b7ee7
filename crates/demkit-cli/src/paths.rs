//! The files a command reads and writes, checked before any computation: every output's
//! directory exists and takes new files, no output is an input, and no two outputs are the same
//! file. Files are compared as the system sees them (device and inode where a file exists), so
//! `out.obj`, `./out.obj` and a link to it are one file.

use crate::Failure;
use demkit::population::PopulationSpec;
use std::path::{Path, PathBuf};

/// One file of a command, with the option (or argument) that names it.
#[derive(Debug, Clone)]
pub struct Named<'a> {
    pub option: &'a str,
    pub path: &'a Path,
}

/// Shorthand for a [`Named`] file.
pub fn named<'a>(option: &'a str, path: &'a Path) -> Named<'a> {
    Named { option, path }
}

/// What `--population` says: `area` and `uniform` name populations (a file called `area` is
/// reached as `./area`); otherwise the name of an existing file is a population file, and
/// anything else an expression ([`demkit::population::parse`]).
pub fn population_spec(arg: &str) -> PopulationSpec {
    match demkit::population::parse(arg) {
        PopulationSpec::Expr(_) if Path::new(arg).is_file() => {
            PopulationSpec::File(PathBuf::from(arg))
        }
        spec => spec,
    }
}

/// The population file of `--population` (when it names one) and the landmark file.
pub fn method_inputs(m: &crate::args::MethodArgs) -> (Option<PathBuf>, Option<PathBuf>) {
    let population = match population_spec(&m.population) {
        PopulationSpec::File(p) => Some(p),
        _ => None,
    };
    (population, m.landmarks.clone())
}

/// The inputs `MESH`, `--population` and `--landmarks` of a command that maps a mesh.
pub fn mesh_inputs<'a>(
    mesh: &'a Path,
    population: &'a Option<PathBuf>,
    landmarks: &'a Option<PathBuf>,
) -> Vec<Named<'a>> {
    let mut v = vec![named("MESH", mesh)];
    if let Some(p) = population {
        v.push(named("--population", p));
    }
    if let Some(l) = landmarks {
        v.push(named("--landmarks", l));
    }
    v
}

/// `(option, Some(path))` pairs kept where a path is given.
pub fn given<'a>(list: &[(&'a str, Option<&'a PathBuf>)]) -> Vec<Named<'a>> {
    list.iter()
        .filter_map(|(o, p)| p.map(|p| named(o, p)))
        .collect()
}

/// How a file is told apart from others: its device and inode when it exists, else its
/// directory's canonical path and its name.
#[derive(Debug, PartialEq, Eq)]
enum Identity {
    Existing(u64, u64),
    New(PathBuf, std::ffi::OsString),
}

fn directory_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

fn identity(path: &Path) -> Option<Identity> {
    use std::os::unix::fs::MetadataExt;
    if let Ok(m) = std::fs::metadata(path) {
        return Some(Identity::Existing(m.dev(), m.ino()));
    }
    let dir = std::fs::canonicalize(directory_of(path)).ok()?;
    Some(Identity::New(dir, path.file_name()?.to_os_string()))
}

/// Checks that every output can be written and replaces neither an input nor another output.
///
/// Errors (exit 2, naming the options): an output whose directory does not exist or is not
/// writable, an output that is a directory, an output that is one of the inputs, two outputs
/// that are one file.
pub fn check(inputs: &[Named], outputs: &[Named]) -> Result<(), Failure> {
    for o in outputs {
        let dir = directory_of(o.path);
        if !dir.is_dir() {
            return Err(Failure::input(format!(
                "{} {}: the directory '{}' does not exist",
                o.option,
                o.path.display(),
                dir.display()
            )));
        }
        if o.path.is_dir() {
            return Err(Failure::input(format!(
                "{} {}: is a directory, not a file",
                o.option,
                o.path.display()
            )));
        }
        let probe = dir.join(format!(".demkit-probe-{}", std::process::id()));
        match std::fs::File::create(&probe) {
            Ok(_) => {
                let _ = std::fs::remove_file(&probe);
            }
            Err(e) => {
                return Err(Failure::input(format!(
                    "{} {}: cannot write in the directory '{}' ({e})",
                    o.option,
                    o.path.display(),
                    dir.display()
                )));
            }
        }
    }
    let ids: Vec<Option<Identity>> = outputs.iter().map(|o| identity(o.path)).collect();
    for (o, id) in outputs.iter().zip(&ids) {
        let Some(id) = id else { continue };
        for i in inputs {
            if identity(i.path).as_ref() == Some(id) {
                return Err(Failure::input(format!(
                    "{} {} would replace the input {} {}",
                    o.option,
                    o.path.display(),
                    i.option,
                    i.path.display()
                )));
            }
        }
    }
    for a in 0..outputs.len() {
        for b in a + 1..outputs.len() {
            if ids[a].is_some() && ids[a] == ids[b] {
                return Err(Failure::input(format!(
                    "{} and {} name the same file {}",
                    outputs[a].option,
                    outputs[b].option,
                    outputs[a].path.display()
                )));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("demkit-paths-{}-{tag}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn an_output_over_an_input_is_refused_even_spelled_differently() {
        let d = dir("input");
        let input = d.join("mesh.obj");
        std::fs::write(&input, "v 0 0 0\n").unwrap();
        let other = d.join(".").join("mesh.obj");
        let e = check(&[named("MESH", &input)], &[named("--out", &other)]).unwrap_err();
        assert_eq!(e.code, 2);
        assert!(
            e.message.contains("--out") && e.message.contains("MESH"),
            "{}",
            e.message
        );
    }

    #[test]
    fn two_outputs_naming_one_new_file_are_refused() {
        let d = dir("two");
        let a = d.join("r.json");
        let b = d.join(".").join("r.json");
        let e = check(&[], &[named("--out", &a), named("--report", &b)]).unwrap_err();
        assert!(e.message.contains("--out and --report"), "{}", e.message);
    }

    #[test]
    fn a_missing_directory_is_refused_and_distinct_outputs_pass() {
        let d = dir("ok");
        let missing = d.join("nodir").join("r.json");
        let e = check(&[], &[named("--report", &missing)]).unwrap_err();
        assert!(e.message.contains("does not exist"), "{}", e.message);
        let (a, b) = (d.join("a.obj"), d.join("b.json"));
        assert!(check(&[], &[named("--out", &a), named("--report", &b)]).is_ok());
    }

    #[test]
    fn population_names_win_then_existing_files_then_expressions() {
        let d = dir("population");
        let file = d.join("pop.txt");
        std::fs::write(&file, "1\n").unwrap();
        let name = file.to_str().unwrap();
        assert_eq!(population_spec(name), PopulationSpec::File(file.clone()));
        assert_eq!(population_spec("area"), PopulationSpec::Area);
        assert_eq!(population_spec(" uniform "), PopulationSpec::Uniform);
        // A directory is not a population file, nor is a file that does not exist.
        let dir_name = d.to_str().unwrap();
        assert_eq!(
            population_spec(dir_name),
            PopulationSpec::Expr(dir_name.into())
        );
        let missing = d.join("missing.txt");
        let missing = missing.to_str().unwrap();
        assert_eq!(
            population_spec(missing),
            PopulationSpec::Expr(missing.into())
        );
        assert_eq!(
            population_spec("area*(1+(x>0))"),
            PopulationSpec::Expr("area*(1+(x>0))".into())
        );
    }
}

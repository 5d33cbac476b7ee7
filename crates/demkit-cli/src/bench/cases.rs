//! The cases of `demkit bench`: meshes demkit generates (always), the papers' meshes (`--data`)
//! and the large cases (`--scale`), each with its population, method and, for tori, target.

use std::path::Path;

/// Where a case's mesh comes from.
#[derive(Debug, Clone)]
pub enum Source {
    /// `demkit generate ARGS` (a kind and its options).
    Generated(&'static [&'static str]),
    /// `DATA/NAME.obj`.
    Data(&'static str),
    /// `DATA/NAME.obj` after `demkit subdivide --levels N --parts K` (and its population file,
    /// if the case uses one, split likewise).
    Subdivided(&'static str, usize, usize),
}

/// A case's population.
#[derive(Debug, Clone)]
pub enum Population {
    /// `area`: an area-preserving map.
    Area,
    /// An expression of the face centroid and area.
    Expression(&'static str),
    /// `DATA/NAME.population.txt` (split among the faces of a subdivided mesh).
    DataFile,
}

/// The target torus of a TDEM case.
#[derive(Debug, Clone)]
pub enum Target {
    /// Not a torus.
    None,
    /// Radii `R:r`.
    Radii(&'static str),
    /// `DATA/NAME.torus.txt` (lines `R value` and `r value`).
    DataFile,
}

/// What the case is part of: its figures are compared with the other sizes of the same ladder.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Suite {
    /// Generated meshes of about 10 000 and 100 000 faces.
    Generated,
    /// The papers' meshes (`--data`).
    Data,
    /// Meshes of 0.1 to 1.6 million faces (`--scale`).
    Scale,
}

impl Suite {
    /// The suite's name in the JSON results.
    pub fn name(self) -> &'static str {
        match self {
            Suite::Generated => "generated",
            Suite::Data => "data",
            Suite::Scale => "scale",
        }
    }
}

/// One case: a mesh mapped by one method.
#[derive(Debug, Clone)]
pub struct Case {
    /// Unique name, what `--filter` matches.
    pub name: &'static str,
    /// The suite it belongs to.
    pub suite: Suite,
    /// The mesh.
    pub source: Source,
    /// The population.
    pub population: Population,
    /// The method `demkit map` runs (`--method`).
    pub method: &'static str,
    /// The target torus (tdem).
    pub target: Target,
    /// The surface this case is one size of (cases with the same ladder are compared by size);
    /// empty for none.
    pub ladder: &'static str,
    /// Holes cut into the mesh once it is made (`demkit cut --planar --hole X,Y,Z,R` for each);
    /// empty for none.
    pub holes: &'static [&'static str],
}

/// Holes around the eyes of `open/human_face` (the DEQ paper's Fig. 9), for `demkit cut
/// --planar`.
const EYES: &[&str] = &["0.028,0.265,0,0.012", "-0.028,0.265,0,0.012"];

/// The population of the generated spheres: density rising along z (README's gallery).
const SPHERE_POPULATION: &str = "area*(1+4.5*(z+1))";
/// The population of the generated tori: the TDEM paper's Fig. 5, 2 − cos u.
const TORUS_POPULATION: &str = "area*(2-cos(atan2(y,x)))";
/// The population of the generated disks: a bump magnified like a lens (README's gallery).
const DISK_POPULATION: &str = "area*(1+4*exp(-8*((x-0.3)^2+(y-0.2)^2)))";

fn generated(
    name: &'static str,
    suite: Suite,
    args: &'static [&'static str],
    method: &'static str,
) -> Case {
    let (population, target, ladder) = match method {
        "sdem" => (SPHERE_POPULATION, Target::None, "generated sphere"),
        "tdem" => (TORUS_POPULATION, Target::Radii("3:1"), "generated torus"),
        _ => (DISK_POPULATION, Target::None, "generated disk"),
    };
    Case {
        name,
        suite,
        source: Source::Generated(args),
        population: Population::Expression(population),
        method,
        target,
        ladder,
        holes: &[],
    }
}

fn data(name: &'static str, method: &'static str, population: Population) -> Case {
    let target = match method {
        "tdem" => Target::DataFile,
        _ => Target::None,
    };
    let ladder = match name {
        "genus0/brain" | "open/human_face" | "genus1/torus_1" => name,
        _ => "",
    };
    Case {
        name,
        suite: Suite::Data,
        source: Source::Data(name),
        population,
        method,
        target,
        ladder,
        holes: &[],
    }
}

fn subdivided(name: &'static str, mesh: &'static str, levels: usize, method: &'static str) -> Case {
    split(name, mesh, levels, 2, method)
}

/// `mesh` subdivided `levels` times with every edge cut in `parts`.
fn split(
    name: &'static str,
    mesh: &'static str,
    levels: usize,
    parts: usize,
    method: &'static str,
) -> Case {
    let mut case = data(mesh, method, Population::Area);
    case.name = name;
    case.suite = Suite::Scale;
    case.source = Source::Subdivided(mesh, levels, parts);
    case.ladder = mesh;
    case
}

/// Every case: the generated ones, then (with `data`) the papers' meshes, then (with `scale`)
/// the large ones; the large real ones need `data` too.
pub fn suite(data_given: bool, scale: bool) -> Vec<Case> {
    use Population::{Area, DataFile};
    let mut cases = vec![
        generated(
            "generated/sphere-20k",
            Suite::Generated,
            &["icosphere", "--subdivisions", "5"],
            "sdem",
        ),
        generated(
            "generated/sphere-82k",
            Suite::Generated,
            &["icosphere", "--subdivisions", "6"],
            "sdem",
        ),
        generated(
            "generated/torus-10k",
            Suite::Generated,
            &[
                "torus", "--R", "3", "--r", "1", "--major", "122", "--minor", "41",
            ],
            "tdem",
        ),
        generated(
            "generated/torus-100k",
            Suite::Generated,
            &[
                "torus", "--R", "3", "--r", "1", "--major", "387", "--minor", "129",
            ],
            "tdem",
        ),
        generated(
            "generated/disk-10k",
            Suite::Generated,
            &["polygon", "--sides", "6", "--rings", "41"],
            "dem",
        ),
        generated(
            "generated/disk-100k",
            Suite::Generated,
            &["polygon", "--sides", "6", "--rings", "129"],
            "dem",
        ),
    ];
    if data_given {
        cases.extend([
            data("genus0/david1", "sdem", DataFile),
            data("genus0/twistedball", "sdem", Area),
            data("genus0/maxplanck", "sdem", Area),
            data("genus0/duck", "sdem", Area),
            data("genus0/brain", "sdem", Area),
            data("open/hand", "dem", Area),
            data("open/human_face", "dem", Area),
            data("genus1/torus_1", "tdem", DataFile),
            data("genus1/torus_4", "tdem", DataFile),
            data("genus1/torus_5_1", "tdem", DataFile),
            data("genus1/bob", "tdem", Area),
            data("genus1/vertebra", "tdem", Area),
        ]);
    }
    if scale {
        cases.push(generated(
            "scale/torus-500k",
            Suite::Scale,
            &[
                "torus", "--R", "3", "--r", "1", "--major", "866", "--minor", "289",
            ],
            "tdem",
        ));
    }
    if scale && data_given {
        cases.extend([
            subdivided("scale/brain-sub1", "genus0/brain", 1, "sdem"),
            subdivided("scale/brain-sub2", "genus0/brain", 2, "sdem"),
            subdivided("scale/human_face-sub1", "open/human_face", 1, "dem"),
            subdivided("scale/human_face-sub2", "open/human_face", 2, "dem"),
            // 36 times the faces: 1.23 million, the million-face disk.
            split("scale/human_face-parts6", "open/human_face", 1, 6, "dem"),
            Case {
                population: DataFile,
                ..subdivided("scale/torus_1-sub3", "genus1/torus_1", 3, "tdem")
            },
            // Surfaces with holes at scale (DEQ): the face with its eyes cut out, 0.3 and 1.2
            // million faces.
            Case {
                holes: EYES,
                ladder: "open/human_face with eye holes",
                ..split(
                    "scale/human_face-eyes-parts3",
                    "open/human_face",
                    1,
                    3,
                    "deq",
                )
            },
            Case {
                holes: EYES,
                ladder: "open/human_face with eye holes",
                ..split(
                    "scale/human_face-eyes-parts6",
                    "open/human_face",
                    1,
                    6,
                    "deq",
                )
            },
        ]);
    }
    cases
}

impl Case {
    /// The data file `NAME.obj` this case reads, if any.
    fn data_name(&self) -> Option<&'static str> {
        match self.source {
            Source::Generated(_) => None,
            Source::Data(name) | Source::Subdivided(name, _, _) => Some(name),
        }
    }

    /// The files of the data directory this case reads, relative to it.
    pub fn data_files(&self) -> Vec<String> {
        let Some(name) = self.data_name() else {
            return Vec::new();
        };
        let mut files = vec![format!("{name}.obj")];
        if matches!(self.population, Population::DataFile) {
            files.push(format!("{name}.population.txt"));
        }
        if matches!(self.target, Target::DataFile) {
            files.push(format!("{name}.torus.txt"));
        }
        files
    }

    /// How the mesh is made, in words (for `--list` and the JSON).
    pub fn mesh_description(&self) -> String {
        let made = self.made_description();
        match self.holes.len() {
            0 => made,
            n => format!("{made}, {n} holes cut"),
        }
    }

    /// How the mesh is made before its holes are cut, in words.
    fn made_description(&self) -> String {
        match self.source {
            Source::Generated(args) => format!("generate {}", args.join(" ")),
            Source::Data(name) => format!("{name}.obj"),
            Source::Subdivided(name, levels, 2) => format!("{name}.obj subdivided {levels}x"),
            Source::Subdivided(name, levels, parts) => {
                format!("{name}.obj subdivided {levels}x in {parts} parts")
            }
        }
    }

    /// The population, in words.
    pub fn population_description(&self) -> String {
        match (&self.population, self.data_name()) {
            (Population::Area, _) => "area".into(),
            (Population::Expression(e), _) => (*e).into(),
            (Population::DataFile, Some(name)) => format!("{name}.population.txt"),
            (Population::DataFile, None) => "population file".into(),
        }
    }
}

/// The radii `R:r` of a torus file: lines `R value` and `r value` (other lines ignored).
pub fn read_torus_file(path: &Path) -> Result<String, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let value = |key: &str| -> Result<f64, String> {
        text.lines()
            .filter_map(|l| {
                let mut words = l.split_whitespace();
                Some((words.next()?, words.next()?))
            })
            .find(|(k, _)| *k == key)
            .and_then(|(_, v)| v.parse::<f64>().ok())
            .ok_or_else(|| format!("{}: no line '{key} NUMBER'", path.display()))
    };
    Ok(format!("{}:{}", value("R")?, value("r")?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_the_suites_grow_with_the_options() {
        let all = suite(true, true);
        let mut names: Vec<&str> = all.iter().map(|c| c.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), all.len());
        assert!(
            suite(false, false)
                .iter()
                .all(|c| c.suite == Suite::Generated)
        );
        assert!(suite(false, true).iter().all(|c| c.data_files().is_empty()));
        assert!(suite(true, false).iter().all(|c| c.suite != Suite::Scale));
        // Every ladder has at least two sizes.
        for c in all.iter().filter(|c| !c.ladder.is_empty()) {
            let rungs = all.iter().filter(|d| d.ladder == c.ladder).count();
            assert!(rungs >= 2, "{}", c.ladder);
        }
    }

    #[test]
    fn data_cases_name_their_files() {
        let all = suite(true, true);
        let case = |name: &str| all.iter().find(|c| c.name == name).unwrap();
        assert_eq!(
            case("genus1/torus_1").data_files(),
            [
                "genus1/torus_1.obj",
                "genus1/torus_1.population.txt",
                "genus1/torus_1.torus.txt"
            ]
        );
        assert_eq!(case("genus1/bob").data_files().len(), 2);
        assert_eq!(
            case("scale/brain-sub2").mesh_description(),
            "genus0/brain.obj subdivided 2x"
        );
        assert_eq!(
            case("scale/human_face-parts6").mesh_description(),
            "open/human_face.obj subdivided 1x in 6 parts"
        );
        assert_eq!(
            case("scale/human_face-eyes-parts6").mesh_description(),
            "open/human_face.obj subdivided 1x in 6 parts, 2 holes cut"
        );
        // A population file belongs to the uncut mesh: cases with holes take an expression
        // or the area.
        for c in all.iter().filter(|c| !c.holes.is_empty()) {
            assert!(!matches!(c.population, Population::DataFile), "{}", c.name);
        }
        let torus = case("scale/torus_1-sub3");
        assert_eq!(torus.data_files(), case("genus1/torus_1").data_files());
        assert_eq!(
            torus.population_description(),
            "genus1/torus_1.population.txt"
        );
    }

    #[test]
    fn torus_files_give_r_colon_r() {
        let dir = std::env::temp_dir().join(format!("demkit-bench-torus-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("t.torus.txt");
        std::fs::write(&file, "R 1.8999999999999999\nr 1\n").unwrap();
        assert_eq!(read_torus_file(&file).unwrap(), "1.9:1");
        std::fs::write(&file, "R 2\n").unwrap();
        assert!(
            read_torus_file(&file)
                .unwrap_err()
                .contains("no line 'r NUMBER'")
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}

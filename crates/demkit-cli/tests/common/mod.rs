//! Helpers for the command-line tests: a scratch directory per test, running the built
//! `demkit` binary in it, and small readers for the meshes it writes.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A fresh directory under the system temp dir, removed when dropped.
pub struct Scratch {
    pub dir: PathBuf,
}

impl Scratch {
    /// A new empty directory whose name contains `label`.
    pub fn new(label: &str) -> Scratch {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::SeqCst);
        let dir = std::env::temp_dir().join(format!(
            "demkit-cli-test-{}-{n}-{label}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create scratch directory");
        Scratch { dir }
    }

    /// The path of `name` inside the directory.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Writes `content` to `name` in the directory.
    pub fn write(&self, name: &str, content: impl AsRef<[u8]>) {
        std::fs::write(self.path(name), content).expect("write test file");
    }

    /// Reads `name` from the directory as text.
    pub fn read(&self, name: &str) -> String {
        std::fs::read_to_string(self.path(name))
            .unwrap_or_else(|e| panic!("cannot read {name}: {e}"))
    }

    /// Reads `name` from the directory as bytes.
    pub fn read_bytes(&self, name: &str) -> Vec<u8> {
        std::fs::read(self.path(name)).unwrap_or_else(|e| panic!("cannot read {name}: {e}"))
    }

    /// Runs `demkit ARGS` with the directory as working directory.
    pub fn run(&self, args: &[&str]) -> Output {
        let out = Command::new(env!("CARGO_BIN_EXE_demkit"))
            .args(args)
            .current_dir(&self.dir)
            .env("RUST_BACKTRACE", "1")
            .output()
            .expect("run demkit");
        Output {
            args: args.iter().map(|s| s.to_string()).collect(),
            code: out.status.code(),
            stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
            stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        }
    }

    /// Runs `demkit ARGS` and asserts exit code 0.
    pub fn ok(&self, args: &[&str]) -> Output {
        let out = self.run(args);
        out.assert_code(0);
        out
    }

    /// Runs `demkit generate ...` and asserts it succeeds.
    pub fn generate(&self, args: &[&str]) {
        let mut all = vec!["generate"];
        all.extend_from_slice(args);
        self.ok(&all);
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// What a run of the binary produced.
pub struct Output {
    pub args: Vec<String>,
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

impl Output {
    /// Asserts the exit code, showing the run on failure.
    pub fn assert_code(&self, code: i32) {
        assert_eq!(
            self.code,
            Some(code),
            "demkit {:?}: expected exit code {code}\nstdout:\n{}\nstderr:\n{}",
            self.args,
            self.stdout,
            self.stderr
        );
    }

    /// Asserts a bad-input failure: exit code 2, exactly one stderr line beginning `error:`
    /// (the last one), no panic text; returns that line.
    pub fn input_error(&self) -> String {
        self.assert_code(2);
        for bad in [
            "panicked",
            "RUST_BACKTRACE",
            "stack backtrace",
            "internal error",
        ] {
            assert!(
                !self.stderr.contains(bad),
                "demkit {:?}: stderr contains '{bad}':\n{}",
                self.args,
                self.stderr
            );
        }
        let lines: Vec<&str> = self
            .stderr
            .lines()
            .filter(|l| !l.trim().is_empty())
            .collect();
        let errors: Vec<&&str> = lines.iter().filter(|l| l.starts_with("error:")).collect();
        assert_eq!(
            errors.len(),
            1,
            "demkit {:?}: expected one 'error:' line on stderr, got:\n{}",
            self.args,
            self.stderr
        );
        assert_eq!(
            lines.last(),
            errors.first().copied(),
            "demkit {:?}: the 'error:' line should be the last line of stderr:\n{}",
            self.args,
            self.stderr
        );
        errors[0].to_string()
    }

    /// Asserts a bad-input failure whose message contains every one of `needles`
    /// (case-insensitive); returns the message.
    pub fn input_error_naming(&self, needles: &[&str]) -> String {
        let line = self.input_error();
        let lower = line.to_lowercase();
        for n in needles {
            assert!(
                lower.contains(&n.to_lowercase()),
                "demkit {:?}: the error should mention '{n}', got: {line}",
                self.args
            );
        }
        line
    }
}

/// A mesh read back from a file the binary wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    pub positions: Vec<[f64; 3]>,
    pub faces: Vec<[usize; 3]>,
}

impl Mesh {
    /// Vertices on boundary edges (edges used by exactly one face).
    pub fn boundary_vertices(&self) -> Vec<usize> {
        let mut count = std::collections::HashMap::<(usize, usize), usize>::new();
        for f in &self.faces {
            for k in 0..3 {
                let (a, b) = (f[k], f[(k + 1) % 3]);
                *count.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        let mut on = vec![false; self.positions.len()];
        for ((a, b), c) in count {
            if c == 1 {
                on[a] = true;
                on[b] = true;
            }
        }
        (0..on.len()).filter(|&v| on[v]).collect()
    }

    /// Face centroids, computed as (a + b + c) / 3 per coordinate.
    pub fn centroids(&self) -> Vec<[f64; 3]> {
        self.faces
            .iter()
            .map(|f| {
                let c = [
                    self.positions[f[0]],
                    self.positions[f[1]],
                    self.positions[f[2]],
                ];
                std::array::from_fn(|k| (c[0][k] + c[1][k] + c[2][k]) / 3.0)
            })
            .collect()
    }

    /// Faces whose signed area in the xy-plane has the sign opposite to the majority or is zero
    /// (DESIGN's planar `flipped_triangles`).
    pub fn planar_flipped(&self) -> usize {
        let signs: Vec<f64> = self
            .faces
            .iter()
            .map(|f| {
                let [a, b, c] = [
                    self.positions[f[0]],
                    self.positions[f[1]],
                    self.positions[f[2]],
                ];
                (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
            })
            .collect();
        let pos = signs.iter().filter(|&&s| s > 0.0).count();
        let neg = signs.iter().filter(|&&s| s < 0.0).count();
        let majority_positive = pos >= neg;
        signs
            .iter()
            .filter(|&&s| {
                if majority_positive {
                    s <= 0.0
                } else {
                    s >= 0.0
                }
            })
            .count()
    }
}

/// The `v` and `f` statements of an OBJ text (triangles, plain 1-based indices as demkit writes
/// them), and the `f` lines verbatim.
pub fn parse_obj(text: &str) -> (Mesh, Vec<String>) {
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    let mut face_lines = Vec::new();
    for line in text.lines() {
        let mut t = line.split_whitespace();
        match t.next() {
            Some("v") => {
                let p: Vec<f64> = t.map(|x| x.parse().expect("vertex coordinate")).collect();
                assert!(p.len() >= 3, "short vertex line: {line}");
                positions.push([p[0], p[1], p[2]]);
            }
            Some("f") => {
                let f: Vec<usize> = t
                    .map(|x| {
                        x.split('/')
                            .next()
                            .unwrap()
                            .parse::<usize>()
                            .expect("face index")
                            - 1
                    })
                    .collect();
                assert_eq!(f.len(), 3, "non-triangle face line: {line}");
                faces.push([f[0], f[1], f[2]]);
                face_lines.push(line.trim().to_string());
            }
            _ => {}
        }
    }
    (Mesh { positions, faces }, face_lines)
}

/// Reads a binary little-endian PLY as demkit writes it (double x y z; uchar/int face lists);
/// returns the header's vertex and face counts and the mesh.
pub fn parse_ply(bytes: &[u8]) -> ((usize, usize), Mesh) {
    let end = b"end_header\n";
    let at = bytes
        .windows(end.len())
        .position(|w| w == end)
        .expect("PLY header ends with end_header");
    let header = std::str::from_utf8(&bytes[..at]).expect("ASCII PLY header");
    assert!(header.starts_with("ply\n"), "not a PLY file: {header}");
    let count = |element: &str| -> usize {
        header
            .lines()
            .find_map(|l| l.strip_prefix(&format!("element {element} ")))
            .unwrap_or_else(|| panic!("no 'element {element}' in PLY header:\n{header}"))
            .trim()
            .parse()
            .expect("element count")
    };
    let (nv, nf) = (count("vertex"), count("face"));
    assert!(
        header.contains("format binary_little_endian 1.0")
            && header.contains("property double x")
            && header.contains("property list uchar int vertex_indices"),
        "unexpected PLY layout (update the test reader):\n{header}"
    );
    let mut body = &bytes[at + end.len()..];
    assert_eq!(body.len(), nv * 24 + nf * 13, "PLY body size");
    let mut positions = Vec::with_capacity(nv);
    for _ in 0..nv {
        let p: [f64; 3] =
            std::array::from_fn(|k| f64::from_le_bytes(body[8 * k..8 * k + 8].try_into().unwrap()));
        positions.push(p);
        body = &body[24..];
    }
    let mut faces = Vec::with_capacity(nf);
    for _ in 0..nf {
        assert_eq!(body[0], 3, "non-triangle PLY face");
        let f: [usize; 3] = std::array::from_fn(|k| {
            i32::from_le_bytes(body[1 + 4 * k..5 + 4 * k].try_into().unwrap()) as usize
        });
        faces.push(f);
        body = &body[13..];
    }
    ((nv, nf), Mesh { positions, faces })
}

/// Parses JSON text, with the text in the panic message if it is not JSON.
pub fn json(text: &str) -> serde_json::Value {
    serde_json::from_str(text).unwrap_or_else(|e| panic!("invalid JSON ({e}):\n{text}"))
}

/// Reads a JSON file.
pub fn json_file(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    json(&text)
}

/// The variance a method's report judges its density equalization by: the face density's
/// (`face_density_var_*`, the DEQ paper's Var(ρ̃)) for DEQ and LDEQ, the vertex density's
/// (`density_var_*`) for the other methods.
pub fn equalized_variance(method: &str) -> &'static str {
    match method {
        "deq" | "ldeq" => "face_density_var",
        _ => "density_var",
    }
}

/// Asserts that the map a `demkit map` report describes made the density more even: the
/// method's variance ([`equalized_variance`]) is positive on the initial map (the population is
/// not already equalized there, else there is nothing to check) and lower on the final map;
/// and, when the caller knows `density_error_mean` on the initial map (`initial_error`), the
/// final `density_error_mean` is below it.
pub fn assert_density_improved(report: &serde_json::Value, initial_error: Option<f64>) {
    let method = report["method"]
        .as_str()
        .unwrap_or_else(|| panic!("report without a method:\n{report:#}"));
    let metric = |name: &str| -> f64 {
        report["metrics"][name]
            .as_f64()
            .unwrap_or_else(|| panic!("report without metrics.{name}:\n{report:#}"))
    };
    let variance = equalized_variance(method);
    let (initial, last) = (
        metric(&format!("{variance}_initial")),
        metric(&format!("{variance}_final")),
    );
    assert!(
        initial > 0.0,
        "{method}: {variance}_initial is {initial}: a trivial population, nothing equalized"
    );
    assert!(
        last < initial,
        "{method}: {variance} did not improve: {initial} on the initial map, {last} on the final \
         one\n{report:#}"
    );
    if let Some(initial_error) = initial_error {
        let error = metric("density_error_mean");
        assert!(
            error < initial_error,
            "{method}: density_error_mean {error} is not below the initial map's \
             {initial_error}\n{report:#}"
        );
    }
}

//! The `demkit` command line: density-equalizing maps of triangulated surfaces.
//!
//! Exit codes: 0 success; 2 bad input or arguments (one `error:` line on stderr); 3 not
//! converged within `--max-iter` (result and report still written); 1 anything else.

mod args;
mod bench;
mod cartogram;
mod cartogram_png;
mod cut;
mod generate;
mod info;
mod map;
mod paths;
mod progress;
mod register;
mod remesh;
mod render;
mod report;
mod subdivide;
mod surface;

use clap::Parser;
use std::process::ExitCode;

/// A failure with the exit code it ends the process with.
pub struct Failure {
    /// Process exit code (1 or 2).
    pub code: u8,
    /// The message after `error: `.
    pub message: String,
}

impl From<demkit::Error> for Failure {
    fn from(e: demkit::Error) -> Self {
        Failure {
            code: if e.is_input_error() { 2 } else { 1 },
            message: with_flag_names(&e),
        }
    }
}

/// The library's parameters and the flags that set them.
const FLAGS: [(&str, &str); 19] = [
    ("landmarks", "--landmarks"),
    ("torus", "--torus"),
    ("fixed_holes", "--no-geometry-update"),
    ("epsilon", "--epsilon"),
    ("dt", "--dt"),
    ("max_iter", "--max-iter"),
    ("alpha", "--alpha"),
    ("beta", "--beta"),
    ("gamma", "--gamma"),
    ("vertices", "--vertices"),
    ("grid", "--grid"),
    ("shape", "--shape"),
    ("ellipsoid", "--ellipsoid"),
    ("key", "--key"),
    ("value", "--value"),
    ("sphere", "--sphere"),
    ("project", "--project"),
    ("levels", "--levels"),
    ("parts", "--parts"),
];

/// The flag that sets the library's `parameter` (the parameter itself when no flag does).
pub fn flag(parameter: &str) -> &str {
    FLAGS
        .iter()
        .find(|(p, _)| *p == parameter)
        .map_or(parameter, |(_, f)| f)
}

/// The error's message, with the library's parameters named by their flags: an argument error
/// that starts with a parameter ("epsilon must be positive" → "--epsilon must be positive"), and
/// a parameter in backquotes anywhere in any message ("no column 'gdp' (`value`)" →
/// "no column 'gdp' (--value)").
fn with_flag_names(e: &demkit::Error) -> String {
    let mut message = e.to_string();
    if let demkit::Error::Argument(msg) = e {
        for (parameter, flag) in FLAGS {
            if let Some(rest) = msg.strip_prefix(parameter).filter(|r| r.starts_with(' ')) {
                message = demkit::Error::Argument(format!("{flag}{rest}")).to_string();
                break;
            }
        }
    }
    for (parameter, flag) in FLAGS {
        message = message.replace(&format!("`{parameter}`"), flag);
    }
    message
}

impl Failure {
    /// A subcommand that is not built yet (exit code 1).
    pub fn not_implemented(what: &str) -> Self {
        Failure {
            code: 1,
            message: format!("{what} is not implemented yet"),
        }
    }

    /// A bad-input failure (exit code 2).
    pub fn input(message: impl Into<String>) -> Self {
        Failure {
            code: 2,
            message: message.into(),
        }
    }
}

/// Refuses (exit 2) a path to be written whose extension is none of `allowed` (compared
/// without case); `what` says what is written there, e.g. "pictures are written as .png".
pub fn require_extension(
    path: &std::path::Path,
    allowed: &[&str],
    what: &str,
) -> Result<(), Failure> {
    let ok = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| allowed.iter().any(|a| e.eq_ignore_ascii_case(a)));
    if ok {
        Ok(())
    } else {
        Err(Failure::input(format!(
            "cannot write '{}': {what}",
            path.display()
        )))
    }
}

/// clap's message on one line: its first line, and when that ends with a colon (the missing
/// arguments, the possible values) the indented lines that follow, joined.
fn one_line(text: &str) -> String {
    let mut lines = text.lines();
    let first = lines.next().unwrap_or("invalid arguments").trim();
    let first = first.strip_prefix("error: ").unwrap_or(first);
    if !first.ends_with(':') {
        return first.to_string();
    }
    let items: Vec<&str> = lines
        .take_while(|l| l.starts_with(char::is_whitespace) && !l.trim().is_empty())
        .map(str::trim)
        .collect();
    format!("{} {}", first, items.join(", "))
}

/// The stack of every rayon worker thread, 8 MiB (the usual main-thread stack).
const WORKER_STACK: usize = 8 << 20;

fn main() -> ExitCode {
    // A bug must never show a panic trace: report it on one line and exit with 1.
    std::panic::set_hook(Box::new(|info| {
        let msg = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown".into());
        let at = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        eprintln!("error: internal error ({msg}{at}); please report it");
    }));
    let cli = match args::Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            use clap::error::ErrorKind;
            if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
                // No subcommand (or no kind of `generate`): the usage, on stderr, as an error.
                eprint!("{e}");
                eprintln!("error: a subcommand is required (see demkit --help)");
                return ExitCode::from(2);
            }
            if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
                let _ = e.print();
                return ExitCode::SUCCESS;
            }
            eprintln!("error: {} (see demkit --help)", one_line(&e.to_string()));
            return ExitCode::from(2);
        }
    };
    // rayon's workers get the main thread's stack size (their default is a quarter of it):
    // the command runs on one of them. If the pool exists already this changes nothing.
    let _ = rayon::ThreadPoolBuilder::new()
        .stack_size(WORKER_STACK)
        .build_global();
    // The command runs on a thread of rayon's pool: the library's parallel loops then start
    // from a worker, which splits them with the other workers directly, instead of handing
    // each loop to the pool from outside and sleeping until it is done (two context switches
    // per loop, thousands of loops per map).
    let outcome = std::panic::catch_unwind(|| {
        rayon::scope(|_| match cli.command {
            args::Command::Info(a) => info::run(&a),
            args::Command::Map(a) => map::run(&a),
            args::Command::Generate(a) => generate::run(&a),
            args::Command::Remesh(a) => remesh::run(&a),
            args::Command::Cartogram(a) => cartogram::run(&a),
            args::Command::Register(a) => register::run(&a),
            args::Command::Render(a) => render::run(&a),
            args::Command::Subdivide(a) => subdivide::run(&a),
            args::Command::Cut(a) => cut::run(&a),
            args::Command::Bench(a) => bench::run(&a),
            args::Command::BenchMap(a) => bench::map_with_peak_memory(&a),
        })
    });
    match outcome {
        Ok(Ok(code)) => ExitCode::from(code),
        Ok(Err(f)) => {
            eprintln!("error: {}", f.message);
            ExitCode::from(f.code)
        }
        Err(_) => ExitCode::from(1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clap_lists_are_joined_on_the_error_line() {
        let text = "error: the following required arguments were not provided:\n  --out <OUT>\n  <MESH>\n\nUsage: demkit map\n";
        assert_eq!(
            one_line(text),
            "the following required arguments were not provided: --out <OUT>, <MESH>"
        );
        assert_eq!(
            one_line("error: unexpected argument 'x' found\n\nUsage: demkit"),
            "unexpected argument 'x' found"
        );
    }

    #[test]
    fn library_parameters_are_named_by_their_flags() {
        let argument = demkit::Error::Argument("epsilon must be positive, not 0".into());
        assert!(with_flag_names(&argument).contains("--epsilon must be positive"));
        // "epsilonx" is no parameter: left as it is.
        let other = demkit::Error::Argument("epsilonx must be positive".into());
        assert!(with_flag_names(&other).contains("epsilonx must be positive"));
        let format = demkit::Error::Format {
            path: "w.csv".into(),
            msg: "no column 'gdp' (`value`) in the header code,pop".into(),
        };
        let message = with_flag_names(&format);
        assert!(message.contains("(--value)"), "{message}");
        assert!(!message.contains('`'), "{message}");
    }
}

//! The library's error type: every failure caused by user input names what is wrong and where.

/// Errors returned by demkit. None of them is a panic: user input never panics.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be opened, read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file concerned.
        path: String,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A line of a text file could not be parsed.
    #[error("{path}:{line}: {msg}")]
    Parse {
        /// The file concerned.
        path: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        msg: String,
    },
    /// A file is malformed as a whole (empty, truncated, unknown format, ...).
    #[error("{path}: {msg}")]
    Format {
        /// The file concerned.
        path: String,
        /// What is wrong.
        msg: String,
    },
    /// The mesh fails validation (the message names the face, vertex or edge).
    #[error("invalid mesh: {0}")]
    InvalidMesh(String),
    /// The mesh's topology does not fit the requested method.
    #[error("wrong topology for {method}: {msg}")]
    Topology {
        /// The method that was asked for.
        method: String,
        /// What the mesh is and what the method needs.
        msg: String,
    },
    /// The population is unusable (wrong length, non-positive, not finite, bad expression).
    #[error("invalid population: {0}")]
    Population(String),
    /// The landmarks are unusable (index out of range, target off the domain, ...).
    #[error("invalid landmarks: {0}")]
    Landmarks(String),
    /// An option or argument is out of its range.
    #[error("invalid argument: {0}")]
    Argument(String),
    /// A numerical step failed (a factorization broke down, ...): not the user's fault.
    #[error("numerical failure: {0}")]
    Numerical(String),
}

impl Error {
    /// True when the error is caused by the input (files, mesh, arguments): exit code 2.
    pub fn is_input_error(&self) -> bool {
        !matches!(self, Error::Numerical(_))
    }
}

/// Result alias used throughout demkit.
pub type Result<T> = std::result::Result<T, Error>;

//! Reading and writing files: cage OBJ files and point lists.
//!
//! Every error names the file, and for text formats the 1-based line, with the reason.

mod obj_cage;
mod points;

use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::cage::CageError;

pub use obj_cage::{ObjCageGroup, ObjCages, parse_obj_cages, read_cage_obj, read_obj_cages};
pub use points::{parse_points, read_points};

/// A file could not be read as what was asked for.
#[derive(Debug, Error)]
pub enum FileError {
    /// The file could not be opened or read.
    #[error("{path}: cannot read: {error}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The system's reason (part of the message, so not a `source`).
        error: std::io::Error,
    },
    /// A line could not be parsed.
    #[error("{path}:{line}: {reason}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong and what was expected.
        reason: String,
    },
    /// The file parsed but its content is not a valid cage.
    #[error("{path}: invalid cage: {problem}")]
    InvalidCage {
        /// The file.
        path: PathBuf,
        /// The cage problem (element indices are 0-based, in file order).
        problem: CageError,
    },
}

impl FileError {
    pub(crate) fn parse(path: &Path, line: usize, reason: impl Into<String>) -> Self {
        Self::Parse {
            path: path.to_path_buf(),
            line,
            reason: reason.into(),
        }
    }
}

pub(crate) fn read_text(path: &Path) -> Result<String, FileError> {
    let bytes = std::fs::read(path).map_err(|error| FileError::Io {
        path: path.to_path_buf(),
        error,
    })?;
    String::from_utf8(bytes).map_err(|e| {
        let line = 1 + e.as_bytes()[..e.utf8_error().valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        FileError::parse(path, line, "not UTF-8 text; is this really a text file?")
    })
}

/// Parses one finite float token, with a reason naming the token on failure.
pub(crate) fn parse_finite(token: &str, what: &str) -> Result<f64, String> {
    let value: f64 = token
        .parse()
        .map_err(|_| format!("{what} '{token}' is not a number"))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("{what} '{token}' is not finite (NaN or infinity)"))
    }
}

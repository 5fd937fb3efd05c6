//! Paths as the subcommands compare them.

use std::path::Path;

/// Whether two paths name one existing file or folder.
pub fn same_path(a: &Path, b: &Path) -> bool {
    matches!(
        (std::fs::canonicalize(a), std::fs::canonicalize(b)),
        (Ok(a), Ok(b)) if a == b
    )
}

//! Paths as the subcommands compare and check them.

use std::path::Path;

/// Whether two paths name one existing file or folder.
pub fn same_path(a: &Path, b: &Path) -> bool {
    matches!(
        (std::fs::canonicalize(a), std::fs::canonicalize(b)),
        (Ok(a), Ok(b)) if a == b
    )
}

/// Checks, before anything is drawn, that `path` (given as `flag`) names a PNG, the format
/// the frames are written in: bad input, said in one line, not a failed write afterwards.
pub fn png_path(flag: &str, path: &Path) -> anyhow::Result<()> {
    let png = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !png {
        anyhow::bail!(
            "{flag} {}: images are written as PNG: give a path ending in .png",
            path.display()
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_png_paths_pass() {
        for ok in ["frame.png", "out/a.PNG", "/tmp/x.y.png"] {
            png_path("--out", Path::new(ok)).unwrap();
        }
        for bad in ["frame.jpg", "frame", "png", "dir/", "a.png.gif"] {
            let e = png_path("--out", Path::new(bad)).unwrap_err().to_string();
            assert!(e.starts_with(&format!("--out {bad}")), "{e}");
        }
    }
}

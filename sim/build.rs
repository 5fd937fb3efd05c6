//! Records the git commit the binary is built from, for `summary.json`'s `git_commit`, where
//! the build can tell (a git checkout with `git` on the PATH); otherwise it stays unset and
//! the field is left out.

use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    if !out.status.success() {
        return None;
    }
    let text = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (!text.is_empty()).then_some(text)
}

fn main() {
    println!("cargo:rerun-if-env-changed=CARFOLLOW_GIT_COMMIT");
    if let Some(commit) = git(&["rev-parse", "HEAD"]) {
        println!("cargo:rustc-env=CARFOLLOW_GIT_COMMIT={commit}");
        // Rebuild when the checked-out commit moves: HEAD itself, and the branch it names
        // (its own file, or the packed refs once git packs it). Only files that exist: cargo
        // runs a build script whose watched file is missing at every build, and so rebuilt
        // this crate, its binary and its tests each time (`packed-refs` is absent until git
        // packs a ref; packing removes the branch's own file, which reruns this).
        let mut watched = vec!["HEAD".to_string(), "packed-refs".to_string()];
        watched.extend(git(&["symbolic-ref", "-q", "HEAD"]));
        for what in watched {
            if let Some(path) = git(&["rev-parse", "--git-path", &what]) {
                if std::path::Path::new(&path).exists() {
                    println!("cargo:rerun-if-changed={path}");
                }
            }
        }
    }
}

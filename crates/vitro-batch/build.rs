//! Records the git commit being built (`VITRO_GIT_HASH`, or `unknown` outside a git
//! checkout) for result manifests, and rebuilds when HEAD moves.

use std::path::Path;
use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()?;
    if !out.status.success() {
        return None;
    }
    let s = String::from_utf8(out.stdout).ok()?.trim().to_owned();
    (!s.is_empty()).then_some(s)
}

fn main() {
    let hash = git(&["rev-parse", "HEAD"])
        .filter(|h| h.len() == 40 && h.chars().all(|c| c.is_ascii_hexdigit()))
        .unwrap_or_else(|| "unknown".to_owned());
    println!("cargo:rustc-env=VITRO_GIT_HASH={hash}");
    // Rebuild when HEAD points elsewhere or its branch moves. Only files that exist are
    // watched: cargo takes a missing one for changed, and would rebuild on every run.
    let watch = |path: &Path| {
        if path.exists() {
            println!("cargo:rerun-if-changed={}", path.display());
        }
    };
    if let Some(dir) = git(&["rev-parse", "--absolute-git-dir"]) {
        let dir = Path::new(&dir);
        watch(&dir.join("HEAD"));
        let common = git(&["rev-parse", "--git-common-dir"])
            .map(|c| Path::new(env!("CARGO_MANIFEST_DIR")).join(c))
            .unwrap_or_else(|| dir.to_owned());
        watch(&common.join("packed-refs"));
        if let Some(head_ref) = git(&["symbolic-ref", "-q", "HEAD"]) {
            watch(&common.join(head_ref));
        }
    }
    println!("cargo:rerun-if-changed=build.rs");
}

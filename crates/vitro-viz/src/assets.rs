//! The page and its scripts, compiled into the binary (debug builds too): no CDN, no network.
//!
//! `assets/vendor/three/` holds three.js 0.187.0 (MIT, `assets/vendor/three/LICENSE`), loaded
//! through the page's import map.

use rust_embed::RustEmbed;

#[derive(RustEmbed)]
#[folder = "assets/"]
struct Assets;

/// The embedded file at `path` (relative, e.g. `"js/main.js"`) and its MIME type.
pub fn get(path: &str) -> Option<(Vec<u8>, String)> {
    let file = Assets::get(path)?;
    let mime = file.metadata.mimetype().to_owned();
    Some((file.data.into_owned(), mime))
}

/// Paths of every embedded file.
pub fn paths() -> impl Iterator<Item = String> {
    Assets::iter().map(|p| p.into_owned())
}

//! Where a glTF file's external resources (its `.bin` buffers and image files) may be read
//! from: inside the model's own folder, or a folder the user allowed (`--allow-folder DIR`,
//! `[scene] allow_folder`). A URI is percent-decoded, joined to the model's folder, normalised
//! and its symbolic links followed before it is checked, so `../../etc/passwd`, `/etc/passwd`,
//! `file:///etc/passwd`, `%2e%2e/…` and a link pointing out of the folder are all refused: on
//! a farm or a service rendering other people's models, a model must not read the machine's
//! files (`export` would write them back out as geometry).

use std::fmt;
use std::path::{Component, Path, PathBuf};
use std::str::FromStr;

use crate::error::{Result, escaped, escaped_path, input_error};

/// A folder the user allows a model's resources to come from besides its own (the
/// `allow_folder` setting): none by default.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct AllowedFolder(pub Option<PathBuf>);

impl AllowedFolder {
    /// No folder besides the model's own.
    pub const NONE: AllowedFolder = AllowedFolder(None);
}

impl fmt::Display for AllowedFolder {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.0 {
            None => write!(f, "none"),
            Some(p) => write!(f, "{}", escaped_path(p)),
        }
    }
}

impl FromStr for AllowedFolder {
    type Err = String;

    /// A folder's path; `none` (a folder of that name is `./none`) allows none.
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "" => Err("needs a folder".into()),
            "none" => Ok(AllowedFolder::NONE),
            _ => Ok(AllowedFolder(Some(PathBuf::from(s)))),
        }
    }
}

/// The folders a model's resources may be read from, each canonical (absolute, its links
/// followed).
#[derive(Clone, Debug)]
pub struct Confinement {
    /// The model's folder first; `None` when it cannot be resolved (a model given as bytes
    /// with a made-up path), and then only the allowed folders are open.
    model_folder: Option<PathBuf>,
    allowed: Vec<PathBuf>,
}

impl Confinement {
    /// The folder of the model file `model`, and `allowed`. An allowed folder that cannot be
    /// resolved (missing, unreadable) is an error naming it.
    pub fn of_model(model: &Path, allowed: &AllowedFolder) -> Result<Confinement> {
        let parent = match model.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        let mut allowed_folders = Vec::new();
        if let Some(folder) = &allowed.0 {
            let real = std::fs::canonicalize(folder).map_err(|e| {
                input_error(
                    folder,
                    format!("the allowed folder (--allow-folder, [scene] allow_folder) cannot be opened: {e}"),
                )
            })?;
            if !real.is_dir() {
                return Err(input_error(
                    folder,
                    "the allowed folder (--allow-folder, [scene] allow_folder) is not a folder",
                ));
            }
            allowed_folders.push(real);
        }
        Ok(Confinement {
            model_folder: std::fs::canonicalize(parent).ok(),
            allowed: allowed_folders,
        })
    }

    /// Whether `path` (absolute, normalised) lies in one of the folders.
    fn admits(&self, path: &Path) -> bool {
        self.model_folder
            .iter()
            .chain(&self.allowed)
            .any(|root| path.starts_with(root))
    }

    /// The file a (non-`data:`) URI names, resolved and checked: percent-decoded, relative to
    /// the model's folder (`file://` URIs are absolute), normalised (`.` and `..` taken
    /// away), then its links followed. `Err` says why it is refused, the URI escaped.
    pub fn resolve(&self, uri: &str) -> std::result::Result<PathBuf, String> {
        let shown = escaped(uri);
        let decoded = if let Some(rest) = uri.strip_prefix("file://") {
            // `file:///x` and `file://localhost/x`; a URI naming another host is not a file here.
            let local = rest.strip_prefix("localhost").unwrap_or(rest);
            if !local.starts_with('/') {
                return Err(format!("'{shown}' names a file on another host"));
            }
            percent_decode(local)
        } else if uri.contains(':') {
            return Err(format!("unsupported URI scheme in '{shown}'"));
        } else {
            percent_decode(uri)
        };
        let base = self.model_folder.clone().unwrap_or_default();
        let outside = || {
            let folder = self
                .model_folder
                .as_deref()
                .map_or_else(|| "?".to_string(), escaped_path);
            format!(
                "'{shown}' lies outside the model's folder {folder}; to read files elsewhere, \
                 allow their folder with --allow-folder DIR or [scene] allow_folder"
            )
        };
        let lexical = normalise(&base.join(decoded));
        if !self.admits(&lexical) {
            return Err(outside());
        }
        // Links are followed only once the path is known to start inside, so the answer
        // never says whether a file elsewhere exists.
        let real = std::fs::canonicalize(&lexical)
            .map_err(|e| format!("cannot read external file '{shown}': {e}"))?;
        if !self.admits(&real) {
            return Err(outside());
        }
        Ok(real)
    }
}

/// `path` with `.` removed and each `..` taking away the component before it (never above the
/// root), without touching the file system.
fn normalise(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// Decodes `%XX` escapes; invalid escapes are kept literally, invalid UTF-8 replaced.
fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            let hex = std::str::from_utf8(&bytes[i + 1..i + 3])
                .ok()
                .and_then(|h| u8::from_str_radix(h, 16).ok());
            if let Some(b) = hex {
                out.push(b);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalising_takes_dots_away_without_climbing_above_the_root() {
        assert_eq!(normalise(Path::new("/a/b/../c/./d")), Path::new("/a/c/d"));
        assert_eq!(normalise(Path::new("/a/../../../etc")), Path::new("/etc"));
    }

    /// Issue 39: every spelling of a file outside the model's folder is refused; a `..` that
    /// climbs out and back in, and an allowed folder, are not.
    #[test]
    fn only_files_inside_the_model_folder_or_an_allowed_one_resolve() {
        let dir = tempfile::tempdir().unwrap();
        let model_dir = dir.path().join("model");
        let other = dir.path().join("other");
        std::fs::create_dir_all(&model_dir).unwrap();
        std::fs::create_dir_all(&other).unwrap();
        std::fs::write(model_dir.join("a.bin"), b"a").unwrap();
        std::fs::write(other.join("b.bin"), b"b").unwrap();
        std::os::unix::fs::symlink(other.join("b.bin"), model_dir.join("link.bin")).unwrap();
        let model = model_dir.join("m.gltf");
        let own = Confinement::of_model(&model, &AllowedFolder::NONE).unwrap();
        for uri in [
            "../../../etc/passwd",
            "/etc/passwd",
            "file:///etc/passwd",
            "%2e%2e/%2e%2e/x.bin",
            "link.bin",
            "../other/b.bin",
            "file://host/etc/passwd",
            "http://example.com/a.bin",
        ] {
            assert!(own.resolve(uri).is_err(), "{uri} resolved");
        }
        assert!(own.resolve("../model/a.bin").is_ok());
        assert!(own.resolve("./a%2ebin").is_ok());
        let allowing = Confinement::of_model(&model, &AllowedFolder(Some(other.clone()))).unwrap();
        assert!(allowing.resolve("link.bin").is_ok());
        assert!(allowing.resolve("../other/b.bin").is_ok());
        assert!(allowing.resolve("/etc/passwd").is_err());
        let missing = AllowedFolder(Some(dir.path().join("missing")));
        assert!(Confinement::of_model(&model, &missing).is_err());
    }

    #[test]
    fn a_refusal_names_the_uri_escaped() {
        let dir = tempfile::tempdir().unwrap();
        let own = Confinement::of_model(&dir.path().join("m.gltf"), &AllowedFolder::NONE).unwrap();
        let why = own.resolve("/etc/\u{1b}[2J\npasswd").unwrap_err();
        assert!(why.contains("'/etc/\\u{1b}[2J\\npasswd'"), "{why}");
        assert!(!why.chars().any(char::is_control), "{why}");
    }
}

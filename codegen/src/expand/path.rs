//! The path in `#[chain(file = …)]`, `#[chain(urdf = …)]` and `#[chain(mjcf = …)]`: resolved against the crate's
//! directory, and the errors about it, each with its likely cause where there is one: the other
//! key (`file = "x.urdf"`), a xacro file not yet expanded, a path missing its extension, a path
//! written from the workspace's root rather than the crate's directory.
//!
//! Messages name the file as the attribute does (relative to the crate): that is the text under
//! the caret, and the same on every machine. Only a file found nowhere is named by the absolute
//! path looked for.

use std::path::{Path, PathBuf};

/// The keys that name a description's file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Key {
    /// `file = "….chain"`.
    File,
    /// `urdf = "….urdf"` (a URDF saved as `.xml` too: the loader reads the root element).
    Urdf,
    /// `mjcf = "….xml"`.
    Mjcf,
}

impl Key {
    /// The extension this key reads.
    fn extension(self) -> &'static str {
        match self {
            Key::File => "chain",
            Key::Urdf => "urdf",
            Key::Mjcf => "xml",
        }
    }

    /// The key as written.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Key::File => "file",
            Key::Urdf => "urdf",
            Key::Mjcf => "mjcf",
        }
    }

    /// The key that reads files with `extension`, if one does.
    pub(crate) fn for_extension(extension: Option<&str>) -> Option<Key> {
        match extension {
            Some("chain") => Some(Key::File),
            Some("urdf") => Some(Key::Urdf),
            Some("xml") => Some(Key::Mjcf),
            _ => None,
        }
    }
}

/// `rel` against `manifest_dir` (the crate's `CARGO_MANIFEST_DIR`); an absolute path as it is.
pub(crate) fn resolve(rel: &str, manifest_dir: Option<&Path>) -> PathBuf {
    let path = Path::new(rel);
    match manifest_dir {
        Some(dir) if path.is_relative() => dir.join(path),
        _ => path.to_path_buf(),
    }
}

/// Why `key = "{shown}"` (resolved to `resolved`) cannot be read for its extension, with the
/// likely slip; `None` where the extension is the key's. `floating`: the attribute asked for a
/// free base, which only a URDF takes.
pub(crate) fn wrong_extension(
    key: Key,
    shown: &str,
    resolved: &Path,
    floating: bool,
) -> Option<String> {
    let found = resolved.extension().and_then(|e| e.to_str());
    if found == Some(key.extension()) || (key == Key::Urdf && found == Some("xml")) {
        return None;
    }
    let expected = key.extension();
    let message = match (key, found) {
        (Key::File, Some("urdf")) => {
            format!("`{shown}` is a URDF, and `file = …` reads a `.chain` file: write `urdf = \"{shown}\"`")
        }
        (Key::Urdf, Some("chain")) => {
            let base = if floating {
                " (and the free base as a joint in the file: `floating` applies to a URDF)"
            } else {
                ""
            };
            format!(
                "`{shown}` is a `.chain` file, and `urdf = …` reads a URDF: write \
                 `file = \"{shown}\"`{base}"
            )
        }
        (_, Some("xacro")) => format!(
            "`{shown}` is a xacro file, which is not read: expand it to a URDF first (`xacro \
             {shown} > robot.urdf`) and give that with `urdf = \"….urdf\"`"
        ),
        (_, Some("xml")) => format!(
            "`{shown}` is an XML file, and `{} = …` reads a `.{expected}` file: write \
             `mjcf = \"{shown}\"` for a MuJoCo model (or `urdf = \"{shown}\"` for a URDF)",
            key.name()
        ),
        (Key::Mjcf, Some("urdf")) => {
            format!("`{shown}` is a URDF, and `mjcf = …` reads MuJoCo's `.xml`: write `urdf = \"{shown}\"`")
        }
        (Key::Mjcf, Some("chain")) => {
            format!("`{shown}` is a `.chain` file, and `mjcf = …` reads MuJoCo's `.xml`: write `file = \"{shown}\"`")
        }
        (_, None) => {
            // The extension left out: the file with it, if it is there.
            let with = ["chain", "urdf", "xml"].into_iter().find(|ext| {
                let mut full = resolved.as_os_str().to_owned();
                full.push(format!(".{ext}"));
                Path::new(&full).is_file()
            });
            match with.and_then(|ext| Key::for_extension(Some(ext)).map(|k| (ext, k))) {
                Some((ext, k)) => format!(
                    "expected a `.{expected}` file, found `{shown}`, which has no extension: \
                     write `{} = \"{shown}.{ext}\"`",
                    k.name()
                ),
                None => format!("expected a `.{expected}` file, found `{shown}`"),
            }
        }
        _ => format!("expected a `.{expected}` file, found `{shown}`"),
    };
    Some(message)
}

/// Why `key = "{shown}"` could not be read (`error`), and where it was looked for: a relative
/// path that is not in the crate's directory but in a directory above it (a path written from
/// the workspace's root, say) gets the path that reaches it.
pub(crate) fn unreadable(
    key: Key,
    shown: &str,
    resolved: &Path,
    manifest_dir: Option<&Path>,
    error: &std::io::Error,
) -> String {
    let rel = Path::new(shown);
    let Some(dir) = manifest_dir.filter(|_| rel.is_relative()) else {
        return format!("{shown}: cannot read: {error}");
    };
    let above = (error.kind() == std::io::ErrorKind::NotFound)
        .then(|| {
            dir.ancestors()
                .skip(1)
                .position(|a| a.join(rel).is_file())
                .map(|levels| levels + 1)
        })
        .flatten();
    match above {
        Some(levels) => {
            let up = "../".repeat(levels);
            let where_ = if levels == 1 {
                "one directory up".to_string()
            } else {
                format!("{levels} directories up")
            };
            format!(
                "{shown}: cannot read: {error}; paths in #[chain(…)] are relative to the crate's \
                 directory (CARGO_MANIFEST_DIR), and the file is {where_}: write `{} = \
                 \"{up}{shown}\"`",
                key.name()
            )
        }
        None => format!(
            "{shown}: cannot read: {error}; paths in #[chain(…)] are relative to the crate's \
             directory (CARGO_MANIFEST_DIR): looked for `{}`",
            resolved.display()
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh directory under the system's temporary directory, removed on drop.
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(name: &str) -> TempDir {
            let dir = std::env::temp_dir().join(format!(
                "articulated-codegen-path-{name}-{}",
                std::process::id()
            ));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).unwrap();
            TempDir(dir)
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    fn not_found() -> std::io::Error {
        std::io::Error::from(std::io::ErrorKind::NotFound)
    }

    #[test]
    fn the_other_key_is_named_with_the_path() {
        let file = wrong_extension(Key::File, "m/x.urdf", Path::new("/c/m/x.urdf"), false);
        assert_eq!(
            file.as_deref(),
            Some("`m/x.urdf` is a URDF, and `file = …` reads a `.chain` file: write `urdf = \"m/x.urdf\"`")
        );
        let urdf = wrong_extension(Key::Urdf, "m/x.chain", Path::new("/c/m/x.chain"), true);
        let urdf = urdf.unwrap();
        assert!(urdf.contains("write `file = \"m/x.chain\"`"), "{urdf}");
        assert!(urdf.contains("`floating` applies to a URDF"), "{urdf}");
        assert_eq!(
            wrong_extension(Key::File, "x.chain", Path::new("/c/x.chain"), false),
            None
        );
        assert_eq!(
            wrong_extension(Key::Urdf, "x.urdf", Path::new("/c/x.urdf"), true),
            None
        );
    }

    #[test]
    fn xacro_and_xml_say_what_to_do() {
        let xacro = wrong_extension(
            Key::Urdf,
            "r.urdf.xacro",
            Path::new("/c/r.urdf.xacro"),
            false,
        );
        assert!(xacro.unwrap().contains("expand it to a URDF first"));
        let xml = wrong_extension(Key::File, "r.xml", Path::new("/c/r.xml"), false);
        assert!(xml
            .unwrap()
            .contains("write `mjcf = \"r.xml\"` for a MuJoCo model"));
        assert_eq!(
            wrong_extension(Key::Urdf, "r.xml", Path::new("/c/r.xml"), false),
            None
        );
        let urdf = wrong_extension(Key::Mjcf, "r.urdf", Path::new("/c/r.urdf"), false);
        assert!(urdf.unwrap().contains("write `urdf = \"r.urdf\"`"));
        let other = wrong_extension(Key::File, "r.txt", Path::new("/c/r.txt"), false);
        assert_eq!(
            other.as_deref(),
            Some("expected a `.chain` file, found `r.txt`")
        );
    }

    #[test]
    fn a_missing_extension_is_found_and_named() {
        let dir = TempDir::new("extension");
        std::fs::write(dir.0.join("arm.urdf"), "<robot/>").unwrap();
        let found = wrong_extension(Key::File, "arm", &dir.0.join("arm"), false).unwrap();
        assert!(
            found.ends_with("which has no extension: write `urdf = \"arm.urdf\"`"),
            "{found}"
        );
        let none = wrong_extension(Key::File, "leg", &dir.0.join("leg"), false).unwrap();
        assert_eq!(none, "expected a `.chain` file, found `leg`");
    }

    #[test]
    fn a_file_above_the_crate_gets_the_path_that_reaches_it() {
        let root = TempDir::new("above");
        let krate = root.0.join("crates").join("robot");
        std::fs::create_dir_all(root.0.join("models")).unwrap();
        std::fs::create_dir_all(&krate).unwrap();
        std::fs::write(root.0.join("models/arm.chain"), "").unwrap();
        let shown = "models/arm.chain";
        let message = unreadable(
            Key::File,
            shown,
            &resolve(shown, Some(&krate)),
            Some(&krate),
            &not_found(),
        );
        assert!(
            message.ends_with(
                "the file is 2 directories up: write `file = \"../../models/arm.chain\"`"
            ),
            "{message}"
        );
    }

    #[test]
    fn a_file_found_nowhere_names_where_it_was_looked_for() {
        let root = TempDir::new("nowhere");
        let shown = "models/no_such_file_anywhere.chain";
        let resolved = resolve(shown, Some(&root.0));
        let message = unreadable(Key::File, shown, &resolved, Some(&root.0), &not_found());
        let looked = format!("looked for `{}`", root.0.join(shown).display());
        assert!(message.ends_with(&looked), "{message}");
        assert!(message.contains("relative to the crate's directory (CARGO_MANIFEST_DIR)"));
        // An absolute path is where it was looked for already.
        let absolute = root.0.join(shown).display().to_string();
        let message = unreadable(
            Key::File,
            &absolute,
            Path::new(&absolute),
            Some(&root.0),
            &not_found(),
        );
        assert_eq!(
            message,
            format!("{absolute}: cannot read: entity not found")
        );
    }
}

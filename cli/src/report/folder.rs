//! Writing a report folder atomically: the folder is filled under a temporary name next to its
//! destination and renamed into place only when complete, so a failed or interrupted run never
//! leaves a folder that looks finished; an existing destination is replaced only when asked.

use super::error::ReportError;
use super::png::PngRenderer;
use std::path::Path;

/// The files of a folder being filled are new: none may be there already.
const NEW: neurotac_core::io::Replace = neurotac_core::io::Replace::No;

pub(crate) fn io(path: &Path) -> impl FnOnce(std::io::Error) -> ReportError + '_ {
    move |source| ReportError::Io {
        path: path.to_owned(),
        source,
    }
}

/// Fails when `out` exists and `force` is not set (checked before a run starts, and again when
/// the report is moved into place).
pub fn check_destination(out: &Path, force: bool) -> Result<(), ReportError> {
    if out.exists() && !force {
        return Err(ReportError::Exists(out.to_owned()));
    }
    Ok(())
}

/// Creates the folder `out` atomically: `fill` writes its files into a temporary folder beside
/// `out`, which then replaces `out` (an existing `out` only with `force`). On any error the
/// temporary folder is removed and `out` is untouched.
pub fn write_folder_atomically(
    out: &Path,
    force: bool,
    fill: impl FnOnce(&Path) -> Result<(), ReportError>,
) -> Result<(), ReportError> {
    check_destination(out, force)?;
    // Filled in a hidden partial folder, then swapped in (neurotac_core::io::AtomicDir: the new
    // folder complete → the old one renamed away → the new one renamed in → the old one
    // deleted); stale partial folders of dead processes are removed on the way.
    let replace = neurotac_core::io::Replace::when(force);
    let partial = neurotac_core::io::AtomicDir::create(out, replace).map_err(io(out))?;
    fill(partial.path())?;
    check_destination(out, force)?;
    partial.commit().map_err(io(out))
}

/// Writes `text` to `dir/file` (a new file in the folder being filled).
pub fn write(dir: &Path, file: &str, text: &str) -> Result<(), ReportError> {
    let path = dir.join(file);
    neurotac_core::io::write(&path, text, NEW).map_err(io(&path))
}

/// Writes a CSV table made by `neurotac_core::io::csv` to `dir/file`; a table that could not be
/// made (a row of another length than the header) is an I/O error of that file.
pub fn write_csv(
    dir: &Path,
    file: &str,
    table: Result<String, neurotac_core::io::csv::Error>,
) -> Result<(), ReportError> {
    let path = dir.join(file);
    write(dir, file, &table.map_err(|e| io(&path)(e.into()))?)
}

/// Writes a figure as `<stem>.svg` and `<stem>.png`.
pub fn write_figure(
    dir: &Path,
    stem: &str,
    svg: &str,
    png: &PngRenderer,
) -> Result<(), ReportError> {
    write(dir, &format!("{stem}.svg"), svg)?;
    let path = dir.join(format!("{stem}.png"));
    let bytes = png.render(svg, 1.5).map_err(|source| ReportError::Png {
        path: path.clone(),
        source,
    })?;
    neurotac_core::io::write(&path, bytes, NEW).map_err(io(&path))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn leftovers(dir: &Path) -> Vec<String> {
        std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.contains("partial"))
            .collect()
    }

    #[test]
    fn a_complete_folder_appears_and_an_existing_one_needs_force() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("report");
        write_folder_atomically(&out, false, |d| write(d, "a.txt", "one")).unwrap();
        assert_eq!(std::fs::read_to_string(out.join("a.txt")).unwrap(), "one");
        let refused = write_folder_atomically(&out, false, |d| write(d, "a.txt", "two"));
        assert!(matches!(refused, Err(ReportError::Exists(_))));
        write_folder_atomically(&out, true, |d| write(d, "b.txt", "two")).unwrap();
        assert!(!out.join("a.txt").exists(), "replaced, not merged");
        assert_eq!(std::fs::read_to_string(out.join("b.txt")).unwrap(), "two");
        assert!(leftovers(dir.path()).is_empty());
    }

    #[test]
    fn a_failed_fill_leaves_neither_the_folder_nor_its_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("report");
        let failed = write_folder_atomically(&out, false, |d| {
            write(d, "a.txt", "half")?;
            write(&d.join("no/such/folder"), "b.txt", "never")
        });
        assert!(matches!(failed, Err(ReportError::Io { .. })));
        assert!(!out.exists());
        assert!(leftovers(dir.path()).is_empty());
    }

    #[test]
    fn a_figure_is_written_as_svg_and_png() {
        let dir = tempfile::tempdir().unwrap();
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"><rect width="10" height="10"/></svg>"#;
        write_figure(dir.path(), "f", svg, &PngRenderer::new()).unwrap();
        assert_eq!(
            std::fs::read_to_string(dir.path().join("f.svg")).unwrap(),
            svg
        );
        let png = std::fs::read(dir.path().join("f.png")).unwrap();
        assert_eq!(&png[1..4], b"PNG");
    }
}

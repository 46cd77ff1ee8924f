//! All-or-nothing output folders that never touch what roamsim did not write (the user's side of
//! it is at the top of `docs/output-formats.md`).
//!
//! Files are written into a fresh staging folder beside the destination; only when every file is
//! complete is the staging folder renamed into place (an existing destination is first moved
//! aside, then removed). A run that fails or is killed midway leaves the previous output, if any,
//! untouched, and at worst a `.<name>.partial-<pid>` folder that the next run into the same
//! destination removes once process `<pid>` is gone (a run killed between its two renames leaves
//! the previous output as `.<name>.old-<pid>`, which the next run puts back). Where there is no
//! `/proc` to tell whether a run is gone, leftovers stay.
//!
//! **What may be replaced.** Every committed folder holds a manifest, [`MANIFEST_NAME`], listing
//! each file roamsim wrote there (one relative path per line, `/`-separated). An existing
//! destination is replaced only when it is empty, or when it holds a manifest and nothing but the
//! files that manifest lists (and the folders holding them). Anything else — a folder of the
//! user's, a roamsim output the user has added a file to, an output of a roamsim that wrote no
//! manifest, a file where the folder should be — is refused before the run starts, with the
//! paths that are in the way and what to do. [`check_destination`] also finds the nearest
//! existing ancestor of a destination that does not exist yet and refuses it when it is a file,
//! so that a run never learns at its end that it cannot write.

use std::collections::BTreeSet;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// The manifest file of every output folder roamsim commits.
pub const MANIFEST_NAME: &str = ".roamsim-output";

/// The manifest's first line; the rest are the relative paths of the files roamsim wrote.
const MANIFEST_HEADER: &str = "# written by roamsim: the files below are roamsim's; a later run may replace this folder only while it holds nothing else";

/// Why an output folder cannot be (re)placed at its destination.
#[derive(Debug, thiserror::Error)]
pub enum OutputLocationError {
    #[error(
        "{}: a file (not a folder) is in the way of the output folder; roamsim leaves it alone: \
         choose another --out, or move the file",
        path.display()
    )]
    FileInTheWay { path: PathBuf },
    #[error(
        "{}: a symbolic link is in the way of the output folder; roamsim neither follows nor \
         replaces it: choose another --out (the folder it points to, say)",
        path.display()
    )]
    LinkInTheWay { path: PathBuf },
    #[error(
        "{}: the output folder cannot be created because {} is a file, not a folder; choose \
         another --out",
        path.display(),
        blocking.display()
    )]
    AncestorIsAFile { path: PathBuf, blocking: PathBuf },
    #[error(
        "{}: this folder exists and is not a roamsim output (it has no {MANIFEST_NAME} manifest; \
         it holds {}); roamsim replaces only folders it wrote itself: choose another --out (a \
         new or empty folder), or move this one away",
        path.display(),
        describe(entries)
    )]
    NotAnOutputFolder { path: PathBuf, entries: Vec<String> },
    #[error(
        "{}: this roamsim output folder now holds files roamsim did not write ({}); roamsim will \
         not delete them: move them out, or choose another --out",
        path.display(),
        describe(entries)
    )]
    ForeignFiles { path: PathBuf, entries: Vec<String> },
    #[error("{}: the output folder has no name (give --out a folder name such as out/run)", path.display())]
    NoName { path: PathBuf },
    #[error(
        "{}: cannot create the output folder: {} does not accept new folders (making {} failed: \
         {source}); choose another --out",
        path.display(),
        parent.display(),
        attempted.display()
    )]
    Create {
        path: PathBuf,
        parent: PathBuf,
        attempted: PathBuf,
        source: io::Error,
    },
    #[error("{}: cannot read the existing folder: {source}", path.display())]
    Read { path: PathBuf, source: io::Error },
}

/// Up to five entries, then how many more.
fn describe(entries: &[String]) -> String {
    let mut text = entries
        .iter()
        .take(5)
        .map(|e| format!("`{e}`"))
        .collect::<Vec<_>>()
        .join(", ");
    if entries.len() > 5 {
        text.push_str(&format!(" and {} more", entries.len() - 5));
    }
    text
}

/// A folder being filled; dropped without [`StagedDir::commit`], it is removed.
#[derive(Debug)]
pub struct StagedDir {
    staging: PathBuf,
    destination: PathBuf,
    committed: bool,
}

impl StagedDir {
    /// Checks the destination ([`check_destination`]), creates the staging folder beside it
    /// (creating parent folders as needed) and removes roamsim's own leftovers of earlier
    /// interrupted runs of the same destination.
    pub fn new(destination: &Path) -> Result<StagedDir, OutputLocationError> {
        check_destination(destination)?;
        let parent = parent_of(destination);
        let name = destination
            .file_name()
            .ok_or_else(|| OutputLocationError::NoName {
                path: destination.to_path_buf(),
            })?
            .to_string_lossy()
            .into_owned();
        fs::create_dir_all(parent).map_err(|source| OutputLocationError::Create {
            path: destination.to_path_buf(),
            parent: nearest_existing(parent),
            attempted: parent.to_path_buf(),
            source,
        })?;
        let leftovers = fs::read_dir(parent).map_err(|source| OutputLocationError::Read {
            path: parent.to_path_buf(),
            source,
        })?;
        for entry in leftovers.flatten() {
            let leftover = entry.file_name().to_string_lossy().into_owned();
            let of_a_dead_run =
                |prefix: &str| leftover.strip_prefix(prefix).is_some_and(process_is_gone);
            if of_a_dead_run(&format!(".{name}.partial-")) {
                let _ = fs::remove_dir_all(entry.path());
            } else if of_a_dead_run(&format!(".{name}.old-")) {
                // A run killed between its two renames: the old folder is the previous output.
                // Put it back when nothing replaced it; else the newer output is in place.
                if destination.exists() {
                    let _ = fs::remove_dir_all(entry.path());
                } else {
                    let _ = fs::rename(entry.path(), destination);
                }
            }
        }
        let staging = parent.join(format!(".{name}.partial-{}", std::process::id()));
        fs::create_dir_all(&staging).map_err(|source| OutputLocationError::Create {
            path: destination.to_path_buf(),
            parent: parent.to_path_buf(),
            attempted: staging.clone(),
            source,
        })?;
        Ok(StagedDir {
            staging,
            destination: destination.to_path_buf(),
            committed: false,
        })
    }

    /// Where to write files now.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// Writes the manifest and moves the finished folder into place. The destination is checked
    /// again first (files may have appeared in it during the run); when it is refused now, the
    /// finished outputs stay in the staging folder, whose path the error's caller can report.
    pub fn commit(mut self) -> Result<PathBuf, CommitError> {
        let manifest = write_manifest(&self.staging).map_err(|source| CommitError::Io {
            path: self.staging.join(MANIFEST_NAME),
            source,
        })?;
        debug_assert!(manifest > 0, "the manifest lists at least itself");
        if let Err(error) = check_destination(&self.destination) {
            self.committed = true; // keep the finished outputs where they are
            return Err(CommitError::Refused {
                error,
                kept_at: self.staging.clone(),
            });
        }
        let parent = parent_of(&self.destination);
        let name = self
            .destination
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let old = parent.join(format!(".{name}.old-{}", std::process::id()));
        let had_previous = self.destination.exists();
        if had_previous {
            fs::rename(&self.destination, &old).map_err(|source| CommitError::Io {
                path: self.destination.clone(),
                source,
            })?;
        }
        if let Err(source) = fs::rename(&self.staging, &self.destination) {
            if had_previous {
                let _ = fs::rename(&old, &self.destination);
            }
            return Err(CommitError::Io {
                path: self.destination.clone(),
                source,
            });
        }
        self.committed = true;
        if had_previous {
            let _ = fs::remove_dir_all(&old);
        }
        Ok(self.destination.clone())
    }
}

/// Why a finished folder was not moved into place.
#[derive(Debug, thiserror::Error)]
pub enum CommitError {
    #[error("{error} (the finished outputs are kept in {})", kept_at.display())]
    Refused {
        error: OutputLocationError,
        kept_at: PathBuf,
    },
    #[error("{}: cannot write the output: {source}", path.display())]
    Io { path: PathBuf, source: io::Error },
}

/// Whether `pid` (the suffix of a leftover's name) names a process that no longer runs: all
/// digits, and not in `/proc`. Where there is no `/proc` to ask, no leftover is ever taken for a
/// dead run's: roamsim deletes nothing it is unsure of (the folders stay, hidden).
fn process_is_gone(pid: &str) -> bool {
    !pid.is_empty()
        && pid.bytes().all(|b| b.is_ascii_digit())
        && pid != std::process::id().to_string()
        && Path::new("/proc/self").exists()
        && !Path::new("/proc").join(pid).exists()
}

/// `folder` or its nearest ancestor that exists.
fn nearest_existing(folder: &Path) -> PathBuf {
    folder
        .ancestors()
        .find(|a| a.exists())
        .unwrap_or(Path::new("."))
        .to_path_buf()
}

fn parent_of(destination: &Path) -> &Path {
    destination
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// Whether roamsim may put an output folder at `destination`: it does not exist and can be
/// created under its nearest existing ancestor (a folder), or it is an empty folder, or a
/// roamsim output holding nothing but what its manifest lists. Reads only; runs call it before
/// simulating, and [`StagedDir`] again before replacing.
pub fn check_destination(destination: &Path) -> Result<(), OutputLocationError> {
    let path = destination.to_path_buf();
    if destination.file_name().is_none() {
        return Err(OutputLocationError::NoName { path });
    }
    match fs::symlink_metadata(destination) {
        Ok(meta) if meta.is_dir() => check_existing_folder(destination),
        Ok(meta) if meta.file_type().is_symlink() => {
            Err(OutputLocationError::LinkInTheWay { path })
        }
        Ok(_) => Err(OutputLocationError::FileInTheWay { path }),
        Err(_) => {
            let mut ancestor = destination.parent();
            while let Some(folder) = ancestor {
                let probe = if folder.as_os_str().is_empty() {
                    Path::new(".")
                } else {
                    folder
                };
                if let Ok(meta) = fs::metadata(probe) {
                    if meta.is_dir() {
                        return Ok(());
                    }
                    return Err(OutputLocationError::AncestorIsAFile {
                        path,
                        blocking: probe.to_path_buf(),
                    });
                }
                ancestor = folder.parent();
            }
            Ok(())
        }
    }
}

fn check_existing_folder(folder: &Path) -> Result<(), OutputLocationError> {
    let read_error = |source| OutputLocationError::Read {
        path: folder.to_path_buf(),
        source,
    };
    let mut present = Vec::new();
    list_files(folder, Path::new(""), &mut present).map_err(read_error)?;
    if present.is_empty() {
        return Ok(());
    }
    let manifest = match fs::read_to_string(folder.join(MANIFEST_NAME)) {
        Ok(text) => text,
        Err(_) => {
            return Err(OutputLocationError::NotAnOutputFolder {
                path: folder.to_path_buf(),
                entries: present,
            });
        }
    };
    let listed: BTreeSet<&str> = manifest
        .lines()
        .filter(|line| !line.starts_with('#') && !line.is_empty())
        .collect();
    let foreign: Vec<String> = present
        .into_iter()
        .filter(|path| path != MANIFEST_NAME && !listed.contains(path.as_str()))
        .collect();
    if foreign.is_empty() {
        Ok(())
    } else {
        Err(OutputLocationError::ForeignFiles {
            path: folder.to_path_buf(),
            entries: foreign,
        })
    }
}

/// Every entry under `folder` that is not a folder (files, links, anything else), and every empty
/// folder, as `/`-separated paths relative to the top, sorted.
fn list_files(folder: &Path, relative: &Path, out: &mut Vec<String>) -> io::Result<()> {
    let mut entries: Vec<_> = fs::read_dir(folder)?.collect::<Result<_, _>>()?;
    entries.sort_by_key(|e| e.file_name());
    if entries.is_empty() && !relative.as_os_str().is_empty() {
        out.push(slash_path(relative) + "/");
    }
    for entry in entries {
        let name = relative.join(entry.file_name());
        if entry.file_type()?.is_dir() {
            list_files(&entry.path(), &name, out)?;
        } else {
            out.push(slash_path(&name));
        }
    }
    Ok(())
}

fn slash_path(path: &Path) -> String {
    path.components()
        .map(|c| c.as_os_str().to_string_lossy())
        .collect::<Vec<_>>()
        .join("/")
}

/// Writes the manifest of everything in `folder`; returns the number of paths it lists.
fn write_manifest(folder: &Path) -> io::Result<usize> {
    let mut files = Vec::new();
    list_files(folder, Path::new(""), &mut files)?;
    files.retain(|f| f != MANIFEST_NAME);
    files.push(MANIFEST_NAME.to_string());
    let text = format!("{MANIFEST_HEADER}\n{}\n", files.join("\n"));
    fs::write(folder.join(MANIFEST_NAME), text)?;
    Ok(files.len())
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = fs::remove_dir_all(&self.staging);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names_in(folder: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(folder)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn an_abandoned_folder_leaves_the_previous_output_untouched() {
        let root = tempfile::tempdir().unwrap();
        let destination = root.path().join("out");
        let first = StagedDir::new(&destination).unwrap();
        fs::write(first.path().join("frames.csv"), "old").unwrap();
        first.commit().unwrap();

        let second = StagedDir::new(&destination).unwrap();
        fs::write(second.path().join("frames.csv"), "half").unwrap();
        drop(second);
        assert_eq!(
            fs::read_to_string(destination.join("frames.csv")).unwrap(),
            "old"
        );
        assert_eq!(names_in(root.path()), ["out"]);

        let third = StagedDir::new(&destination).unwrap();
        fs::write(third.path().join("frames.csv"), "new").unwrap();
        third.commit().unwrap();
        assert_eq!(
            fs::read_to_string(destination.join("frames.csv")).unwrap(),
            "new"
        );
    }

    #[test]
    fn a_committed_folder_lists_every_file_it_holds_in_its_manifest() {
        let root = tempfile::tempdir().unwrap();
        let destination = root.path().join("out");
        let staged = StagedDir::new(&destination).unwrap();
        fs::create_dir_all(staged.path().join("plots")).unwrap();
        fs::write(staged.path().join("plots/a.svg"), "<svg/>").unwrap();
        fs::write(staged.path().join("summary.json"), "{}").unwrap();
        staged.commit().unwrap();
        let manifest = fs::read_to_string(destination.join(MANIFEST_NAME)).unwrap();
        let listed: Vec<&str> = manifest.lines().skip(1).collect();
        assert_eq!(listed, ["plots/a.svg", "summary.json", MANIFEST_NAME]);
    }

    #[test]
    fn a_file_in_the_way_is_refused_and_left_alone() {
        let root = tempfile::tempdir().unwrap();
        let destination = root.path().join("out");
        fs::write(&destination, "the user's notes").unwrap();
        let error = StagedDir::new(&destination).expect_err("a file is in the way");
        assert!(matches!(error, OutputLocationError::FileInTheWay { .. }));
        assert_eq!(
            fs::read_to_string(&destination).unwrap(),
            "the user's notes"
        );
        assert_eq!(names_in(root.path()), ["out"], "nothing staged beside it");
    }

    #[test]
    fn a_folder_roamsim_did_not_write_is_refused_and_nothing_in_it_is_touched() {
        let root = tempfile::tempdir().unwrap();
        let destination = root.path().join("project");
        fs::create_dir_all(destination.join("data")).unwrap();
        fs::write(destination.join("experiment.json"), "{}").unwrap();
        fs::write(destination.join("data/tile.hgt"), "heights").unwrap();
        let error = StagedDir::new(&destination).expect_err("not roamsim's folder");
        let message = error.to_string();
        assert!(matches!(
            error,
            OutputLocationError::NotAnOutputFolder { .. }
        ));
        assert!(message.contains("`data/tile.hgt`"), "{message}");
        assert!(message.contains("choose another --out"), "{message}");
        assert_eq!(names_in(&destination), ["data", "experiment.json"]);
        assert_eq!(
            names_in(root.path()),
            ["project"],
            "nothing staged beside it"
        );
    }

    #[test]
    fn an_output_the_user_added_a_file_to_is_refused_naming_the_file() {
        let root = tempfile::tempdir().unwrap();
        let destination = root.path().join("out");
        let staged = StagedDir::new(&destination).unwrap();
        fs::write(staged.path().join("frames.csv"), "rows").unwrap();
        staged.commit().unwrap();
        fs::write(destination.join("my-notes.txt"), "keep me").unwrap();
        let error = StagedDir::new(&destination).expect_err("a foreign file");
        assert!(
            matches!(&error, OutputLocationError::ForeignFiles { entries, .. } if entries == &["my-notes.txt"]),
            "{error}"
        );
        assert_eq!(
            fs::read_to_string(destination.join("my-notes.txt")).unwrap(),
            "keep me"
        );
    }

    #[test]
    fn an_empty_folder_is_used() {
        let root = tempfile::tempdir().unwrap();
        let destination = root.path().join("empty");
        fs::create_dir(&destination).unwrap();
        let staged = StagedDir::new(&destination).unwrap();
        fs::write(staged.path().join("frames.csv"), "rows").unwrap();
        staged.commit().unwrap();
        assert!(destination.join("frames.csv").is_file());
    }

    #[test]
    fn a_folder_under_a_file_is_refused_before_anything_is_created() {
        let root = tempfile::tempdir().unwrap();
        fs::write(root.path().join("notes.txt"), "mine").unwrap();
        let destination = root.path().join("notes.txt/deeper/out");
        let error = check_destination(&destination).expect_err("a file is an ancestor");
        match &error {
            OutputLocationError::AncestorIsAFile { blocking, .. } => {
                assert_eq!(blocking, &root.path().join("notes.txt"));
            }
            other => panic!("{other}"),
        }
        assert!(error.to_string().contains("is a file, not a folder"));
        assert_eq!(names_in(root.path()), ["notes.txt"]);
    }

    #[test]
    fn a_file_added_during_the_run_keeps_the_new_outputs_in_the_staging_folder() {
        let root = tempfile::tempdir().unwrap();
        let destination = root.path().join("out");
        let staged = StagedDir::new(&destination).unwrap();
        fs::write(staged.path().join("frames.csv"), "rows").unwrap();
        fs::create_dir(&destination).unwrap();
        fs::write(destination.join("added.txt"), "mine").unwrap();
        match staged.commit() {
            Err(CommitError::Refused { kept_at, .. }) => {
                assert!(kept_at.join("frames.csv").is_file());
            }
            other => panic!("{other:?}"),
        }
        assert!(destination.join("added.txt").is_file());
    }

    #[test]
    fn only_the_leftovers_of_runs_that_are_gone_are_cleared_and_an_old_output_is_put_back() {
        if !Path::new("/proc/self").exists() {
            return; // without /proc no leftover is ever cleared; nothing to check here
        }
        let root = tempfile::tempdir().unwrap();
        let destination = root.path().join("out");
        let live = root.path().join(".out.partial-1"); // process 1 runs while the system does
        let users = root.path().join(".out.old-backup");
        let dead_partial = root.path().join(".out.partial-4000000000");
        let dead_old = root.path().join(".out.old-4000000001");
        for folder in [&live, &users, &dead_partial, &dead_old] {
            fs::create_dir_all(folder).unwrap();
        }
        fs::write(dead_old.join("frames.csv"), "the previous output").unwrap();
        let staged = StagedDir::new(&destination).unwrap();
        assert!(live.exists(), "a running run's staging folder is kept");
        assert!(
            users.exists(),
            "a name that is not a pid is not roamsim's to clear"
        );
        assert!(!dead_partial.exists());
        assert_eq!(
            fs::read_to_string(destination.join("frames.csv")).unwrap(),
            "the previous output",
            "killed between its renames, the previous output is put back"
        );
        drop(staged);
    }

    #[test]
    fn a_symbolic_link_in_the_way_is_refused_as_a_link() {
        let root = tempfile::tempdir().unwrap();
        fs::create_dir(root.path().join("real")).unwrap();
        let link = root.path().join("out");
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(root.path().join("real"), &link).unwrap();
            let error = check_destination(&link).expect_err("a link");
            assert!(
                error.to_string().contains("a symbolic link is in the way"),
                "{error}"
            );
        }
    }
}

//! All-or-nothing output folders.
//!
//! Files are written into a fresh temporary folder beside the destination; only when every file
//! is complete is the temporary folder renamed into place (an existing destination is first moved
//! aside, then removed). A run that fails or is killed midway leaves the previous output, if any,
//! untouched, and at worst a `.<name>.partial-<pid>` folder that the next run of the same
//! experiment removes.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// A folder being filled; dropped without [`StagedDir::commit`], it is removed.
pub struct StagedDir {
    staging: PathBuf,
    destination: PathBuf,
    committed: bool,
}

impl StagedDir {
    /// Creates the staging folder beside `destination` (creating parent folders as needed) and
    /// removes leftovers of earlier interrupted runs.
    pub fn new(destination: &Path) -> io::Result<StagedDir> {
        check_destination(destination)?;
        let parent = destination
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        fs::create_dir_all(parent)?;
        let name = destination
            .file_name()
            .ok_or_else(|| io::Error::other("the output folder has no name"))?
            .to_string_lossy()
            .into_owned();
        for entry in fs::read_dir(parent)?.flatten() {
            let leftover = entry.file_name().to_string_lossy().into_owned();
            if leftover.starts_with(&format!(".{name}.partial-"))
                || leftover.starts_with(&format!(".{name}.old-"))
            {
                let _ = fs::remove_dir_all(entry.path());
            }
        }
        let staging = parent.join(format!(".{name}.partial-{}", std::process::id()));
        fs::create_dir_all(&staging)?;
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

    /// Moves the finished folder into place.
    pub fn commit(mut self) -> io::Result<PathBuf> {
        let parent = self.staging.parent().unwrap_or(Path::new("."));
        let name = self
            .destination
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let old = parent.join(format!(".{name}.old-{}", std::process::id()));
        let had_previous = self.destination.exists();
        if had_previous {
            fs::rename(&self.destination, &old)?;
        }
        if let Err(error) = fs::rename(&self.staging, &self.destination) {
            if had_previous {
                let _ = fs::rename(&old, &self.destination);
            }
            return Err(error);
        }
        self.committed = true;
        if had_previous {
            let _ = fs::remove_dir_all(&old);
        }
        Ok(self.destination.clone())
    }
}

/// Refuses a destination that is an existing file (not a folder): that is the user's, not an old
/// output, and must be neither moved aside nor replaced. Runs call it before simulating too.
pub fn check_destination(destination: &Path) -> io::Result<()> {
    if destination.exists() && !destination.is_dir() {
        return Err(io::Error::new(
            io::ErrorKind::AlreadyExists,
            "a file (not a folder) is in the way of the output folder",
        ));
    }
    Ok(())
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
        let names: Vec<_> = fs::read_dir(root.path())
            .unwrap()
            .flatten()
            .map(|e| e.file_name())
            .collect();
        assert_eq!(names.len(), 1, "{names:?}");

        let third = StagedDir::new(&destination).unwrap();
        fs::write(third.path().join("frames.csv"), "new").unwrap();
        third.commit().unwrap();
        assert_eq!(
            fs::read_to_string(destination.join("frames.csv")).unwrap(),
            "new"
        );
    }

    #[test]
    fn a_file_in_the_way_is_refused_and_left_alone() {
        let root = tempfile::tempdir().unwrap();
        let destination = root.path().join("out");
        fs::write(&destination, "the user's notes").unwrap();
        let error = StagedDir::new(&destination)
            .err()
            .expect("a file is in the way");
        assert_eq!(error.kind(), io::ErrorKind::AlreadyExists);
        assert_eq!(
            fs::read_to_string(&destination).unwrap(),
            "the user's notes"
        );
        let names: Vec<_> = fs::read_dir(root.path()).unwrap().flatten().collect();
        assert_eq!(names.len(), 1, "nothing staged beside it");
    }
}

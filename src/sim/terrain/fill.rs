//! Void filling: every void sample takes the height of its nearest valid sample (SPEC §2: voids
//! are filled before use and the number filled is reported). It is the one fill policy; it does
//! not interpolate, and a grid with no valid sample is an error, not a guess.
//!
//! "Nearest" is by 4-connected grid distance, found by one breadth-first pass that starts from
//! all valid samples at once, so the whole fill is O(samples). Ties (two valid samples at the
//! same grid distance) go to the one met first in row-major scan order, which makes the result
//! deterministic. The fill never invents heights outside the valid range.

use super::{SampleGrid, SampleGridError};
use std::collections::VecDeque;

/// What filling did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FillReport {
    pub voids_filled: usize,
}

/// Why voids could not be filled.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FillError {
    #[error("every one of the {n_samples} samples is void; there is nothing to fill from")]
    AllVoid { n_samples: usize },
    #[error(transparent)]
    Grid(#[from] SampleGridError),
}

/// Replaces every void by its nearest valid sample's height; the returned grid has no voids.
pub fn fill_voids(grid: SampleGrid) -> Result<(SampleGrid, FillReport), FillError> {
    let n_voids = grid.void_indices().len();
    if n_voids == 0 {
        return Ok((grid, FillReport { voids_filled: 0 }));
    }
    let (width, height, mut heights, void_indices) = grid.into_parts();
    let n_samples = width * height;
    if n_voids == n_samples {
        return Err(FillError::AllVoid { n_samples });
    }
    let mut is_void = vec![false; n_samples];
    for &index in &void_indices {
        is_void[index] = true;
    }
    let mut frontier: VecDeque<usize> = (0..n_samples).filter(|&i| !is_void[i]).collect();
    while let Some(index) = frontier.pop_front() {
        let (column, row) = (index % width, index / width);
        let neighbours = [
            (column > 0).then(|| index - 1),
            (column + 1 < width).then(|| index + 1),
            (row > 0).then(|| index - width),
            (row + 1 < height).then(|| index + width),
        ];
        for neighbour in neighbours.into_iter().flatten() {
            if is_void[neighbour] {
                is_void[neighbour] = false;
                heights[neighbour] = heights[index];
                frontier.push_back(neighbour);
            }
        }
    }
    let filled = SampleGrid::new(width, height, heights, Vec::new())?;
    Ok((
        filled,
        FillReport {
            voids_filled: n_voids,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_void_takes_its_nearest_valid_neighbour() {
        // 3×3, a void in the centre and one in the south-west corner.
        let heights = vec![0.0, 10.0, 20.0, 30.0, 0.0, 50.0, 60.0, 70.0, 80.0];
        let grid = SampleGrid::new(3, 3, heights, vec![0, 4]).unwrap();
        let (filled, report) = fill_voids(grid).unwrap();
        assert_eq!(report.voids_filled, 2);
        // Corner (0,0): neighbours (1,0) = 10 and (0,1) = 30; (1,0) comes first in scan order.
        assert_eq!(filled.height_at(0, 0), 10.0);
        // Centre: its first valid neighbour in scan order is (1,0) = 10.
        assert_eq!(filled.height_at(1, 1), 10.0);
        assert!(filled.void_indices().is_empty());
    }

    #[test]
    fn a_grid_of_only_voids_is_an_error() {
        let grid = SampleGrid::new(3, 3, vec![0.0; 9], (0..9).collect()).unwrap();
        assert_eq!(
            fill_voids(grid).unwrap_err(),
            FillError::AllVoid { n_samples: 9 }
        );
    }
}

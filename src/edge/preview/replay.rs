//! An experiment's flight replayed frame by frame for the preview, every chosen algorithm in
//! lockstep, through the simulation's own [`FrameRunner`]: the meshes and statistics are those
//! `roamsim run` computes for the same experiment (same effects, so the audit's error is there
//! when the experiment asks for it). Replays only go forward; nothing here draws.

use crate::edge::experiment::{self, Experiment, ExperimentError};
use crate::edge::output::significant::{column_with_unit, three_significant};
use crate::sim::algorithm::LodAlgorithm;
use crate::sim::draw::GpuBuffers;
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::MeshOutput;
use crate::sim::run::{FrameOutcome, FrameRunner, RunError, RunInputs};
use crate::sim::stats::FrameStats;
use crate::sim::view::Camera;
use std::path::Path;

/// A loaded experiment with its preprocessed terrain: what every replay borrows.
pub struct Scene {
    pub experiment: Experiment,
    pub hierarchy: Hierarchy,
}

/// The experiment has no algorithm entry of that label or name.
#[derive(Debug, thiserror::Error)]
#[error("no algorithm entry named {wanted:?}; the experiment has: {available}")]
pub struct UnknownAlgorithm {
    pub wanted: String,
    pub available: String,
}

impl Scene {
    /// Loads and preprocesses an experiment file.
    pub fn load(path: &Path) -> Result<Scene, ExperimentError> {
        let experiment = experiment::load(path)?;
        let hierarchy = Hierarchy::new(std::sync::Arc::clone(&experiment.field));
        Ok(Scene {
            experiment,
            hierarchy,
        })
    }

    /// The algorithm entries' labels, in the experiment's order.
    pub fn labels(&self) -> Vec<&str> {
        self.experiment
            .algorithms
            .iter()
            .map(|a| a.label.as_str())
            .collect()
    }

    /// The entry whose label is `wanted`, or else the first whose algorithm name is.
    pub fn entry_index(&self, wanted: &str) -> Result<usize, UnknownAlgorithm> {
        let algorithms = &self.experiment.algorithms;
        algorithms
            .iter()
            .position(|a| a.label == wanted)
            .or_else(|| algorithms.iter().position(|a| a.config.name() == wanted))
            .ok_or_else(|| UnknownAlgorithm {
                wanted: wanted.to_string(),
                available: self.labels().join(", "),
            })
    }

    pub fn n_frames(&self) -> u64 {
        self.experiment.flight.n_frames()
    }

    fn run_inputs(&self) -> RunInputs<'_> {
        RunInputs {
            hierarchy: &self.hierarchy,
            view: &self.experiment.view,
            flight: &self.experiment.flight,
            violations: &self.experiment.violations,
            effects: self.experiment.effects,
            max_triangles: Some(self.experiment.max_triangles),
            // The preview audits against the source only.
            detail_truth: None,
        }
    }
}

/// Chosen algorithm entries stepped through the flight together.
pub struct Replay<'s> {
    scene: &'s Scene,
    lanes: Vec<Lane<'s>>,
}

/// One algorithm entry's run.
struct Lane<'s> {
    entry: usize,
    algorithm: Box<dyn LodAlgorithm + 's>,
    runner: FrameRunner<'s>,
    last: Option<FrameOutcome>,
}

/// What one lane shows after a step.
pub struct LaneFrame<'a> {
    pub label: &'a str,
    pub mesh: MeshOutput<'a>,
    /// The buffers the algorithm keeps for its GPU (what the preview draws).
    pub buffers: &'a GpuBuffers,
    pub stats: &'a FrameStats,
    /// The camera the algorithm saw (terrain-local).
    pub camera: &'a Camera,
    /// The algorithm's own count, [`LodAlgorithm::triangle_count`].
    pub triangle_count: u64,
    /// The algorithm's extra columns' names, in the order of `stats.extra`.
    pub extra_columns: &'static [&'static str],
}

impl<'s> Replay<'s> {
    /// Fresh algorithms for the entries `entries` (indices into the experiment's list), before
    /// frame 0.
    pub fn new(scene: &'s Scene, entries: &[usize]) -> Replay<'s> {
        let experiment = &scene.experiment;
        let lanes = entries
            .iter()
            .map(|&entry| Lane {
                entry,
                algorithm: experiment.algorithms[entry].config.build(
                    &scene.hierarchy,
                    &experiment.view,
                    experiment.speed,
                ),
                runner: FrameRunner::new(&scene.run_inputs()),
                last: None,
            })
            .collect();
        Replay { scene, lanes }
    }

    pub fn scene(&self) -> &'s Scene {
        self.scene
    }

    /// The frame the next step runs.
    pub fn next_frame(&self) -> u64 {
        self.lanes
            .first()
            .map_or(0, |lane| lane.runner.next_frame())
    }

    /// Runs the next frame on every lane; `false` (and nothing done) once the flight is over.
    pub fn step(&mut self) -> Result<bool, RunError> {
        for lane in &mut self.lanes {
            let label = &self.scene.experiment.algorithms[lane.entry].label;
            match lane.runner.step(label, lane.algorithm.as_mut()) {
                None => return Ok(false),
                Some(outcome) => lane.last = Some(outcome?),
            }
        }
        Ok(!self.lanes.is_empty())
    }

    /// Steps until `frame` is the last frame run (no step if it already is or is past).
    pub fn run_to(&mut self, frame: u64) -> Result<(), RunError> {
        while self.next_frame() <= frame {
            if !self.step()? {
                break;
            }
        }
        Ok(())
    }

    pub fn n_lanes(&self) -> usize {
        self.lanes.len()
    }

    /// Lane `k` after the last step; `None` before the first step.
    pub fn lane(&self, k: usize) -> Option<LaneFrame<'_>> {
        let lane = &self.lanes[k];
        let outcome = lane.last.as_ref()?;
        Some(LaneFrame {
            label: &self.scene.experiment.algorithms[lane.entry].label,
            mesh: lane.algorithm.mesh(),
            buffers: lane.algorithm.buffers(),
            stats: &outcome.stats,
            camera: &outcome.camera,
            triangle_count: lane.algorithm.triangle_count(),
            extra_columns: lane.algorithm.extra_columns(),
        })
    }
}

impl LaneFrame<'_> {
    /// The frame's statistics in a few short lines: label and frame; triangles (in view),
    /// splits, merges; the algorithm's extra columns (Wu's base b among them), three a line, each
    /// with three significant digits and its unit (`tau_px 49.4 px`); the audited error when the
    /// experiment audits.
    pub fn caption_lines(&self) -> Vec<String> {
        let stats = self.stats;
        let mut lines = vec![
            format!("{} · frame {}", self.label, stats.frame),
            format!(
                "{} triangles ({} in view) · {} splits · {} merges",
                stats.triangles, stats.triangles_rendered, stats.splits, stats.merges
            ),
        ];
        let extras: Vec<String> = self
            .extra_columns
            .iter()
            .zip(&stats.extra)
            .map(|(name, value)| column_with_unit(name, *value))
            .collect();
        lines.extend(extras.chunks(3).map(|chunk| chunk.join(" · ")));
        if let Some(error) = stats.audit.as_ref().and_then(|a| a.projected.as_ref()) {
            lines.push(format!(
                "projected error p95 {} px, max {} px",
                three_significant(error.p95),
                three_significant(error.max)
            ));
        }
        lines
    }

    /// [`LaneFrame::caption_lines`] on one line (the window title, the command's output).
    pub fn caption(&self) -> String {
        self.caption_lines().join(" · ")
    }
}

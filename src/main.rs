//! The `roamsim` command line: `run` (with `--shard K/N`, one part of it: `docs/sharding.md`),
//! `merge`, `validate`, `info`, and with the `preview` feature `preview` (a window) and `render`
//! (PNG files). A build without the feature still knows those two names and answers how to build
//! them. What a run reads and writes: `docs/experiment-format.md`, `docs/output-formats.md`.
//!
//! A thin edge over the library: parse arguments, call `edge::session` or the experiment
//! loader, print results and errors, set the exit status (failure, with `error: …` on stderr,
//! for any error). An indicatif progress bar is drawn on stderr when stderr is a terminal;
//! otherwise `edge::progress` writes plain lines, so that a batch job's log says how far it got.
//!
//! Stdout may be a pipe whose reader stops early (`roamsim info … | head`). Every line for stdout
//! goes through a `Write` that returns its error; a broken pipe ends the command at once and
//! quietly, with no message and exit status 141 (128 + SIGPIPE), as `cat`, `grep` or `seq` end when
//! the signal kills them. Not 0, as ripgrep chooses: `validate` answers with its status, and a
//! validation cut short must not read as "valid"; 141 is what a shell already shows for a reader
//! that stopped. SIGPIPE itself stays ignored, as Rust leaves it, so no library call is needed. A
//! `run` or `merge` prints only after its outputs are committed (renamed into place by
//! `atomic_dir`), so a closed stdout cannot leave them half-written; progress and warnings go to
//! stderr.
//!
//! `roamsim validate` keeps its name although the code calls what it does *checking*
//! (`check_experiment`): in the code, "validate" means only the mesh and structure validators
//! that `--check` runs.

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use roamsim::edge::experiment;
use roamsim::edge::flight_motion::describe_flight_motion;
use roamsim::edge::info_command::{InfoFailure, InfoRequest, RawKeys, TerrainFileKeys, run_info};
use roamsim::edge::output::end_of_run::end_of_run_text;
use roamsim::edge::progress::LineProgress;
use roamsim::edge::pyramid::PrepareSource;
use roamsim::edge::session::{
    MergeOptions, ProgressSink, RunOptions, RunOutcome, Timing, merge_shards, run_experiment,
};
use roamsim::edge::shard::{SHARD_FILE, ShardSpec};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

const EXAMPLES: &str = "\
Examples:
  roamsim run experiments/quickstart.json
      Runs the quickstart and writes out/quickstart/{frames.csv,summary.json,plots/}.
  roamsim run experiments/quickstart.json --out results/qs --check
      Same, into results/qs, validating every mesh every frame.
  roamsim run experiments/scaling.json --shard 2/3 --out shards/2
      Runs the second of three parts of the experiment (for a batch system; docs/sharding.md).
  roamsim merge shards/1 shards/2 shards/3 --out out/scaling
      Assembles the three parts into the outputs of one whole run.
  roamsim validate experiments/quickstart.json
      Checks the experiment (and loads its terrain and flight) without running it.
  roamsim info experiments/data/N48E009.hgt --map out/n48e009.png
      Describes a terrain file, times its preprocessing and draws its map.
  roamsim info alps.png --height-scale 0.1 --spacing-m 92.7
      Reads a 16-bit PNG as an experiment with those terrain.file keys would.
  roamsim preview experiments/compare-circle.json
      (built with --features preview) Replays the flight in a window, two algorithms side by side.
  roamsim render experiments/quickstart.json --frames 0,200 --out out/render --camera overview
      (built with --features preview) Writes out/render/frame-000000.png and frame-000200.png.";

/// Simulates view-dependent terrain LOD algorithms over replayed camera flights.
#[derive(Parser)]
#[command(version, about, after_help = EXAMPLES)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run an experiment and write frames.csv, summary.json and plots.
    #[command(after_help = EXAMPLES)]
    Run {
        /// The experiment file (JSON, format documented in docs/experiment-format.md).
        experiment: PathBuf,
        /// Output folder (default: out/<experiment name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Validate every algorithm's mesh after every frame (slower).
        #[arg(long)]
        check: bool,
        /// Threads running algorithm entries side by side (default: one per core). Counts and
        /// meshes do not depend on it; use 1 for timing comparisons.
        #[arg(long)]
        threads: Option<usize>,
        /// Run only the first N frames of the flight (any flight: parametric, waypoints,
        /// recorded), exactly as the full run has them: for quick probes.
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
        frames: Option<u64>,
        /// Run only the K-th of N parts of the experiment's (sweep point, entry) units and write
        /// their raw results (shard.json, default folder out/<name>-shard-K-of-N) for
        /// `roamsim merge`; see docs/sharding.md.
        #[arg(long, value_name = "K/N", value_parser = ShardSpec::parse)]
        shard: Option<ShardSpec>,
        /// Time the updates in N timing passes (each entry flown again with every effect off;
        /// frames.csv gets each frame's median, summary.json the passes' spread). Without it,
        /// one timing pass runs when any effect (audit, culling, --check, mesh export) is on.
        #[arg(long, value_name = "N", default_value_t = 1,
              value_parser = clap::value_parser!(u32).range(1..))]
        repeat: u32,
        /// Keep the update times measured with the effects on (no timing pass: faster, but
        /// the effects inflate the times).
        #[arg(long, conflicts_with = "repeat")]
        time_with_effects: bool,
    },
    /// Merge the N shard folders of `run --shard K/N` into the outputs one run of the whole
    /// experiment writes (identical apart from timings and run metadata).
    #[command(after_help = EXAMPLES)]
    Merge {
        /// The shard folders, all N of them, in any order.
        #[arg(required = true)]
        shards: Vec<PathBuf>,
        /// Output folder (default: out/<experiment name>).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Check an experiment file without running it; exits non-zero when it is invalid.
    #[command(after_help = EXAMPLES)]
    Validate { experiment: PathBuf },
    /// Describe a terrain file or an experiment's terrain, with preprocessing time and memory;
    /// with --map, draw it from above (the experiment's flight too).
    #[command(after_help = EXAMPLES)]
    Info {
        /// An experiment (.json) or a terrain file (.hgt, .png, .tif, .tiff, .asc, or a raw file
        /// with --raw-columns, --raw-rows and --raw-sample).
        path: PathBuf,
        /// A raw file's columns (samples per row).
        #[arg(long, requires_all = ["raw_rows", "raw_sample"])]
        raw_columns: Option<usize>,
        /// A raw file's rows.
        #[arg(long, requires_all = ["raw_columns", "raw_sample"])]
        raw_rows: Option<usize>,
        /// A raw file's sample type and byte order.
        #[arg(long, value_enum, requires_all = ["raw_columns", "raw_rows"])]
        raw_sample: Option<RawSampleChoice>,
        /// A raw file's first row is the south edge (default: the north edge, as most are).
        #[arg(long, requires = "raw_sample")]
        raw_south_first: bool,
        /// Metres per stored height unit (terrain.file.height_scale).
        #[arg(long, value_name = "FACTOR", allow_negative_numbers = true)]
        height_scale: Option<f64>,
        /// Metres added to every height after scaling (terrain.file.height_offset_m).
        #[arg(long, value_name = "M", allow_negative_numbers = true)]
        height_offset_m: Option<f64>,
        /// The stored value that marks a void (terrain.file.nodata).
        #[arg(long, value_name = "VALUE", allow_negative_numbers = true)]
        nodata: Option<f64>,
        /// Grid spacing in metres, one number for both axes or DX,DY (terrain.file.spacing_m).
        #[arg(long, value_name = "DX[,DY]", value_delimiter = ',', num_args = 1)]
        spacing_m: Vec<f64>,
        /// How the grid is fitted into (2^n+1)² samples (terrain.file.fit; default pad).
        #[arg(long, value_enum)]
        fit: Option<FitChoice>,
        /// With --fit crop: the column and row the kept square starts at (terrain.file.crop_origin).
        #[arg(long, value_name = "COLUMN,ROW", value_delimiter = ',', num_args = 1)]
        crop_origin: Vec<usize>,
        /// World position of sample (0, 0) at height 0 (terrain.file.origin_m).
        #[arg(
            long,
            value_name = "X,Y,Z",
            value_delimiter = ',',
            num_args = 1,
            allow_negative_numbers = true
        )]
        origin_m: Vec<f64>,
        /// Draw the terrain from above into FILE (.png or .svg): hillshade, heights, a scale in
        /// metres, world coordinates; for an experiment, its flight over it.
        #[arg(long, value_name = "FILE")]
        map: Option<PathBuf>,
    },
    /// Write a terrain's chunk pyramid (the chunked LOD quadtree with every chunk's heights and
    /// nested error) for an on-demand flight; see docs/output-formats.md, "Chunk pyramid". A raw
    /// file of (2^n+1)² samples (--raw-side, --raw-sample) is streamed in bounded memory; any
    /// other terrain the experiment format reads (.hgt, .png, .tif, .tiff, .asc, or an
    /// experiment .json for its terrain: a mosaic, a folder of tiles) is read whole, fitted like
    /// an experiment's, after its memory is stated and checked.
    #[command(after_help = EXAMPLES)]
    Prepare {
        /// The terrain: a raw file with --raw-side and --raw-sample, a terrain file, or an
        /// experiment (.json).
        terrain: PathBuf,
        /// A raw file's samples per side (2^n + 1): the file is streamed.
        #[arg(long, requires = "raw_sample")]
        raw_side: Option<usize>,
        /// A raw file's sample type and byte order.
        #[arg(long, value_enum, requires = "raw_side")]
        raw_sample: Option<RawSampleChoice>,
        /// The raw file's first row is the south edge (default: the north edge, as most are).
        #[arg(long, requires = "raw_sample")]
        raw_south_first: bool,
        /// Grid spacing in metres, one number for both axes or DX,DY (required for a raw file;
        /// for a terrain file, terrain.file.spacing_m).
        #[arg(long, value_name = "DX[,DY]", value_delimiter = ',', num_args = 1)]
        spacing_m: Vec<f64>,
        /// Metres per stored height unit (terrain.file.height_scale; not for a streamed raw file).
        #[arg(long, value_name = "FACTOR", allow_negative_numbers = true)]
        height_scale: Option<f64>,
        /// Metres added to every height after scaling (terrain.file.height_offset_m).
        #[arg(long, value_name = "M", allow_negative_numbers = true)]
        height_offset_m: Option<f64>,
        /// The stored value that marks a void (terrain.file.nodata).
        #[arg(long, value_name = "VALUE", allow_negative_numbers = true)]
        nodata: Option<f64>,
        /// How the grid is fitted into (2^n+1)² samples (terrain.file.fit; default pad).
        #[arg(long, value_enum)]
        fit: Option<FitChoice>,
        /// With --fit crop: the column and row the kept square starts at (terrain.file.crop_origin).
        #[arg(long, value_name = "COLUMN,ROW", value_delimiter = ',', num_args = 1)]
        crop_origin: Vec<usize>,
        /// c: chunks of (2^c + 1)² vertices, as the chunked entry's `chunk_level` (default 6).
        #[arg(long, default_value_t = 6)]
        chunk_level: u32,
        /// The pyramid file to write (replaced only when it is a pyramid).
        #[arg(long)]
        out: PathBuf,
    },
    /// Replay an experiment's flight in a window: the meshes, their wireframe by level, the
    /// statistics in the title. Keys: Space pause · → step · A/B switch the left/right
    /// algorithm · S split screen · W wireframe · C culling view · R triangle roles · Q quit.
    #[cfg(feature = "preview")]
    #[command(after_help = EXAMPLES)]
    Preview {
        experiment: PathBuf,
        /// Entry label or algorithm name; give it twice for the two panes (default: the first
        /// two entries).
        #[arg(long = "algorithm")]
        algorithms: Vec<String>,
        /// Close the window after drawing this many frames.
        #[arg(long)]
        quit_after: Option<u64>,
    },
    /// Draw chosen frames of an experiment offscreen (no window or display needed) into PNGs.
    #[cfg(feature = "preview")]
    #[command(after_help = EXAMPLES)]
    Render {
        experiment: PathBuf,
        /// Frames to draw, e.g. `0,100,399`.
        #[arg(long, value_delimiter = ',', required = true)]
        frames: Vec<u64>,
        /// Output folder (created if missing).
        #[arg(long)]
        out: PathBuf,
        /// Entry label or algorithm name; repeat it to draw several side by side (default: the
        /// first entry).
        #[arg(long = "algorithm")]
        algorithms: Vec<String>,
        /// `flight`: the flight's camera; `overview`: from above, with the frustum and the
        /// culled triangles darkened.
        #[arg(long, default_value = "flight")]
        camera: CameraChoice,
        /// Draw the shaded mesh without its wireframe.
        #[arg(long)]
        no_wireframe: bool,
        /// Leave out the statistics drawn in each pane's corner.
        #[arg(long)]
        no_captions: bool,
        /// Tell triangle roles apart: skirts cyan, stitches violet, degenerate triangles as
        /// magenta lines.
        #[arg(long)]
        roles: bool,
    },
    /// (Needs a build with the `preview` feature.)
    #[cfg(not(feature = "preview"))]
    #[command(hide = true, disable_help_flag = true)]
    Preview {
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        rest: Vec<String>,
    },
    /// (Needs a build with the `preview` feature.)
    #[cfg(not(feature = "preview"))]
    #[command(hide = true, disable_help_flag = true)]
    Render {
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        rest: Vec<String>,
    },
}

/// What `preview` and `render` answer in a build without the feature that draws.
#[cfg(not(feature = "preview"))]
fn needs_preview_feature(command: &str) -> Result<(), Failure> {
    Err(Failure::Error(format!(
        "`{command}` draws with wgpu, which this build leaves out: build with the `preview` \
         feature, e.g. `cargo run --release --features preview -- {command} EXPERIMENT …` \
         (README, \"Seeing the meshes\")"
    )))
}

/// Raw sample types, as the experiment format names them.
#[derive(Clone, Copy, clap::ValueEnum)]
enum RawSampleChoice {
    I16le,
    I16be,
    U16le,
    U16be,
    F32le,
    F32be,
}

impl RawSampleChoice {
    /// The sample's name in an experiment's terrain.file.format.raw.sample.
    fn key(self) -> &'static str {
        match self {
            RawSampleChoice::I16le => "i16le",
            RawSampleChoice::I16be => "i16be",
            RawSampleChoice::U16le => "u16le",
            RawSampleChoice::U16be => "u16be",
            RawSampleChoice::F32le => "f32le",
            RawSampleChoice::F32be => "f32be",
        }
    }

    fn sample(self) -> roamsim::edge::terrain_readers::RawSample {
        use roamsim::edge::terrain_readers::RawSample;
        match self {
            RawSampleChoice::I16le => RawSample::I16Le,
            RawSampleChoice::I16be => RawSample::I16Be,
            RawSampleChoice::U16le => RawSample::U16Le,
            RawSampleChoice::U16be => RawSample::U16Be,
            RawSampleChoice::F32le => RawSample::F32Le,
            RawSampleChoice::F32be => RawSample::F32Be,
        }
    }
}

/// terrain.file.fit.
#[derive(Clone, Copy, clap::ValueEnum)]
enum FitChoice {
    Pad,
    Crop,
}

#[cfg(feature = "preview")]
#[derive(Clone, Copy, clap::ValueEnum)]
enum CameraChoice {
    Flight,
    Overview,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run {
            experiment,
            out,
            check,
            threads,
            frames,
            shard,
            repeat,
            time_with_effects,
        } => run(
            &experiment,
            RunOptions {
                out_dir: out,
                check_meshes: check,
                threads,
                command_line: Some(command_line()),
                max_frames: frames,
                shard,
                timing: Timing {
                    repeat,
                    with_effects: time_with_effects,
                },
            },
        ),
        Command::Merge { shards, out } => merge(&shards, out),
        Command::Validate { experiment } => check_experiment(&experiment),
        Command::Info {
            path,
            raw_columns,
            raw_rows,
            raw_sample,
            raw_south_first,
            height_scale,
            height_offset_m,
            nodata,
            spacing_m,
            fit,
            crop_origin,
            origin_m,
            map,
        } => {
            let keys = TerrainFileKeys {
                raw: raw_columns
                    .zip(raw_rows)
                    .zip(raw_sample)
                    .map(|((columns, rows), sample)| RawKeys {
                        columns,
                        rows,
                        sample: sample.key(),
                        north_first: !raw_south_first,
                    }),
                height_scale,
                height_offset_m,
                nodata,
                spacing_m,
                fit: fit.map(|fit| match fit {
                    FitChoice::Pad => "pad",
                    FitChoice::Crop => "crop",
                }),
                crop_origin,
                origin_m,
            };
            let request = InfoRequest {
                path,
                file_keys: keys,
                map,
            };
            run_info(&request, &mut std::io::stdout()).map_err(|failure| match failure {
                InfoFailure::Output(error) => Failure::from(error),
                InfoFailure::Error(message) => Failure::Error(message),
            })
        }
        Command::Prepare {
            terrain,
            raw_side,
            raw_sample,
            raw_south_first,
            spacing_m,
            height_scale,
            height_offset_m,
            nodata,
            fit,
            crop_origin,
            chunk_level,
            out,
        } => {
            let keys = TerrainFileKeys {
                raw: None,
                height_scale,
                height_offset_m,
                nodata,
                spacing_m,
                fit: fit.map(|fit| match fit {
                    FitChoice::Pad => "pad",
                    FitChoice::Crop => "crop",
                }),
                crop_origin,
                origin_m: Vec::new(),
            };
            let raw = raw_side.zip(raw_sample.map(|sample| sample.sample()));
            PrepareSource::from_arguments(terrain, raw, raw_south_first, keys)
                .and_then(|source| {
                    roamsim::edge::pyramid::prepare_command(source, chunk_level, &out)
                })
                .map_err(Failure::Error)
        }
        #[cfg(not(feature = "preview"))]
        Command::Preview { .. } => needs_preview_feature("preview"),
        #[cfg(not(feature = "preview"))]
        Command::Render { .. } => needs_preview_feature("render"),
        #[cfg(feature = "preview")]
        Command::Preview {
            experiment,
            algorithms,
            quit_after,
        } => preview(experiment, algorithms, quit_after),
        #[cfg(feature = "preview")]
        Command::Render {
            experiment,
            frames,
            out,
            algorithms,
            camera,
            no_wireframe,
            no_captions,
            roles,
        } => render(roamsim::edge::preview::headless::RenderRequest {
            experiment,
            frames,
            out_dir: out,
            algorithms,
            view: match camera {
                CameraChoice::Flight => roamsim::edge::preview::geometry::ViewChoice::Flight,
                CameraChoice::Overview => roamsim::edge::preview::geometry::ViewChoice::Overview,
            },
            wireframe: !no_wireframe,
            size: None,
            captions: !no_captions,
            roles,
        }),
    };
    // What is left in stdout's buffer is written now, where its error can still be seen.
    let result = result.and_then(|()| std::io::stdout().flush().map_err(Failure::from));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::StdoutClosed) => ExitCode::from(CLOSED_STDOUT_STATUS),
        Err(Failure::Error(message)) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

/// The exit status when stdout is a closed pipe: 128 + SIGPIPE (13), what a shell reports for a
/// program the signal ended (see the module doc).
const CLOSED_STDOUT_STATUS: u8 = 128 + 13;

/// Why a command stopped early.
enum Failure {
    /// An error for the user: `error: …` on stderr, exit status 1.
    Error(String),
    /// Stdout is a pipe whose reader has gone: stop quietly, exit [`CLOSED_STDOUT_STATUS`].
    StdoutClosed,
}

impl From<String> for Failure {
    fn from(message: String) -> Failure {
        Failure::Error(message)
    }
}

/// The only IO errors this file sees unconverted are those of writing to stdout.
impl From<std::io::Error> for Failure {
    fn from(error: std::io::Error) -> Failure {
        if error.kind() == std::io::ErrorKind::BrokenPipe {
            Failure::StdoutClosed
        } else {
            Failure::Error(format!("cannot write to stdout: {error}"))
        }
    }
}

/// This process's command line, recorded in the outputs.
fn command_line() -> Vec<String> {
    std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .collect()
}

fn run(path: &Path, options: RunOptions) -> Result<(), Failure> {
    let started = Instant::now();
    let check = options.check_meshes;
    let outcome = if std::io::stderr().is_terminal() {
        run_experiment(path, &options, &BarProgress::new())
    } else {
        run_experiment(path, &options, &LineProgress::to_stderr())
    }
    .map_err(|e| e.to_string())?;
    if let Some(shard) = options.shard {
        writeln!(
            std::io::stdout(),
            "{}: shard {shard}: {} frames in {:.2} s on {} thread(s) (preprocessing {:.3} s){}\n\
             wrote {}/{}; when all {} shards are done: roamsim merge <the {} shard folders>",
            outcome.experiment_name,
            outcome.frames,
            started.elapsed().as_secs_f64(),
            outcome.threads,
            outcome.preprocessing_seconds,
            if check {
                format!("; --check: every mesh valid ({} meshes)", outcome.meshes)
            } else {
                String::new()
            },
            outcome.out_dir.display(),
            SHARD_FILE,
            shard.count,
            shard.count,
        )?;
        return Ok(());
    }
    report_outcome(&outcome, started)
}

fn merge(shards: &[PathBuf], out: Option<PathBuf>) -> Result<(), Failure> {
    let started = Instant::now();
    let options = MergeOptions {
        out_dir: out,
        command_line: Some(command_line()),
    };
    let outcome =
        merge_shards(shards, &options, &LineProgress::to_stderr()).map_err(|e| e.to_string())?;
    writeln!(std::io::stdout(), "merged {} shard folder(s)", shards.len())?;
    report_outcome(&outcome, started)
}

/// The warnings and the end-of-run printout of a finished run or merge.
fn report_outcome(outcome: &RunOutcome, started: Instant) -> Result<(), Failure> {
    let check = outcome.check_meshes;
    if !outcome.speed_violation_frames.is_empty() {
        let frames = &outcome.speed_violation_frames;
        let shown: Vec<String> = frames.iter().take(10).map(u64::to_string).collect();
        eprintln!(
            "warning: {} frame(s) break the speed or rotation bounds (algorithms revalidated \
             there; summary.json says which bound): {}{}",
            frames.len(),
            shown.join(", "),
            if frames.len() > 10 { ", …" } else { "" }
        );
    }
    for flag in &outcome.goal_flags {
        eprintln!("warning: {flag}");
    }
    writeln!(
        std::io::stdout(),
        "{}: {} frames in {:.2} s on {} thread(s) (preprocessing {:.3} s){}",
        outcome.experiment_name,
        outcome.frames,
        started.elapsed().as_secs_f64(),
        outcome.threads,
        outcome.preprocessing_seconds,
        if check {
            format!(
                "; --check: every mesh valid after every frame ({} meshes)",
                outcome.meshes
            )
        } else {
            String::new()
        },
    )?;
    write!(
        std::io::stdout(),
        "{}",
        end_of_run_text(&outcome.out_dir, &outcome.points, &outcome.written)
    )?;
    Ok(())
}

fn check_experiment(path: &Path) -> Result<(), Failure> {
    let plan = experiment::plan(path).map_err(|e| e.to_string())?;
    for k in 0..plan.n_points() {
        let experiment = plan.load_point(k).map_err(|e| e.to_string())?;
        let point = plan
            .choice(k)
            .map(|c| {
                format!(
                    " (sweep point {}/{}: {})",
                    k + 1,
                    plan.n_points(),
                    experiment::choice_label(c)
                )
            })
            .unwrap_or_default();
        writeln!(
            std::io::stdout(),
            "{}{point}: valid — {} algorithm(s), {} frames, terrain {}² from {}",
            path.display(),
            experiment.algorithms.len(),
            experiment.flight.n_frames(),
            experiment.terrain.side,
            experiment.terrain.source
        )?;
        if experiment.rotation_bound == experiment::BoundOrigin::Derived {
            writeln!(
                std::io::stdout(),
                "note: no rotation bound declared: the flight's largest turn, {} rad a frame, is \
                 used (speed_bounds.rotation_rad_per_frame)",
                experiment.speed.rotation
            )?;
        }
        if let Some(first) = experiment.below_ground_frames.first() {
            writeln!(
                std::io::stdout(),
                "note: the eye is below the ground in {} frame(s) (first: frame {first})",
                experiment.below_ground_frames.len()
            )?;
        }
        write!(std::io::stdout(), "{}", describe_flight_motion(&experiment))?;
    }
    Ok(())
}

#[cfg(feature = "preview")]
fn preview(
    experiment: PathBuf,
    algorithms: Vec<String>,
    quit_after_frames: Option<u64>,
) -> Result<(), Failure> {
    use roamsim::edge::preview::window::{PreviewRequest, run_preview};
    let summary = run_preview(&PreviewRequest {
        experiment,
        algorithms,
        quit_after_frames,
    })
    .map_err(|e| e.to_string())?;
    writeln!(
        std::io::stdout(),
        "drew {} frame(s) on {}; the replay reached flight frame {}",
        summary.frames_drawn,
        summary.adapter,
        summary.last_frame
    )?;
    Ok(())
}

#[cfg(feature = "preview")]
fn render(request: roamsim::edge::preview::headless::RenderRequest) -> Result<(), Failure> {
    let frames =
        roamsim::edge::preview::headless::render_experiment(&request).map_err(|e| e.to_string())?;
    for frame in &frames {
        writeln!(std::io::stdout(), "{}", frame.path.display())?;
        for caption in &frame.captions {
            writeln!(std::io::stdout(), "  {caption}")?;
        }
    }
    Ok(())
}

/// One indicatif bar for all the frames of all the entries (a new bar for each sweep point).
struct BarProgress {
    bar: std::sync::Mutex<ProgressBar>,
}

impl BarProgress {
    fn new() -> BarProgress {
        BarProgress {
            bar: std::sync::Mutex::new(ProgressBar::hidden()),
        }
    }

    fn bar(&self) -> std::sync::MutexGuard<'_, ProgressBar> {
        self.bar
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

impl ProgressSink for BarProgress {
    fn start(&self, total_frames: u64) {
        let bar = ProgressBar::new(total_frames);
        if let Ok(style) =
            ProgressStyle::with_template("running [{bar:40}] {pos}/{len} frames ({eta})")
        {
            bar.set_style(style.progress_chars("=> "));
        }
        *self.bar() = bar;
    }

    fn advance(&self, frames: u64) {
        self.bar().inc(frames);
    }

    fn notice(&self, message: &str) {
        self.bar().println(format!("note: {message}"));
    }

    fn tuning(&self, line: &str) {
        self.bar().suspend(|| eprintln!("{line}"));
    }

    fn finish(&self) {
        self.bar().finish_and_clear();
    }

    fn point(&self, index: usize, count: usize, choice: &str) {
        eprintln!("sweep point {}/{count}: {choice}", index + 1);
    }
}

//! What `roamsim validate` says about a flight's motion: its largest horizontal move, vertical
//! move and turn per frame, each with its frame, beside the bound the algorithms assume, and,
//! when frames break a bound, how many break each bound and the first of them. The figures are
//! the core's motion check (`sim::flight`), the same steps `flight.csv` lists; this file only
//! lays them out for a person.

use crate::edge::experiment::{BoundOrigin, Experiment};
use crate::edge::output::significant::three_significant;
use crate::sim::flight::{BrokenBounds, SpeedViolation, largest_steps};
use std::fmt::Write;

/// The flight's largest steps beside the bounds, then a note naming the bound each violation
/// breaks (none when no frame breaks one). Lines end with a newline.
pub fn describe_flight_motion(experiment: &Experiment) -> String {
    let mut out = String::new();
    let speed = experiment.speed;
    let violations = &experiment.violations;
    let Some(largest) = largest_steps(&experiment.flight) else {
        out.push_str("flight: one frame, no motion to check\n");
        return out;
    };
    let broken_count = |which: BoundTest| violations.iter().filter(|v| which(v.broken)).count();
    let rotation_origin = match experiment.rotation_bound {
        BoundOrigin::Declared => "",
        BoundOrigin::Derived => ", undeclared: the flight's largest turn",
    };
    out.push_str("flight: largest step per frame, beside the bound the algorithms assume\n");
    let rows = [
        (
            "horizontal",
            format!("{} m", three_significant(largest.horizontal.value)),
            largest.horizontal.frame,
            format!("{} m", three_significant(speed.horizontal)),
            broken_count(|b| b.horizontal),
        ),
        (
            "vertical",
            format!("{} m", three_significant(largest.vertical.value)),
            largest.vertical.frame,
            format!("{} m", three_significant(speed.vertical)),
            broken_count(|b| b.vertical),
        ),
        (
            "turn",
            format!(
                "{} rad ({}°)",
                three_significant(largest.turn.value),
                three_significant(largest.turn.value.to_degrees())
            ),
            largest.turn.frame,
            format!("{} rad{rotation_origin}", three_significant(speed.rotation)),
            broken_count(|b| b.rotation),
        ),
    ];
    for (name, value, frame, bound, broken) in rows {
        let broken = if broken > 0 {
            format!(" — broken in {broken} frame(s)")
        } else {
            String::new()
        };
        let _ = writeln!(
            out,
            "  {name:<11}{:<28}  bound {bound}{broken}",
            format!("{value} (frame {frame})")
        );
    }
    if let Some(first) = violations.first() {
        let _ = writeln!(
            out,
            "note: {} frame(s) break the speed or rotation bounds (first: frame {}, {}): {}",
            violations.len(),
            first.frame,
            first.broken.names().join(" and "),
            per_bound(violations)
        );
    }
    out
}

/// Whether a frame's broken bounds include one bound.
type BoundTest = fn(BrokenBounds) -> bool;

/// `horizontal in 1 frame(s) (first: frame 57), rotation in 3 frame(s) (first: frame 156)`.
fn per_bound(violations: &[SpeedViolation]) -> String {
    let bounds: [(&str, BoundTest); 3] = [
        ("horizontal", |b| b.horizontal),
        ("vertical", |b| b.vertical),
        ("rotation", |b| b.rotation),
    ];
    bounds
        .iter()
        .filter_map(|(name, broke)| {
            let mut frames = violations.iter().filter(|v| broke(v.broken));
            let first = frames.next()?;
            Some(format!(
                "{name} in {} frame(s) (first: frame {})",
                1 + frames.count(),
                first.frame
            ))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

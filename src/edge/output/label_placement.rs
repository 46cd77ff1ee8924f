//! Where to put the labels of a scatter chart's points so that they do not overlap: the labels
//! of `accuracy_vs_time`'s Pareto front (`docs/output-formats.md`, "plots/"; `plots/scatter.rs`
//! draws them). It draws nothing and chooses no point to label: the caller does both.
//!
//! Pure pixel geometry, no drawing: given each point's pixel position and its label's size, it
//! returns a box for each label. Points are served in the order given (callers put the most
//! important first: the Pareto front). Each label tries, in order, the four spots touching its
//! point (right-above, right-below, left-above, left-below), then spots on rings of growing
//! radius around it in sixteen directions, to be drawn with a leader line; it takes the first spot
//! that stays inside the plotting area and overlaps neither an earlier label nor any point's dot.
//! A label that finds no free spot takes the spot, moved inside the area, that overlaps the fewest
//! labels and dots (and says it overlaps), so that every point stays labelled. Greedy, O(points² · candidates): meant for tens
//! of points, not thousands.

/// An axis-aligned pixel box: left, top, width, height.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelBox {
    pub left: i32,
    pub top: i32,
    pub width: i32,
    pub height: i32,
}

impl PixelBox {
    fn right(&self) -> i32 {
        self.left + self.width
    }

    fn bottom(&self) -> i32 {
        self.top + self.height
    }

    /// Whether the two boxes share any pixel, after growing this one by `pad` on every side.
    pub fn overlaps(&self, other: &PixelBox, pad: i32) -> bool {
        self.left - pad < other.right()
            && other.left < self.right() + pad
            && self.top - pad < other.bottom()
            && other.top < self.bottom() + pad
    }

    fn inside(&self, area: &PixelBox) -> bool {
        self.left >= area.left
            && self.top >= area.top
            && self.right() <= area.right()
            && self.bottom() <= area.bottom()
    }

    /// The box shifted by the least amount that puts it inside `area` (its top-left corner when
    /// it is larger than the area).
    fn moved_inside(&self, area: &PixelBox) -> PixelBox {
        let left = self.left.min(area.right() - self.width).max(area.left);
        let top = self.top.min(area.bottom() - self.height).max(area.top);
        PixelBox { left, top, ..*self }
    }

    /// The point of the box's outline nearest to `p` (where a leader line meets the label).
    pub fn nearest_to(&self, p: (i32, i32)) -> (i32, i32) {
        (
            p.0.clamp(self.left, self.right()),
            p.1.clamp(self.top, self.bottom()),
        )
    }
}

/// Where one label went.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Placement {
    pub label: PixelBox,
    /// Drawn away from its point: join them with a leader line.
    pub needs_leader: bool,
    /// No free spot was found: it overlaps something.
    pub overlapping: bool,
}

/// Radius of a point's dot, and the gap kept between a dot and a label touching it.
pub const DOT_RADIUS: i32 = 6;
const GAP: i32 = 3;
/// Padding kept between two labels.
const LABEL_PAD: i32 = 2;
/// Rings tried for labels with leader lines, in pixels from the point.
const RINGS: [i32; 8] = [26, 42, 62, 88, 120, 160, 210, 270];
const DIRECTIONS: usize = 16;

/// Places every label; `points[k]` is a dot's centre and `sizes[k]` its label's (width, height).
pub fn place_labels(points: &[(i32, i32)], sizes: &[(i32, i32)], area: PixelBox) -> Vec<Placement> {
    let dots: Vec<PixelBox> = points
        .iter()
        .map(|&(x, y)| PixelBox {
            left: x - DOT_RADIUS,
            top: y - DOT_RADIUS,
            width: 2 * DOT_RADIUS,
            height: 2 * DOT_RADIUS,
        })
        .collect();
    let mut placed: Vec<PixelBox> = Vec::with_capacity(points.len());
    let mut placements = Vec::with_capacity(points.len());
    for (&point, &(width, height)) in points.iter().zip(sizes) {
        let candidates = candidates(point, width, height);
        let free = |label: &PixelBox| {
            label.inside(&area)
                && !placed.iter().any(|other| label.overlaps(other, LABEL_PAD))
                && !dots.iter().any(|dot| label.overlaps(dot, 1))
        };
        let placement = match candidates.iter().position(|(label, _)| free(label)) {
            Some(k) => Placement {
                label: candidates[k].0,
                needs_leader: candidates[k].1,
                overlapping: false,
            },
            None => {
                // The spot, moved inside the area, that overlaps the fewest labels and dots.
                let overlaps = |label: &PixelBox| {
                    placed.iter().filter(|o| label.overlaps(o, 0)).count()
                        + dots.iter().filter(|d| label.overlaps(d, 0)).count()
                };
                let (label, needs_leader) = candidates
                    .iter()
                    .map(|&(label, leader)| (label.moved_inside(&area), leader))
                    .min_by_key(|(label, _)| overlaps(label))
                    .unwrap_or(candidates[0]);
                Placement {
                    label,
                    needs_leader,
                    overlapping: true,
                }
            }
        };
        placed.push(placement.label);
        placements.push(placement);
    }
    placements
}

/// Candidate boxes for one label, best first, each with whether it needs a leader line.
fn candidates((x, y): (i32, i32), width: i32, height: i32) -> Vec<(PixelBox, bool)> {
    let at = |left: i32, top: i32| PixelBox {
        left,
        top,
        width,
        height,
    };
    let near = DOT_RADIUS + GAP;
    let mut candidates = vec![
        (at(x + near, y - near - height + DOT_RADIUS), false),
        (at(x + near, y + near - DOT_RADIUS), false),
        (at(x - near - width, y - near - height + DOT_RADIUS), false),
        (at(x - near - width, y + near - DOT_RADIUS), false),
    ];
    for radius in RINGS {
        for k in 0..DIRECTIONS {
            let angle = std::f64::consts::TAU * k as f64 / DIRECTIONS as f64;
            let (dx, dy) = (angle.cos(), -angle.sin());
            // The box's centre on the ring, pushed out by half the box along the direction.
            let cx = x as f64 + dx * (radius as f64 + 0.5 * width as f64 * dx.abs());
            let cy = y as f64 + dy * (radius as f64 + 0.5 * height as f64 * dy.abs());
            let left = (cx - 0.5 * width as f64).round() as i32;
            let top = (cy - 0.5 * height as f64).round() as i32;
            candidates.push((at(left, top), true));
        }
    }
    candidates
}

#[cfg(test)]
mod tests {
    use super::*;

    const AREA: PixelBox = PixelBox {
        left: 0,
        top: 0,
        width: 1000,
        height: 600,
    };

    #[test]
    fn a_lone_point_is_labelled_right_above_it_without_a_leader() {
        let placement = place_labels(&[(500, 300)], &[(80, 14)], AREA)[0];
        assert!(!placement.needs_leader && !placement.overlapping);
        assert!(placement.label.left > 500 && placement.label.bottom() <= 300);
    }

    #[test]
    fn a_tight_cluster_gets_labels_that_overlap_nothing() {
        // Twenty points within a 30-pixel square, as close sweep points are on the Pareto plot.
        let points: Vec<(i32, i32)> = (0..20)
            .map(|k| (480 + (k * 7) % 30, 290 + (k * 11) % 30))
            .collect();
        let sizes = vec![(150, 14); points.len()];
        let placements = place_labels(&points, &sizes, AREA);
        for (k, a) in placements.iter().enumerate() {
            assert!(!a.overlapping, "label {k} found no free spot");
            assert!(a.label.inside(&AREA));
            for b in &placements[k + 1..] {
                assert!(!a.label.overlaps(&b.label, 0), "{a:?} overlaps {b:?}");
            }
            for &(x, y) in &points {
                let dot = PixelBox {
                    left: x - DOT_RADIUS,
                    top: y - DOT_RADIUS,
                    width: 12,
                    height: 12,
                };
                assert!(
                    !a.label.overlaps(&dot, 0),
                    "{a:?} covers the dot at ({x}, {y})"
                );
            }
        }
        assert!(placements.iter().any(|p| p.needs_leader));
    }

    #[test]
    fn a_point_at_the_right_edge_is_labelled_on_its_left() {
        let placement = place_labels(&[(990, 300)], &[(80, 14)], AREA)[0];
        assert!(placement.label.right() <= 990 && !placement.overlapping);
    }

    #[test]
    fn when_nothing_fits_the_label_still_goes_inside_the_area_and_says_so() {
        let small = PixelBox {
            left: 0,
            top: 0,
            width: 60,
            height: 40,
        };
        let placements = place_labels(&[(30, 20), (32, 22)], &[(50, 14), (50, 14)], small);
        assert!(placements[1].overlapping);
        assert!(placements.iter().all(|p| p.label.inside(&small)));
    }
}

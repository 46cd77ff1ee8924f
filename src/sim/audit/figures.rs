//! The tallies of one error figure over a frame's samples in view (SPEC §7: "per frame: max,
//! mean and 95th percentile"): [`Figures`] keeps the values as found, their running sum and
//! maximum, and a histogram of their top bits, and summarises them. It measures nothing (the
//! batch hands it finished values, `batch.rs`) and keeps nothing across frames.
//!
//! Decisions:
//!
//! - **The p95 is nearest-rank**, the rule of [`crate::sim::stats::nearest_rank`], and samples
//!   with zero error count (they are part of the mean).
//! - **Exact tallies.** The sum is kept in order, from −0.0 as `Iterator::sum` starts (its
//!   rounding must be that of a sum in order); the maxima and the histogram, which merge
//!   exactly, are kept in [`LANES`] lanes, so that a run of values in one bucket does not wait
//!   on the value before. The two figures are tallied side by side in one loop, so that their
//!   two chains of additions run together.
//! - **The p95 selected inside its bucket.** Values are counted into 65 536 buckets of their top
//!   16 bits in total order; the summary selects among the values of the one bucket that holds
//!   the p95's rank only. `f64::total_cmp` orders bit patterns, so the value found is the one a
//!   selection over all values finds, to the bit.

use crate::sim::stats::ErrorSummary;

/// Buckets of the histogram of a figure's values: by their top 16 bits in total order.
const BUCKETS: usize = 1 << 16;

/// Values a figure takes in at once: its maximum and its histogram are kept per lane, so
/// that neither waits on the value before (runs of values in one bucket are the rule).
const LANES: usize = 4;

/// A key that orders `f64`s as [`f64::total_cmp`] does, as an unsigned integer.
#[inline]
fn total_order_key(value: f64) -> u64 {
    let bits = value.to_bits();
    bits ^ ((((bits as i64) >> 63) as u64) >> 1) ^ (1 << 63)
}

/// One error measure's values over a frame's samples in view, in the order they were found,
/// with their running sum, maximum and a histogram of their top bits: the summary then reads
/// only the values of the p95's bucket again.
pub(super) struct Figures {
    values: Vec<f64>,
    sum: f64,
    max: f64,
    /// Values per bucket (`total_order_key >> 48`) and lane: bucket `b`'s count is the sum
    /// of `histogram[b * LANES..][..LANES]`.
    histogram: Box<[u32]>,
    /// The lowest and highest bucket holding a value (empty: `BUCKETS`, 0): the summary
    /// scans and the next frame clears only these.
    buckets: (usize, usize),
}

impl Default for Figures {
    fn default() -> Figures {
        Figures {
            values: Vec::new(),
            sum: -0.0,
            max: f64::NEG_INFINITY,
            histogram: vec![0; BUCKETS * LANES].into_boxed_slice(),
            buckets: (BUCKETS, 0),
        }
    }
}

impl Figures {
    pub(super) fn clear(&mut self) {
        let (low, high) = self.buckets;
        if low <= high {
            self.histogram[low * LANES..(high + 1) * LANES].fill(0);
        }
        self.buckets = (BUCKETS, 0);
        self.values.clear();
        // The sum and the maximum start where `Iterator::sum` and the reference's fold do.
        self.sum = -0.0;
        self.max = f64::NEG_INFINITY;
    }

    /// Adds `first` to one figure and `second` to another, each in order: one loop, so that
    /// the two sums (chains of additions, each waiting on the one before) run side by side.
    #[inline(always)]
    pub(super) fn extend_both(first: (&mut Figures, &[f64]), second: (&mut Figures, &[f64])) {
        let ((a, first), (b, second)) = (first, second);
        a.values.extend_from_slice(first);
        b.values.extend_from_slice(second);
        let (mut a_sums, mut b_sums) = (Sums::new(a), Sums::new(b));
        let (first_chunks, second_chunks) = (first.chunks_exact(LANES), second.chunks_exact(LANES));
        let common = first_chunks.len().min(second_chunks.len());
        for (x, y) in first_chunks.zip(second_chunks) {
            for lane in 0..LANES {
                a_sums.add(lane, x[lane]);
                b_sums.add(lane, y[lane]);
            }
        }
        for (sums, values) in [(&mut a_sums, first), (&mut b_sums, second)] {
            for chunk in values[common * LANES..].chunks(LANES) {
                for (lane, &value) in chunk.iter().enumerate() {
                    sums.add(lane, value);
                }
            }
        }
        let (a_figures, b_figures) = (a_sums.finish(), b_sums.finish());
        (a.sum, a.max, a.buckets) = a_figures;
        (b.sum, b.max, b.buckets) = b_figures;
    }

    pub(super) fn len(&self) -> usize {
        self.values.len()
    }

    /// Max, mean and nearest-rank p95 (the rule of [`crate::sim::stats::nearest_rank`]): the
    /// p95 is found in the histogram's bucket that holds its rank, by selection among that
    /// bucket's values only. `f64::total_cmp` orders bit patterns, so the value found is the
    /// one a selection over all values finds, to the bit.
    pub(super) fn summary(&self, scratch: &mut Vec<f64>) -> Option<ErrorSummary> {
        let n = self.len();
        if n == 0 {
            return None;
        }
        let rank = ((0.95 * n as f64).ceil() as usize).clamp(1, n);
        let mut below = 0;
        let (low, high) = self.buckets;
        let mut bucket = low as u64;
        let counts = self.histogram[low * LANES..(high + 1) * LANES].chunks_exact(LANES);
        for (k, count) in counts.map(|lanes| lanes.iter().sum::<u32>()).enumerate() {
            if below + count as usize >= rank {
                bucket = (low + k) as u64;
                break;
            }
            below += count as usize;
        }
        scratch.clear();
        // Eight values at a time (a vector comparison), most of them holding none of the
        // bucket's.
        let in_bucket = |value: f64| total_order_key(value) >> 48 == bucket;
        let chunks = self.values.chunks_exact(8);
        let rest = chunks.remainder();
        for chunk in chunks {
            if chunk
                .iter()
                .fold(false, |any, &value| any | in_bucket(value))
            {
                scratch.extend(chunk.iter().copied().filter(|&value| in_bucket(value)));
            }
        }
        scratch.extend(rest.iter().copied().filter(|&value| in_bucket(value)));
        let (_, p95, _) = scratch.select_nth_unstable_by(rank - 1 - below, f64::total_cmp);
        Some(ErrorSummary {
            max: self.max,
            mean: self.sum / n as f64,
            p95: *p95,
        })
    }
}

/// A figure's running sum, maximum, histogram and bucket range while values are added: the
/// maximum and the bucket range per lane, so that neither waits on the value before (runs of
/// values in one bucket are the rule); the sum in order (its rounding must be that of a sum
/// in order). The lanes' maxima equal the maximum in order because no value is −0.0 (each is
/// a square root, an `atan2` of a non-negative sine, or 0 or π over the pixel angle) and
/// `f64::max` skips NaN either way.
struct Sums<'a> {
    sum: f64,
    max: [f64; LANES],
    low: [usize; LANES],
    high: [usize; LANES],
    histogram: &'a mut [u32],
}

impl Sums<'_> {
    fn new(figures: &mut Figures) -> Sums<'_> {
        Sums {
            sum: figures.sum,
            max: [figures.max; LANES],
            low: [figures.buckets.0; LANES],
            high: [figures.buckets.1; LANES],
            histogram: &mut figures.histogram,
        }
    }

    #[inline(always)]
    fn add(&mut self, lane: usize, value: f64) {
        self.sum += value;
        self.max[lane] = self.max[lane].max(value);
        let bucket = (total_order_key(value) >> 48) as usize;
        self.histogram[bucket * LANES + lane] += 1;
        self.low[lane] = self.low[lane].min(bucket);
        self.high[lane] = self.high[lane].max(bucket);
    }

    /// The figure's sum, maximum and bucket range.
    fn finish(self) -> (f64, f64, (usize, usize)) {
        let max = self.max.into_iter().fold(f64::NEG_INFINITY, f64::max);
        let low = self.low.into_iter().min().unwrap_or(BUCKETS);
        let high = self.high.into_iter().max().unwrap_or(0);
        (self.sum, max, (low, high))
    }
}

#[cfg(test)]
mod tests {
    use super::Figures;
    use crate::sim::audit::reference;

    #[test]
    fn the_histogram_summary_equals_the_selection_over_all_values_bit_for_bit() {
        // Values spread over many buckets, crowded into one, repeated, zero, and counts where
        // the p95's rank falls on a bucket's first or last value.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut sets: Vec<Vec<f64>> = vec![vec![0.0], vec![3.5; 7], vec![0.0, 1.0]];
        for n in [1, 2, 19, 20, 21, 100, 1000, 4001] {
            sets.push((0..n).map(|_| (next() % 1_000_000) as f64 * 1e-4).collect());
            sets.push(
                (0..n)
                    .map(|_| 1.0 + (next() % 1000) as f64 * 1e-12)
                    .collect(),
            );
            sets.push((0..n).map(|_| (next() % 4) as f64).collect());
            sets.push(
                (0..n)
                    .map(|_| f64::from_bits(next() >> 2) % 1e6)
                    .map(f64::abs)
                    .collect(),
            );
        }
        let (mut figures, mut other) = (Figures::default(), Figures::default());
        let mut scratch = Vec::new();
        for values in sets {
            // Added in pieces of every length (lanes and the tail of a piece), beside another
            // figure taking every third value.
            figures.clear();
            other.clear();
            let thirds: Vec<f64> = values.iter().copied().step_by(3).collect();
            let (mut at, mut piece) = (0, 1);
            while at < values.len() {
                let end = (at + piece).min(values.len());
                let other_piece = &thirds[(at / 3).min(thirds.len())..(end / 3).min(thirds.len())];
                Figures::extend_both((&mut figures, &values[at..end]), (&mut other, other_piece));
                (at, piece) = (end, piece % 9 + 1);
            }
            let rest = &thirds[(values.len() / 3).min(thirds.len())..];
            Figures::extend_both((&mut figures, &[]), (&mut other, rest));
            for (figures, values) in [(&figures, &values), (&other, &thirds)] {
                let ours = figures.summary(&mut scratch);
                let theirs = reference::summarise_in_place(&mut values.clone());
                assert_eq!(
                    format!("{ours:?}"),
                    format!("{theirs:?}"),
                    "{} values",
                    values.len()
                );
            }
        }
        figures.clear();
        assert_eq!(figures.summary(&mut scratch), None);
    }
}

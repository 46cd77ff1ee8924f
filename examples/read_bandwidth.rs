//! The machine's single-thread read bandwidth, for the audit's memory-bandwidth limit
//! (`docs/performance.md`, "The audit"):
//!
//! ```text
//! cargo run --release --example read_bandwidth [MEBIBYTES] [PASSES]
//! ```
//!
//! sums an array of `f32` of MEBIBYTES MiB (default 256, far above the caches) PASSES times
//! (default 10) on one thread, in eight independent sums so that the additions do not limit
//! the reads, and prints the best pass's bandwidth in GB/s (10^9 bytes per second).

use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let number = |k: usize, default: usize| {
        args.get(k).map_or(default, |a| {
            a.parse()
                .unwrap_or_else(|_| panic!("argument {} is a whole number, got {a:?}", k + 1))
        })
    };
    let (mebibytes, passes) = (number(0, 256), number(1, 10));
    let values: Vec<f32> = (0..mebibytes << 18).map(|k| (k % 1000) as f32).collect();
    let bytes = std::mem::size_of_val(values.as_slice()) as f64;
    let mut best = f64::INFINITY;
    let mut total = 0.0;
    for _ in 0..passes.max(1) {
        let start = Instant::now();
        let mut sums = [0.0f32; 8];
        for chunk in values.chunks_exact(8) {
            for (sum, value) in sums.iter_mut().zip(chunk) {
                *sum += value;
            }
        }
        let seconds = start.elapsed().as_secs_f64();
        total += std::hint::black_box(sums).iter().sum::<f32>() as f64;
        best = best.min(seconds);
    }
    println!(
        "read {:.0} MiB in {:.2} ms: {:.2} GB/s (best of {} passes; checksum {total})",
        bytes / (1 << 20) as f64,
        best * 1e3,
        bytes / best / 1e9,
        passes.max(1),
    );
}

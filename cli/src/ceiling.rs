//! This core's own ceilings for a neuron-update loop, measured on the spot: the peak
//! fused-multiply-add throughput at a precision ([`peak_fma_flops`]) and the bandwidth of a
//! read-modify-write pass over a working set of a given size ([`stream_bandwidth`]).
//!
//! `neurotac bench neurons` divides what it achieved by them ([`Ceiling::fractions`]), so a
//! user sees how close a loop is to what this machine can do at all: an update loop that does
//! `f` flops and moves `b` bytes per neuron update at `r` updates/s runs at `r·f / peak` of the
//! arithmetic ceiling and `r·b / bandwidth` of the memory ceiling; the larger of the two
//! fractions says which one binds (the roofline model: Williams, Waterman & Patterson, "Roofline:
//! an insightful visual performance model for multicore architectures", CACM 52(4), 2009).

use neurotac_experiments::neuron_setup::Precision;
use neurotac_neurons::Real;
use serde::Serialize;
use std::hint::black_box;
use std::time::Instant;

/// Independent accumulators of the portable FMA kernel: 32 vectors of 128 bits at f64, 16 of
/// 256 bits, more than an FMA's latency × issue width on current x86 and Arm cores, so the
/// kernel is bound by FMA throughput, not by latency.
const ACCUMULATORS: usize = 64;

/// Independent 512-bit accumulators of the AVX-512 kernel (4-cycle latency × 2 ports = 8 in
/// flight, doubled for margin; 16 of the 32 vector registers).
#[cfg(all(target_arch = "x86_64", target_feature = "avx512f"))]
const ZMM_ACCUMULATORS: usize = 16;

/// The largest working set the bandwidth is measured on: far beyond any cache, so a larger
/// population's loop streams from memory at the bandwidth measured here, without a second
/// buffer the size of its state.
pub const MAX_WORKING_SET: usize = 1 << 30;

/// Repetitions of each micro-benchmark; the fastest counts (noise only ever adds time).
const REPEATS: usize = 5;

/// What the micro-benchmarks measured, and the work a loop does per update.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Ceiling {
    /// Peak fused-multiply-add throughput of one core at the precision (flop/s; an FMA is 2
    /// flops).
    pub peak_flops_per_s: f64,
    /// The vectors the peak was measured with: `"avx512"` (the widest this CPU has, built
    /// with `target-cpu=native`) or `"portable"` (what the compiler chose for this build).
    pub peak_kernel: &'static str,
    /// Read-modify-write bandwidth of one core over a working set of `working_set_bytes`
    /// (bytes read + bytes written per second).
    pub bandwidth_bytes_per_s: f64,
    /// The working set the bandwidth was measured on (bytes).
    pub working_set_bytes: usize,
}

/// The share of each ceiling a loop reached.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct CeilingFractions {
    /// `updates/s × flops per update / peak flop/s`.
    pub of_peak_flops: f64,
    /// `updates/s × bytes per update / bandwidth`.
    pub of_bandwidth: f64,
}

impl Ceiling {
    /// Measures both ceilings on the calling thread: the FMA peak at `precision`, and the
    /// bandwidth of a read-modify-write pass over `working_set_bytes` (from 4 KiB to
    /// [`MAX_WORKING_SET`]).
    pub fn measure(precision: Precision, working_set_bytes: usize) -> Ceiling {
        let working_set_bytes = working_set_bytes.clamp(4096, MAX_WORKING_SET);
        let (peak_flops_per_s, peak_kernel) = peak_fma_flops(precision);
        let bandwidth_bytes_per_s = match precision {
            Precision::F32 => stream_bandwidth::<f32>(working_set_bytes),
            Precision::F64 => stream_bandwidth::<f64>(working_set_bytes),
        };
        Ceiling {
            peak_flops_per_s,
            peak_kernel,
            bandwidth_bytes_per_s,
            working_set_bytes,
        }
    }

    /// The higher of two measurements of each ceiling (over the same working set): noise
    /// only ever lowers a measured ceiling.
    pub fn max(self, other: Ceiling) -> Ceiling {
        let (peak_flops_per_s, peak_kernel) = if other.peak_flops_per_s > self.peak_flops_per_s {
            (other.peak_flops_per_s, other.peak_kernel)
        } else {
            (self.peak_flops_per_s, self.peak_kernel)
        };
        Ceiling {
            peak_flops_per_s,
            peak_kernel,
            bandwidth_bytes_per_s: self.bandwidth_bytes_per_s.max(other.bandwidth_bytes_per_s),
            working_set_bytes: self.working_set_bytes,
        }
    }

    /// The fractions of both ceilings reached by `updates_per_s` (one thread's) doing `flops`
    /// and moving `bytes` per update.
    pub fn fractions(&self, updates_per_s: f64, flops: u32, bytes: u32) -> CeilingFractions {
        CeilingFractions {
            of_peak_flops: updates_per_s * f64::from(flops) / self.peak_flops_per_s,
            of_bandwidth: updates_per_s * f64::from(bytes) / self.bandwidth_bytes_per_s,
        }
    }
}
/// Peak fused-multiply-add throughput of the calling thread at `precision` (flop/s, an FMA
/// counting 2) and the kernel that reached it: independent chains `x ← x·a + b` in
/// 64 scalars the compiler vectorises (`"portable"`) and, where the build
/// targets AVX-512, in 512-bit registers (`"avx512"`: compilers prefer 256-bit vectors on such
/// CPUs, so the portable kernel alone would understate the core); the faster counts.
pub fn peak_fma_flops(precision: Precision) -> (f64, &'static str) {
    let mut best = match precision {
        Precision::F64 => (
            flop_rate(ACCUMULATORS, |i, a, b| fma_chains(i, a, b)[0]),
            "portable",
        ),
        Precision::F32 => (
            flop_rate(ACCUMULATORS, |i, a, b| {
                f64::from(fma_chains(i, a as f32, b as f32)[0])
            }),
            "portable",
        ),
    };
    #[cfg(all(target_arch = "x86_64", target_feature = "avx512f"))]
    {
        // SAFETY: the build targets AVX-512 (the cfg), so every CPU that runs this binary has it.
        let zmm = match precision {
            Precision::F64 => flop_rate(ZMM_ACCUMULATORS * 8, |i, a, b| unsafe {
                avx512::fma_chains_f64(i, a, b)
            }),
            Precision::F32 => flop_rate(ZMM_ACCUMULATORS * 16, |i, a, b| unsafe {
                f64::from(avx512::fma_chains_f32(i, a as f32, b as f32))
            }),
        };
        if zmm > best.0 {
            best = (zmm, "avx512");
        }
    }
    best
}

/// The flop rate of an FMA `kernel(iterations, a, b)` running `chains` chains: ≈ 1–3 ms per
/// timing, the fastest of [`REPEATS`].
fn flop_rate(chains: usize, kernel: impl Fn(u64, f64, f64) -> f64) -> f64 {
    let iterations: u64 = 200_000;
    let mut best = f64::INFINITY;
    for _ in 0..REPEATS {
        let start = Instant::now();
        // a < 1 and b small keep every chain finite and normal for any number of iterations;
        // opaque at every call, so no call can be hoisted out of its timing.
        black_box(kernel(
            black_box(iterations),
            black_box(0.999_999),
            black_box(1e-6),
        ));
        best = best.min(start.elapsed().as_secs_f64());
    }
    2.0 * chains as f64 * iterations as f64 / best
}

/// The portable FMA kernel: `iterations` rounds of `x ← x·a + b` on every accumulator.
#[inline(never)]
fn fma_chains<F: Real>(iterations: u64, a: F, b: F) -> [F; ACCUMULATORS] {
    let mut acc = [F::one(); ACCUMULATORS];
    for _ in 0..iterations {
        for x in &mut acc {
            *x = x.mul_add(a, b);
        }
    }
    acc
}

/// The FMA kernel in AVX-512 registers ([`ZMM_ACCUMULATORS`] chains of 8 f64 or 16 f32 lanes);
/// returns the sum of every lane, so nothing is optimised away.
#[cfg(all(target_arch = "x86_64", target_feature = "avx512f"))]
mod avx512 {
    use super::ZMM_ACCUMULATORS;
    use std::arch::x86_64::*;

    macro_rules! kernel {
        ($name:ident, $t:ty, $set1:ident, $fmadd:ident, $add:ident, $reduce:ident) => {
            #[inline(never)]
            #[target_feature(enable = "avx512f")]
            pub(super) fn $name(iterations: u64, a: $t, b: $t) -> $t {
                let (va, vb) = ($set1(a), $set1(b));
                let mut acc = [$set1(1.0); ZMM_ACCUMULATORS];
                for _ in 0..iterations {
                    for x in &mut acc {
                        *x = $fmadd(*x, va, vb);
                    }
                }
                $reduce(acc.into_iter().fold($set1(0.0), |s, x| $add(s, x)))
            }
        };
    }
    kernel!(
        fma_chains_f64,
        f64,
        _mm512_set1_pd,
        _mm512_fmadd_pd,
        _mm512_add_pd,
        _mm512_reduce_add_pd
    );
    kernel!(
        fma_chains_f32,
        f32,
        _mm512_set1_ps,
        _mm512_fmadd_ps,
        _mm512_add_ps,
        _mm512_reduce_add_ps
    );
}

/// Read-modify-write bandwidth of the calling thread over a buffer of `bytes` of `F` (bytes
/// read + written per second): passes of `x[i] ← x[i]·a + b`, as a neuron-update loop reads
/// and writes its state, over ≥ 64 MiB of traffic per timing; the fastest of five.
pub fn stream_bandwidth<F: Real>(bytes: usize) -> f64 {
    let n = (bytes / size_of::<F>()).max(1);
    let mut x = vec![F::one(); n];
    let (a, b) = (black_box(F::of(0.999_999)), black_box(F::of(1e-6)));
    let moved_per_pass = 2 * n * size_of::<F>();
    let passes = (64usize << 20).div_ceil(moved_per_pass).max(2);
    // One untimed pass brings the buffer into the cache level it fits.
    rmw_pass(&mut x, a, b);
    let mut best = f64::INFINITY;
    for _ in 0..REPEATS {
        let start = Instant::now();
        for _ in 0..passes {
            rmw_pass(black_box(&mut x), a, b);
        }
        best = best.min(start.elapsed().as_secs_f64());
    }
    (moved_per_pass * passes) as f64 / best
}

#[inline(never)]
fn rmw_pass<F: Real>(x: &mut [F], a: F, b: F) {
    for v in x {
        *v = v.mul_add(a, b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_portable_fma_kernel_computes_every_chain() {
        // x ← x·a + b from 1 for 3 rounds, the closed form of the affine map.
        let (a, b) = (0.5f64, 1.0);
        let chains = fma_chains(3, a, b);
        let expected = a.powi(3) + b * (1.0 + a + a * a);
        assert!(chains.iter().all(|&x| x == expected), "{chains:?}");
    }

    #[test]
    fn the_fractions_divide_the_work_by_the_ceilings() {
        let ceiling = Ceiling {
            peak_flops_per_s: 8e10,
            peak_kernel: "portable",
            bandwidth_bytes_per_s: 4e10,
            working_set_bytes: 1 << 20,
        };
        let f = ceiling.fractions(2e9, 8, 16);
        assert_eq!((f.of_peak_flops, f.of_bandwidth), (0.2, 0.8));
        // Of two measurements, each ceiling's higher one counts (noise only lowers them).
        let busy = Ceiling {
            peak_flops_per_s: 4e10,
            bandwidth_bytes_per_s: 5e10,
            ..ceiling
        };
        let best = ceiling.max(busy);
        assert_eq!(
            (best.peak_flops_per_s, best.bandwidth_bytes_per_s),
            (8e10, 5e10)
        );
    }
}

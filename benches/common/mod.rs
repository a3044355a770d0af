//! Shared by the benches: a criterion measurement of the benchmark thread's CPU time
//! (`clock_gettime(CLOCK_THREAD_CPUTIME_ID)`), which other processes sharing the cores cannot
//! inflate by time-slicing. Criterion then reports "M/s per CPU".
#![allow(dead_code)] // each bench uses what it needs

use criterion::Throughput;
use criterion::measurement::{Measurement, ValueFormatter};
use std::time::Duration;

/// CPU time of the calling thread (ns since it started).
pub fn thread_cpu_ns() -> u64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the clock id is a constant POSIX clock.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "CLOCK_THREAD_CPUTIME_ID is available");
    ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
}

/// Criterion measurement: CPU time of the benchmark thread.
pub struct ThreadCpuTime;

impl Measurement for ThreadCpuTime {
    type Intermediate = u64;
    type Value = Duration;

    fn start(&self) -> u64 {
        thread_cpu_ns()
    }

    fn end(&self, start: u64) -> Duration {
        Duration::from_nanos(thread_cpu_ns().saturating_sub(start))
    }

    fn add(&self, a: &Duration, b: &Duration) -> Duration {
        *a + *b
    }

    fn zero(&self) -> Duration {
        Duration::ZERO
    }

    fn to_f64(&self, value: &Duration) -> f64 {
        value.as_nanos() as f64
    }

    fn formatter(&self) -> &dyn ValueFormatter {
        &CpuFormatter
    }
}

/// Formats CPU nanoseconds as µs (values) and M events per CPU second (throughput).
struct CpuFormatter;

impl ValueFormatter for CpuFormatter {
    fn scale_values(&self, _typical: f64, values: &mut [f64]) -> &'static str {
        values.iter_mut().for_each(|v| *v /= 1e3);
        "µs (CPU)"
    }

    fn scale_throughputs(
        &self,
        _typical: f64,
        throughput: &Throughput,
        values: &mut [f64],
    ) -> &'static str {
        let per_iteration = match *throughput {
            Throughput::Elements(n) | Throughput::ElementsAndBytes { elements: n, .. } => n as f64,
            Throughput::Bytes(n) | Throughput::BytesDecimal(n) => n as f64,
            Throughput::Bits(n) => n as f64,
        };
        values
            .iter_mut()
            .for_each(|v| *v = per_iteration * 1e3 / *v);
        "M/s per CPU"
    }

    fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
        "ns"
    }
}

#[path = "../../tests/common/shared_data.rs"]
mod shared_data;

/// `../shared/data/davis240/<name>` when it exists; otherwise prints why the bench skips it.
pub fn shared_recording(name: &str) -> Option<std::path::PathBuf> {
    shared_data::davis240_file(name)
}

/// Runs `$bench(c, group)` twice — as `$group` in wall-clock time and as `${group}_cpu` in the
/// thread's CPU time — and makes the criterion `main`.
#[macro_export]
macro_rules! wall_and_cpu_main {
    ($bench:ident, $group:literal) => {
        fn wall_time(c: &mut criterion::Criterion) {
            $bench(c, $group);
        }
        fn cpu_time(c: &mut criterion::Criterion<common::ThreadCpuTime>) {
            $bench(c, concat!($group, "_cpu"));
        }
        criterion::criterion_group!(wall, wall_time);
        criterion::criterion_group! {
            name = cpu;
            config = criterion::Criterion::default().with_measurement(common::ThreadCpuTime);
            targets = cpu_time
        }
        criterion::criterion_main!(wall, cpu);
    };
}

//! Criterion measurement: this thread's CPU time ([`helixreach::cpu_time::thread_cpu_nanos`]),
//! the meaningful figure on a shared, oversubscribed machine (it excludes time the thread spent
//! descheduled, though not cache and SMT contention). Shared by the benches via
//! `#[path = "common/cpu_time.rs"] mod cpu_time;`.

use criterion::measurement::{Measurement, ValueFormatter, WallTime};

/// Thread CPU time in nanoseconds (Linux `clock_gettime(CLOCK_THREAD_CPUTIME_ID)`).
#[derive(Debug, Clone, Copy)]
pub struct ThreadCpuTime;

fn thread_cpu_ns() -> u64 {
    helixreach::cpu_time::thread_cpu_nanos().expect("this thread's CPU clock")
}

impl Measurement for ThreadCpuTime {
    type Intermediate = u64;
    type Value = u64;
    fn start(&self) -> u64 {
        thread_cpu_ns()
    }
    fn end(&self, i: u64) -> u64 {
        thread_cpu_ns() - i
    }
    fn add(&self, a: &u64, b: &u64) -> u64 {
        a + b
    }
    fn zero(&self) -> u64 {
        0
    }
    fn to_f64(&self, v: &u64) -> f64 {
        *v as f64
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        // Values are nanoseconds, as for the wall clock.
        static WALL: WallTime = WallTime;
        WALL.formatter()
    }
}

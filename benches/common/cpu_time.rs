//! Criterion measurement: this thread's CPU time (Linux `clock_gettime(CLOCK_THREAD_CPUTIME_ID)`),
//! the meaningful figure on a shared, oversubscribed machine (it excludes time the thread spent
//! descheduled, though not cache and SMT contention). Shared by the benches via
//! `#[path = "common/cpu_time.rs"] mod cpu_time;`.

use criterion::measurement::{Measurement, ValueFormatter, WallTime};

/// Thread CPU time in nanoseconds (Linux `clock_gettime(CLOCK_THREAD_CPUTIME_ID)`).
#[derive(Debug, Clone, Copy)]
pub struct ThreadCpuTime;

const CLOCK_THREAD_CPUTIME_ID: i32 = 3;

extern "C" {
    fn clock_gettime(clk_id: i32, tp: *mut [i64; 2]) -> i32;
}

fn thread_cpu_ns() -> u64 {
    let mut ts = [0i64; 2];
    // SAFETY: `ts` has the layout of `struct timespec` on 64-bit Linux ({i64 sec, i64 nsec}) and
    // outlives the call; the clock id is a valid Linux constant.
    let rc = unsafe { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    ts[0] as u64 * 1_000_000_000 + ts[1] as u64
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

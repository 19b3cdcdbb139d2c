//! CPU time of the calling thread, with nanosecond resolution: POSIX
//! `clock_gettime(CLOCK_THREAD_CPUTIME_ID)`. Used for speed figures on a shared machine, where
//! wall time measures the load more than the code. (`/proc/thread-self/schedstat` is not a
//! substitute: it advances in scheduler ticks, so short measurements read 0.)
//!
//! ```
//! let t0 = helixreach::cpu_time::thread_cpu_seconds().unwrap();
//! let mut x = 0u64;
//! for i in 0..100_000u64 { x = x.wrapping_mul(31).wrapping_add(i); }
//! std::hint::black_box(x);
//! let dt = helixreach::cpu_time::thread_cpu_seconds().unwrap() - t0;
//! assert!(dt > 0.0 && dt < 10.0, "{dt}");
//! ```

use crate::error::{Error, Result};

/// One nanosecond in seconds (the clocks count nanoseconds; a unit, not a tolerance).
const SECONDS_PER_NANO: f64 = 1e-9;

/// This thread's CPU time in seconds since an arbitrary origin (errors if the OS has no
/// per-thread CPU clock).
pub fn thread_cpu_seconds() -> Result<f64> {
    thread_cpu_nanos().map(|ns| ns as f64 * SECONDS_PER_NANO)
}

/// This thread's CPU time in nanoseconds since an arbitrary origin: the one reading of the
/// clock (the benches' criterion measurement uses it too).
pub fn thread_cpu_nanos() -> Result<u64> {
    #[cfg(unix)]
    return read_clock(libc::CLOCK_THREAD_CPUTIME_ID, "CLOCK_THREAD_CPUTIME_ID");
    #[cfg(not(unix))]
    Err(Error::invalid(
        "clock",
        "thread CPU time",
        "not available on this platform",
    ))
}

/// CPU time of the whole process (all threads) in seconds since an arbitrary origin: for a
/// parallel run, CPU ÷ cores is the wall time idle cores would need.
pub fn process_cpu_seconds() -> Result<f64> {
    #[cfg(unix)]
    return read_clock(libc::CLOCK_PROCESS_CPUTIME_ID, "CLOCK_PROCESS_CPUTIME_ID")
        .map(|ns| ns as f64 * SECONDS_PER_NANO);
    #[cfg(not(unix))]
    Err(Error::invalid(
        "clock",
        "process CPU time",
        "not available on this platform",
    ))
}

/// One reading of a POSIX CPU clock, in nanoseconds.
#[cfg(unix)]
fn read_clock(clock: libc::clockid_t, name: &str) -> Result<u64> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec for the duration of the call.
    let rc = unsafe { libc::clock_gettime(clock, &mut ts) };
    if rc == 0 {
        return Ok(ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64);
    }
    Err(Error::invalid(
        "clock",
        name,
        std::io::Error::last_os_error().to_string(),
    ))
}

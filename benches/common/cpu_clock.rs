//! The thread CPU clock shared by the benches.

use std::time::Duration;

/// The calling thread's CPU time. The per-step benches report it instead
/// of the wall clock: on a shared machine the wall clock of a step
/// includes the waits for a core (a step of 0.1 ms measured 8 to 44 ms
/// about every 23 steps under a load average of 9, in whole scheduler
/// ticks of 4 ms), which made the HHT-α per element-integration row
/// bimodal (40 ns and 210 ns estimates).
pub fn thread_cpu_time() -> Duration {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid timespec for the call to fill.
    let status = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) };
    assert_eq!(status, 0, "the thread's CPU clock is readable");
    Duration::new(t.tv_sec as u64, t.tv_nsec as u32)
}

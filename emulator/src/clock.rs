//! Real time: the interpolation cycles of an emulator advance with the
//! wall clock, `factor` times faster than it.
//!
//! Without a clock an emulator is stepped: nothing moves until someone
//! sends `EXEC`, which makes every run deterministic. With a
//! [`RealTimeClock`] the owner of the emulator calls
//! [`RealTimeClock::catch_up`] whenever it is about to serve a request
//! (and, to keep a dashboard moving, now and then in between). The clock
//! counts the cycles due from one fixed start instant, never by adding up
//! sleeps, so it does not drift however irregular the calls are; each
//! catch-up runs at most one `EXEC` slice
//! ([`EXEC_SLICE_CYCLES`](tc_module::EXEC_SLICE_CYCLES) stepped cycles of
//! an active per-cycle model), so the work of one call stays bounded, and
//! cycles not run yet stay owed to the next call. The cycles each
//! catch-up ran are returned, so a recorder can write them as `EXEC n`
//! and a replay of the session is stepped and deterministic again.

use std::time::{Duration, Instant};

use tc_module::{CycleTime, ExecLeft, TcExtension};

use crate::Emulator;

/// Slowest real-time factor: a hundredth of the wall clock.
pub const MIN_FACTOR: f64 = 0.01;

/// Fastest real-time factor: ten thousand times the wall clock (at the
/// default 1 ms cycle, 10 million cycles a second, which a catch-up runs
/// in one slice as long as no per-cycle model is active).
pub const MAX_FACTOR: f64 = 10_000.0;

/// How much faster than the wall clock the executor runs: a finite number
/// in [`MIN_FACTOR`]`..=`[`MAX_FACTOR`]; 1 is real time.
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
pub struct RealTimeFactor(f64);

/// A real-time factor outside [`MIN_FACTOR`]`..=`[`MAX_FACTOR`].
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("real-time factor {0} must lie in {MIN_FACTOR}..={MAX_FACTOR}")]
pub struct FactorError(pub f64);

impl RealTimeFactor {
    /// Real time: one second of machine time per second.
    pub const ONE: RealTimeFactor = RealTimeFactor(1.0);

    /// The factor `f`, checked.
    pub fn new(f: f64) -> Result<Self, FactorError> {
        if (MIN_FACTOR..=MAX_FACTOR).contains(&f) {
            Ok(Self(f))
        } else {
            Err(FactorError(f))
        }
    }

    /// The factor as a number.
    pub fn get(self) -> f64 {
        self.0
    }
}

impl Default for RealTimeFactor {
    fn default() -> Self {
        Self::ONE
    }
}

/// The real-time clock of one emulator: which cycle the wall clock has
/// reached, and how many the emulator has run.
#[derive(Debug, Clone)]
pub struct RealTimeClock {
    /// The instant cycle 0 began.
    start: Instant,
    /// Machine seconds per wall-clock second.
    factor: f64,
    /// The interpolation cycle, in seconds.
    cycle_s: f64,
    /// Cycles the emulator has run since `start`.
    passed: u64,
}

impl RealTimeClock {
    /// A clock starting now, for an emulator with interpolation cycle
    /// `cycle`.
    pub fn new(factor: RealTimeFactor, cycle: CycleTime) -> Self {
        Self::starting_at(Instant::now(), factor, cycle)
    }

    /// A clock whose cycle 0 began at `start`.
    pub fn starting_at(start: Instant, factor: RealTimeFactor, cycle: CycleTime) -> Self {
        Self {
            start,
            factor: factor.get(),
            cycle_s: cycle.secs(),
            passed: 0,
        }
    }

    /// The real-time factor.
    pub fn factor(&self) -> f64 {
        self.factor
    }

    /// Cycles the emulator has run on this clock.
    pub fn passed(&self) -> u64 {
        self.passed
    }

    /// Cycles the wall clock has reached at `now`, counted from the start
    /// instant (whole cycles; never fewer at a later `now`).
    pub fn due(&self, now: Instant) -> u64 {
        let elapsed = now.saturating_duration_since(self.start).as_secs_f64();
        // A float-to-int cast saturates; the quotient is never negative.
        (elapsed * self.factor / self.cycle_s).floor() as u64
    }

    /// Cycles due at `now` that the emulator has not run yet.
    pub fn owed(&self, now: Instant) -> u64 {
        self.due(now).saturating_sub(self.passed)
    }

    /// The instant at which the wall clock reaches cycle `cycle` (a
    /// microsecond late rather than early, so that [`due`](Self::due)
    /// then counts it); `None` when that lies beyond what an [`Instant`]
    /// can hold.
    pub fn instant_of(&self, cycle: u64) -> Option<Instant> {
        let secs = cycle as f64 * self.cycle_s / self.factor;
        let after = Duration::try_from_secs_f64(secs).ok()?;
        self.start
            .checked_add(after)?
            .checked_add(Duration::from_micros(1))
    }

    /// Runs on `emu` the cycles owed at `now`, at most one `EXEC` slice of
    /// them; returns how many cycles ran (the rest stays owed).
    pub fn catch_up<E: TcExtension>(&mut self, emu: &mut Emulator<E>, now: Instant) -> u64 {
        let owed = self.owed(now);
        if owed == 0 {
            return 0;
        }
        let ran = match emu.exec_slice(Some(owed)) {
            ExecLeft::Done => owed,
            ExecLeft::Rest(rest) => owed - rest.unwrap_or(0).min(owed),
        };
        self.passed += ran;
        ran
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tc_request::text::parse_request;

    fn ms(n: u64) -> Duration {
        Duration::from_millis(n)
    }

    #[test]
    fn factors_out_of_range_are_refused() {
        for bad in [0.0, -1.0, 0.001, 10_000.5, f64::NAN, f64::INFINITY] {
            assert!(RealTimeFactor::new(bad).is_err(), "{bad}");
        }
        for good in [MIN_FACTOR, 1.0, 10.0, MAX_FACTOR] {
            assert_eq!(RealTimeFactor::new(good).map(RealTimeFactor::get), Ok(good));
        }
    }

    #[test]
    fn cycles_due_follow_the_wall_clock_times_the_factor() {
        let t0 = Instant::now();
        let one = RealTimeClock::starting_at(t0, RealTimeFactor::ONE, CycleTime::DEFAULT);
        assert_eq!(one.due(t0), 0);
        assert_eq!(one.due(t0 + ms(1500)), 1500);
        let ten = RealTimeFactor::new(10.0).unwrap();
        let fast = RealTimeClock::starting_at(t0, ten, CycleTime::DEFAULT);
        assert_eq!(fast.due(t0 + ms(1500)), 15_000);
        let at = fast.instant_of(15_000).unwrap();
        assert_eq!(fast.due(at), 15_000);
        assert!(at > t0 + ms(1499) && at < t0 + ms(1501));
        let slow = RealTimeFactor::new(MIN_FACTOR).unwrap();
        let one_s = CycleTime::from_secs(1.0).unwrap();
        let slow = RealTimeClock::starting_at(t0, slow, one_s);
        assert_eq!(slow.instant_of(u64::MAX), None);
    }

    #[test]
    fn catching_up_at_irregular_instants_never_drifts() {
        let t0 = Instant::now();
        let mut emu = Emulator::default();
        let lin = parse_request("LIN X100 F6000").unwrap();
        emu.run(&lin);
        let mut clock = RealTimeClock::starting_at(t0, RealTimeFactor::ONE, CycleTime::DEFAULT);
        let mut ran = 0;
        for at in [3, 253, 254, 331, 731, 1000] {
            let now = t0 + ms(at);
            ran += clock.catch_up(&mut emu, now);
            assert_eq!(ran, at);
            assert_eq!(clock.owed(now), 0);
        }
        // 1000 cycles of 1 ms at F6000 (100 mm/s): the 100 mm line ends.
        assert_eq!(ran, 1000);
        assert_eq!(emu.queue_len(), 0);
        assert!((emu.position()[0] - 100.0).abs() < 1e-9);
        assert_eq!(clock.catch_up(&mut emu, t0 + ms(1000)), 0);
    }
}

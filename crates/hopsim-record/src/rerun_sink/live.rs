//! Live streams: the pace at which frames are sent to a viewer.

use std::str::FromStr;
use std::time::{Duration, Instant};

/// Longest wall-clock time the columns of a live stream are held back.
pub(super) const LIVE_FLUSH_INTERVAL: Duration = Duration::from_millis(50);

/// How fast a live stream ([`RerunRecorder::spawn`]) plays the run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pace {
    /// `factor` simulated seconds per wall-clock second (1: real time).
    Speed(f64),
    /// As fast as the simulation runs.
    Unpaced,
}

impl Default for Pace {
    fn default() -> Self {
        Pace::Speed(1.0)
    }
}

/// `max` or a positive factor, e.g. `0.25` (four times slower than real time).
impl FromStr for Pace {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s.trim() == "max" {
            return Ok(Pace::Unpaced);
        }
        match s.trim().parse::<f64>() {
            Ok(f) if f.is_finite() && f > 0.0 => Ok(Pace::Speed(f)),
            _ => Err(format!(
                "`{s}` is not a speed: give a positive factor of real time (1 = real time, \
                 0.5 = half speed) or `max` (as fast as possible)"
            )),
        }
    }
}

/// A live stream's clock.
pub(super) struct Live {
    pub(super) pace: Pace,
    /// Wall-clock instant and simulation time of the first frame.
    pub(super) start: Option<(Instant, f64)>,
    pub(super) last_flush: Instant,
}

impl Live {
    /// Sleeps until the wall clock reaches simulation time `t` at the pace.
    pub(super) fn wait_for(&mut self, t: f64) {
        let Pace::Speed(speed) = self.pace else {
            return;
        };
        let now = Instant::now();
        let (start, t0) = *self.start.get_or_insert((now, t));
        let ahead = (t - t0) / speed;
        if let Ok(ahead) = Duration::try_from_secs_f64(ahead) {
            if let Some(wait) = (start + ahead).checked_duration_since(now) {
                std::thread::sleep(wait);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speeds_are_positive_factors_or_max() {
        assert_eq!("max".parse::<Pace>(), Ok(Pace::Unpaced));
        assert_eq!("0.5".parse::<Pace>(), Ok(Pace::Speed(0.5)));
        assert_eq!(Pace::default(), Pace::Speed(1.0));
        for bad in ["0", "-1", "inf", "NaN", "fast"] {
            let e = bad.parse::<Pace>().unwrap_err();
            assert!(e.contains("positive factor") && e.contains("max"), "{e}");
        }
    }

    /// A live stream at speed 4 takes a quarter of the simulated time, however fast the
    /// frames come; unpaced it does not wait.
    #[test]
    fn a_paced_stream_waits_for_the_wall_clock() {
        let mut live = Live {
            pace: Pace::Speed(4.0),
            start: None,
            last_flush: Instant::now(),
        };
        let started = Instant::now();
        for k in 0..=20 {
            live.wait_for(1.0 + 0.01 * k as f64);
        }
        let elapsed = started.elapsed().as_secs_f64();
        // 0.2 s simulated at speed 4: 0.05 s, plus sleeping overshoot (a few ms).
        assert!((0.05..0.2).contains(&elapsed), "{elapsed} s");
        live.pace = Pace::Unpaced;
        let started = Instant::now();
        live.wait_for(1e6);
        assert!(started.elapsed() < Duration::from_millis(10));
    }
}

//! The bounds the scene reader holds `[initial]` to; the checks of a start state are
//! hopsim-sim's (`check_state`, `check_start`), shared with every front end.

use crate::reader::Num;

/// The bound of each generalised coordinate of a state, m or rad (`[initial] q`).
pub(crate) const COORDINATE: Num = Num::any("m or rad").coordinate();

/// The bound of each generalised velocity of a state (`[initial] u`): a start faster than
/// `simulation.max_speed` would stop the run as a runaway at once.
pub(crate) const fn velocity(max_speed: f64) -> Num {
    Num::any("m/s or rad/s").at_most(max_speed)
}

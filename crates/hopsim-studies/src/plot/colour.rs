//! Colours: the qualitative palette of series, and the colour scales of maps (viridis for
//! a quantity, a blue–white–red scale centred on a meaningful value such as `|λ| = 1`).

pub use plotters::style::RGBColor;

/// Black, for reference lines.
pub const BLACK: RGBColor = RGBColor(0, 0, 0);

/// Qualitative palette (Tableau 10).
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Piecewise-linear interpolation through `stops` at `t ∈ [0, 1]` (NaN: the first stop).
fn interpolate(stops: &[(u8, u8, u8)], t: f64) -> RGBColor {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let pos = t * (stops.len() - 1) as f64;
    let i = (pos.floor() as usize).min(stops.len() - 2);
    let f = pos - i as f64;
    let lerp = |a: u8, b: u8| (a as f64 + (b as f64 - a as f64) * f).round() as u8;
    let (a, b) = (stops[i], stops[i + 1]);
    RGBColor(lerp(a.0, b.0), lerp(a.1, b.1), lerp(a.2, b.2))
}

/// Viridis colour map at `t ∈ [0, 1]` (piecewise-linear through 9 samples).
pub fn viridis(t: f64) -> RGBColor {
    const STOPS: [(u8, u8, u8); 9] = [
        (68, 1, 84),
        (71, 44, 122),
        (59, 81, 139),
        (44, 113, 142),
        (33, 144, 141),
        (39, 173, 129),
        (92, 200, 99),
        (170, 220, 50),
        (253, 231, 37),
    ];
    interpolate(&STOPS, t)
}

/// A diverging blue–white–red map at `t ∈ [0, 1]`, white at `t = 1/2` (ColorBrewer's RdBu,
/// reversed: blue low, red high).
pub fn blue_white_red(t: f64) -> RGBColor {
    const STOPS: [(u8, u8, u8); 9] = [
        (33, 102, 172),
        (67, 147, 195),
        (146, 197, 222),
        (209, 229, 240),
        (247, 247, 247),
        (253, 219, 199),
        (244, 165, 130),
        (214, 96, 77),
        (178, 24, 43),
    ];
    interpolate(&STOPS, t)
}

/// `color` drawn with opacity `alpha` on white.
pub fn on_white(color: RGBColor, alpha: f64) -> RGBColor {
    let mix = |c: u8| (255.0 - alpha * (255.0 - c as f64)).round() as u8;
    RGBColor(mix(color.0), mix(color.1), mix(color.2))
}

/// How a map turns values into colours.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum ColourScale {
    /// Viridis from the low to the high end of the range.
    #[default]
    Sequential,
    /// Blue below `centre`, white at it, red above; each side spans its own part of the
    /// range (so `centre` is white whatever the range).
    Diverging { centre: f64 },
}

impl ColourScale {
    /// The colour of `value` on the range `lo … hi` (values beyond it take the end colours).
    pub fn colour(self, value: f64, (lo, hi): (f64, f64)) -> RGBColor {
        let fraction = |a: f64, b: f64| match b > a {
            true => (value - a) / (b - a),
            false => 0.5,
        };
        match self {
            ColourScale::Sequential => viridis(fraction(lo, hi)),
            ColourScale::Diverging { centre } if value < centre => {
                blue_white_red(0.5 * fraction(lo, centre))
            }
            ColourScale::Diverging { centre } => {
                blue_white_red(0.5 + 0.5 * fraction(centre, hi).max(0.0))
            }
        }
    }

    /// The range a map of values in `lo … hi` shows: a diverging scale always reaches its
    /// centre.
    pub fn range(self, (lo, hi): (f64, f64)) -> (f64, f64) {
        match self {
            ColourScale::Sequential => (lo, hi),
            ColourScale::Diverging { centre } => (lo.min(centre), hi.max(centre)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(f64::NAN), RGBColor(68, 1, 84));
    }

    /// A diverging scale is white at its centre and blue or red at the ends of the range,
    /// however lopsided the range is about the centre.
    #[test]
    fn a_diverging_scale_is_white_at_its_centre() {
        let scale = ColourScale::Diverging { centre: 1.0 };
        let range = scale.range((0.4, 5.0));
        assert_eq!(range, (0.4, 5.0));
        assert_eq!(scale.colour(1.0, range), RGBColor(247, 247, 247));
        assert_eq!(scale.colour(0.4, range), RGBColor(33, 102, 172));
        assert_eq!(scale.colour(5.0, range), RGBColor(178, 24, 43));
        assert_eq!(scale.colour(9.0, range), RGBColor(178, 24, 43));
        // Halfway between the low end and the centre is halfway into the blue side.
        assert_eq!(scale.colour(0.7, range), blue_white_red(0.25));
        // A range entirely below the centre still reaches it.
        assert_eq!(scale.range((0.2, 0.8)), (0.2, 1.0));
        assert_eq!(on_white(BLACK, 0.5), RGBColor(128, 128, 128));
    }
}

//! The environment: straight terrain pieces and the convex corners between them.

use crate::Vec2;

/// One piece of terrain a shape can touch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TerrainFeature {
    /// The straight piece `origin + s t`, `s ∈ [from, to]` (either may be infinite), with
    /// unit outward normal `normal` and tangent `t = (n_y, -n_x)` (docs/physics.md §1, §2).
    Line {
        origin: Vec2,
        normal: Vec2,
        from: f64,
        to: f64,
    },
    /// A convex corner (a contact point such as a step's edge, §5.2) whose outward normals
    /// span the cone from `normal_first` counter-clockwise to `normal_last`.
    Corner {
        point: Vec2,
        normal_first: Vec2,
        normal_last: Vec2,
    },
}

impl TerrainFeature {
    /// The unit tangent of a line feature, `t = (n_y, -n_x)`.
    pub fn tangent(normal: Vec2) -> Vec2 {
        Vec2::new(normal.y, -normal.x)
    }
}

/// The terrain of a scene as a list of features.
#[derive(Clone, Debug, PartialEq)]
pub struct Terrain {
    pub features: Vec<TerrainFeature>,
}

impl Terrain {
    /// Flat ground `y = height`.
    pub fn flat(height: f64) -> Self {
        Self {
            features: vec![TerrainFeature::Line {
                origin: Vec2::new(0.0, height),
                normal: Vec2::new(0.0, 1.0),
                from: f64::NEG_INFINITY,
                to: f64::INFINITY,
            }],
        }
    }

    /// A plane through the origin rising at `angle` rad (positive: uphill towards +x).
    pub fn incline(angle: f64) -> Self {
        let (s, c) = angle.sin_cos();
        Self {
            features: vec![TerrainFeature::Line {
                origin: Vec2::zeros(),
                normal: Vec2::new(-s, c),
                from: f64::NEG_INFINITY,
                to: f64::INFINITY,
            }],
        }
    }

    /// Flat ground at `y = 0` with a step up of `height` m whose face is at `x = face_x`;
    /// the step's top edge `(face_x, height)` is a corner contact (docs/physics.md §5.2).
    /// At the face's foot, a concave corner, the ground and the face both reach under the
    /// step: a point pushed into that corner is held by both lines (the ground below it, the
    /// face before it), never let through between them. The parts of a line under the step
    /// are not drawn ([`Terrain::hides`]).
    pub fn step(face_x: f64, height: f64) -> Self {
        let up = Vec2::new(0.0, 1.0);
        let left = Vec2::new(-1.0, 0.0);
        Self {
            features: vec![
                TerrainFeature::Line {
                    origin: Vec2::new(face_x, 0.0),
                    normal: up,
                    from: f64::NEG_INFINITY,
                    to: f64::INFINITY,
                },
                TerrainFeature::Line {
                    origin: Vec2::new(face_x, 0.0),
                    normal: left,
                    from: f64::NEG_INFINITY,
                    to: height,
                },
                TerrainFeature::Line {
                    origin: Vec2::new(face_x, height),
                    normal: up,
                    from: 0.0,
                    to: f64::INFINITY,
                },
                TerrainFeature::Corner {
                    point: Vec2::new(face_x, height),
                    normal_first: up,
                    normal_last: left,
                },
            ],
        }
    }

    /// Whether point `p` lies strictly inside the terrain behind a line feature other than
    /// `except` (strictly within that line's extent): a piece of line there is under the surface,
    /// not part of it (for drawing).
    pub fn hides(&self, p: Vec2, except: usize) -> bool {
        self.features.iter().enumerate().any(|(i, f)| match f {
            TerrainFeature::Line {
                origin,
                normal,
                from,
                to,
            } if i != except => {
                let rel = p - origin;
                let s = rel.dot(&TerrainFeature::tangent(*normal));
                let eps = 1e-9 * (1.0 + p.norm());
                s > from + eps && s < to - eps && rel.dot(normal) < -eps
            }
            _ => false,
        })
    }

    /// The terrain height below `x` (the highest line feature covering `x`), used for
    /// drawing and for checking initial states; `None` where no line covers `x`.
    pub fn height_at(&self, x: f64) -> Option<f64> {
        self.features
            .iter()
            .filter_map(|f| match f {
                TerrainFeature::Line {
                    origin,
                    normal,
                    from,
                    to,
                } if normal.y > 1e-9 => {
                    // Point on the line with abscissa x: origin + s t, t = (n_y, -n_x).
                    let s = (x - origin.x) / normal.y;
                    (s >= *from && s <= *to).then(|| origin.y - s * normal.x)
                }
                _ => None,
            })
            .reduce(f64::max)
    }
}

//! Mass and inertia from geoms, as MuJoCo's compiler computes them (`mjCGeom::GetVolume`,
//! `SetInertia`, `mjCBody::InertiaFromGeom`), reduced to the plane: each body's mass, centre
//! of mass and moment of inertia about the plane's normal through that centre.

use std::f64::consts::PI;

use nalgebra::{UnitQuaternion, Vector3};

use crate::orient::EPS;
use crate::read::{Body3, Geom3, GeomType};

type V3 = Vector3<f64>;

/// The solid's volume (planes: 0).
pub(crate) fn volume(kind: GeomType, s: [f64; 3]) -> f64 {
    match kind {
        GeomType::Sphere => 4.0 * PI * s[0] * s[0] * s[0] / 3.0,
        GeomType::Capsule => PI * (s[0] * s[0] * 2.0 * s[1] + 4.0 * s[0] * s[0] * s[0] / 3.0),
        GeomType::Cylinder => PI * s[0] * s[0] * 2.0 * s[1],
        GeomType::Ellipsoid => 4.0 * PI * s[0] * s[1] * s[2] / 3.0,
        GeomType::Box => 8.0 * s[0] * s[1] * s[2],
        GeomType::Plane => 0.0,
    }
}

/// Principal moments of inertia of the solid of mass `m`, in its own frame.
pub(crate) fn principal_inertia(kind: GeomType, s: [f64; 3], m: f64) -> V3 {
    match kind {
        GeomType::Sphere => V3::repeat(2.0 * m * s[0] * s[0] / 5.0),
        GeomType::Capsule => {
            // A cylinder and two hemispheres; MuJoCo's expression for the hemispheres'
            // offset, to agree with it exactly.
            let (r, h) = (s[0], 2.0 * s[1]);
            let sphere = m * 4.0 * r / (4.0 * r + 3.0 * h);
            let cylinder = m - sphere;
            let across = cylinder * (3.0 * r * r + h * h) / 12.0
                + 2.0 * sphere * r * r / 5.0
                + sphere * h * (3.0 * r + 2.0 * h) / 8.0;
            V3::new(
                across,
                across,
                cylinder * r * r / 2.0 + 2.0 * sphere * r * r / 5.0,
            )
        }
        GeomType::Cylinder => {
            let (r, h) = (s[0], 2.0 * s[1]);
            let across = m * (3.0 * r * r + h * h) / 12.0;
            V3::new(across, across, m * r * r / 2.0)
        }
        GeomType::Ellipsoid => three_axes(m, s, 5.0),
        GeomType::Box => three_axes(m, s, 3.0),
        GeomType::Plane => V3::zeros(),
    }
}

/// `m (b² + c²) / k` and its turns: an ellipsoid's (`k` = 5) or a box's (`k` = 3) principal
/// inertias for semi-axes or half-sizes `s`.
fn three_axes(m: f64, s: [f64; 3], k: f64) -> V3 {
    let q = s.map(|x| x * x);
    V3::new(
        m * (q[1] + q[2]) / k,
        m * (q[0] + q[2]) / k,
        m * (q[0] + q[1]) / k,
    )
}

/// The geom's mass from `mass` or else `density`, and its inertia, as MuJoCo's compiler
/// sets them (a given mass on a solid of no volume counts as 0, as there).
pub(crate) fn set_geom_mass(g: &mut Geom3, mass: Option<f64>, density: f64) {
    let vol = volume(g.kind, g.size);
    g.mass = match mass {
        Some(m) if m > 0.0 && vol > EPS => m,
        Some(_) => 0.0,
        None => density * vol,
    };
    g.inertia = principal_inertia(g.kind, g.size, g.mass);
}

/// The moment of inertia `nᵀ R diag(d) Rᵀ n` about the unit axis `n` (in the frame that `R`
/// turns `d`'s principal frame into).
fn about(n: &V3, q: &UnitQuaternion<f64>, d: &V3) -> f64 {
    let local = q.inverse_transform_vector(n);
    d.x * local.x * local.x + d.y * local.y * local.y + d.z * local.z * local.z
}

/// One MJCF body's own mass properties in its frame: mass, centre of mass (3-D), and
/// moment of inertia about the axis `n` (unit, body frame) through that centre.
#[derive(Debug, Clone, Copy)]
pub(crate) struct MassProps {
    pub mass: f64,
    pub com: V3,
    pub inertia: f64,
}

/// The body's mass properties: from `<inertial>` unless `inertiafromgeom` is true (or
/// "auto" and there is none), else from its geoms (one geom: its own; several: summed
/// with the parallel-axis theorem about their common centre). Errors as MuJoCo's
/// ("body mass is too small") come back as `Err` with the message.
pub(crate) fn body_mass(
    body: &Body3,
    from_geom: Option<bool>,
    n: &V3,
) -> Result<MassProps, String> {
    let use_geoms = match (from_geom, &body.inertial) {
        (Some(true), _) | (None, None) => true,
        (Some(false), _) | (None, Some(_)) => false,
    };
    if !use_geoms {
        return Ok(match &body.inertial {
            Some(i) => MassProps {
                mass: i.mass,
                com: i.pos,
                inertia: match i.full {
                    Some(f) => {
                        let m = nalgebra::Matrix3::new(
                            f[0], f[3], f[4], f[3], f[1], f[5], f[4], f[5], f[2],
                        );
                        n.dot(&(m * n))
                    }
                    None => about(n, &i.quat, &i.diag),
                },
            },
            None => MassProps {
                mass: 0.0,
                com: V3::zeros(),
                inertia: 0.0,
            },
        });
    }
    let geoms: Vec<&Geom3> = body.geoms.iter().filter(|g| g.counted).collect();
    match geoms.as_slice() {
        [] => Ok(MassProps {
            mass: 0.0,
            com: V3::zeros(),
            inertia: 0.0,
        }),
        [g] => Ok(MassProps {
            mass: g.mass,
            com: g.pos,
            inertia: about(n, &g.quat, &g.inertia),
        }),
        many => {
            let mass: f64 = many.iter().map(|g| g.mass).sum();
            if mass < EPS {
                return Err("the body's mass is too small to place its centre of mass (MuJoCo refuses it too)".into());
            }
            let com = many.iter().map(|g| g.pos * g.mass).sum::<V3>() / mass;
            let inertia = many
                .iter()
                .map(|g| {
                    let d = g.pos - com;
                    about(n, &g.quat, &g.inertia) + g.mass * (d.norm_squared() - d.dot(n).powi(2))
                })
                .sum();
            Ok(MassProps { mass, com, inertia })
        }
    }
}

//! Orientations as MuJoCo writes them (`quat`, `axisangle`, `xyaxes`, `zaxis`, `euler` with
//! the compiler's `angle` unit and `eulerseq`), turned into quaternions the way MuJoCo's
//! compiler does (`ResolveOrientation`, `mjuu_z2quat`).

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use crate::attrs::View;
use crate::error::Result;

/// Smallest norm of an axis or vector that MuJoCo accepts (`mjEPS`).
pub(crate) const EPS: f64 = 1e-14;

/// The compiler settings that orientations depend on.
#[derive(Debug, Clone)]
pub(crate) struct Angles {
    /// Angles in degrees (MuJoCo's default) rather than radians.
    pub degree: bool,
    /// Three of x, y, z (rotating axes) or X, Y, Z (fixed axes).
    pub eulerseq: [u8; 3],
}

impl Angles {
    pub fn to_radians(&self, angle: f64) -> f64 {
        if self.degree {
            angle / 180.0 * std::f64::consts::PI
        } else {
            angle
        }
    }
}

/// The orientation attributes a frame can have; at most one may be given.
pub(crate) const ORIENTATION: [&str; 5] = ["quat", "axisangle", "xyaxes", "zaxis", "euler"];

/// The frame's orientation from whichever of [`ORIENTATION`] it gives (identity if none).
pub(crate) fn orientation(v: &View, angles: &Angles) -> Result<UnitQuaternion<f64>> {
    let mut given = ORIENTATION
        .into_iter()
        .filter_map(|n| v.get(n).map(|a| (n, a)));
    let Some((name, a)) = given.next() else {
        return Ok(UnitQuaternion::identity());
    };
    if let Some((second, b)) = given.next() {
        return Err(v.error_at(
            b,
            format!("an orientation is given twice (`{name}` and `{second}`)"),
        ));
    }
    let too_small = |what: &str| v.error_at(a, format!("{what} too small"));
    Ok(match name {
        "quat" => {
            let [w, x, y, z] = v.values::<4>(a)?;
            let q = Quaternion::new(w, x, y, z);
            if q.norm() < EPS {
                return Err(too_small("quaternion"));
            }
            UnitQuaternion::from_quaternion(q)
        }
        "axisangle" => {
            let [x, y, z, angle] = v.values::<4>(a)?;
            let axis = Vector3::new(x, y, z);
            if axis.norm() < EPS {
                return Err(too_small("axis"));
            }
            let axis = axis / axis.norm();
            let half = angles.to_radians(angle) / 2.0;
            unit(Quaternion::new(
                half.cos(),
                half.sin() * axis.x,
                half.sin() * axis.y,
                half.sin() * axis.z,
            ))
        }
        "xyaxes" => {
            let [x0, x1, x2, y0, y1, y2] = v.values::<6>(a)?;
            let x = Vector3::new(x0, x1, x2);
            if x.norm() < EPS {
                return Err(too_small("x axis"));
            }
            let x = x / x.norm();
            let y = Vector3::new(y0, y1, y2);
            let y = y - x * x.dot(&y);
            if y.norm() < EPS {
                return Err(too_small("y axis (once made orthogonal to the x axis)"));
            }
            let y = y / y.norm();
            let z = x.cross(&y);
            let m = nalgebra::Matrix3::from_columns(&[x, y, z / z.norm()]);
            UnitQuaternion::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(m))
        }
        "zaxis" => {
            let [x, y, z] = v.values::<3>(a)?;
            let axis = Vector3::new(x, y, z);
            if axis.norm() < EPS {
                return Err(too_small("z axis"));
            }
            z_to(&(axis / axis.norm()))
        }
        _ => {
            let e = v.values::<3>(a)?;
            let mut q = Quaternion::identity();
            for (angle, &axis) in e.iter().zip(&angles.eulerseq) {
                let half = angles.to_radians(*angle) / 2.0;
                let (s, c) = half.sin_cos();
                let r = match axis.to_ascii_lowercase() {
                    b'x' => Quaternion::new(c, s, 0.0, 0.0),
                    b'y' => Quaternion::new(c, 0.0, s, 0.0),
                    _ => Quaternion::new(c, 0.0, 0.0, s),
                };
                // Rotating axes multiply on the right, fixed axes on the left.
                q = if axis.is_ascii_lowercase() {
                    q * r
                } else {
                    r * q
                };
            }
            unit(q)
        }
    })
}

fn unit(q: Quaternion<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(q)
}

/// The smallest rotation taking `+z` to the unit vector `v` (MuJoCo's `mjuu_z2quat`; a
/// half turn about `x` for `−z`).
pub(crate) fn z_to(v: &Vector3<f64>) -> UnitQuaternion<f64> {
    let cross = Vector3::z().cross(v);
    let s = cross.norm();
    let axis = if s < 1e-10 { Vector3::x() } else { cross / s };
    let angle = s.atan2(v.z);
    let (sin, cos) = (angle / 2.0).sin_cos();
    unit(Quaternion::new(
        cos,
        sin * axis.x,
        sin * axis.y,
        sin * axis.z,
    ))
}

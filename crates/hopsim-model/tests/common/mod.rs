//! Helpers shared by the model's geometry tests.
#![allow(dead_code)]

use hopsim_model::{Shape, Vec2};
use proptest::prelude::*;

pub fn capsule(from: Vec2, to: Vec2, radius: f64) -> Shape {
    Shape::Capsule { from, to, radius }
}

pub fn end_points() -> impl Strategy<Value = (Vec2, Vec2, f64)> {
    (
        -0.2..0.2f64,
        -0.2..0.2f64,
        0.02..0.3f64,
        -4.0..4.0f64,
        0.01..0.15f64,
    )
        .prop_map(|(cx, cy, half, angle, radius)| {
            let d = half * Vec2::new(angle.cos(), angle.sin());
            let c = Vec2::new(cx, cy);
            (c - d, c + d, radius)
        })
}

//! The raw material of a generated mechanism: numbers in fixed ranges, drawn and shrunk by
//! proptest. [`crate::Mechanism::from_genes`] reads them into a valid scene, so every
//! combination of genes is a mechanism, and shrinking a failing case (fewer bodies,
//! shapes and springs; numbers towards the low end of their range; options towards
//! `None`) keeps it one.

use proptest::collection::vec;
use proptest::option;
use proptest::prelude::*;

/// The most bodies of a generated mechanism.
pub const MAX_GENERATED_BODIES: usize = 8;

/// One body: where it hangs, its joint, its inertia, its stops, spring, damper and start.
/// Every field is a unit number (`[0, 1)`) unless said otherwise.
#[derive(Clone, Debug)]
pub struct BodyGene {
    /// Below 0.7: a child of an earlier body (which one: this value scaled); above: the
    /// base of a new tree (the first body always is one).
    pub attach: f64,
    /// A new tree's base: floating below 0.6, pinned below 0.85, fixed above.
    pub base: f64,
    /// A child's joint: prismatic instead of revolute.
    pub prismatic: bool,
    /// A revolute child's coordinate is its absolute angle (only without stops).
    pub absolute: bool,
    /// Mass, log-uniform 0.01 … 10 kg.
    pub mass: f64,
    /// Size `L`, 0.05 … 0.5 m; the inertia is `m L² / 12` times 0.5 … 2 (`inertia`).
    pub size: f64,
    pub inertia: f64,
    /// Joint pivot in the parent's frame and the centre of mass from the joint, in units of
    /// the parent's and the body's size; components in `[-1, 1]`.
    pub pivot: (f64, f64),
    pub com: (f64, f64),
    /// A prismatic joint's axis angle, in turns.
    pub axis: f64,
    /// Stops: the lower and upper bound's distances from zero.
    pub limits: Option<(f64, f64)>,
    /// Stop restitution.
    pub limit_restitution: f64,
    /// Joint spring: stiffness (log-uniform) and rest position.
    pub spring: Option<(f64, f64)>,
    /// Joint damper (log-uniform).
    pub damping: Option<f64>,
    /// Dry friction in the joint (log-uniform, about the body's weight).
    pub dry_friction: Option<f64>,
    /// Start: the coordinate's place in its range, and its rate in `[-1, 1]`.
    pub start: f64,
    pub rate: f64,
    /// A base's start: `x`, `y` (or a pinned base's pivot, a fixed base's position) and angle.
    pub place: (f64, f64, f64),
}

/// One shape on a body.
#[derive(Clone, Debug)]
pub struct ShapeGene {
    /// Which body (scaled to the body count).
    pub body: f64,
    /// circle, arc, ellipse, point, polygon, box, capsule (scaled to seven kinds).
    pub kind: f64,
    /// Six unit numbers for the geometry (see `Mechanism::from_genes`).
    pub p: [f64; 6],
    /// Its own friction, normal and tangential restitution.
    pub material: Option<(f64, f64, f64)>,
    /// A switchable point (a cane) when the controller is a pulse.
    pub cane: bool,
}

/// A spring between two bodies.
#[derive(Clone, Debug)]
pub struct SpringGene {
    pub bodies: (f64, f64),
    pub points: (f64, f64, f64, f64),
    pub stiffness: f64,
    pub rest: f64,
    pub damping: Option<f64>,
    pub tension_only: bool,
}

/// An explicit contact pair (`[[contact_pairs]]`): two shapes (scaled to the shape
/// count), their own friction `μ` in `[0, 2]` and restitutions when given. Pairs of the
/// same body, of two fixed bodies, with a switchable shape or without exact geometry are
/// left out; pairs of joined bodies are kept (only explicit pairs make those).
#[derive(Clone, Debug)]
pub struct PairGene {
    pub shapes: (f64, f64),
    pub material: Option<(f64, f64, f64)>,
}

/// The world, the controller and the settings.
#[derive(Clone, Debug)]
pub struct WorldGene {
    /// flat, incline or step (scaled to three kinds), and their two numbers.
    pub terrain: (f64, f64, f64),
    /// Friction `μ` in `[0, 2]`, restitution `ε_N`, and `ε_T` in `[-1, 1]` when given.
    pub friction: f64,
    pub restitution: f64,
    pub tangential: Option<f64>,
    /// Contacts between bodies: `all = true` with this friction and restitution.
    pub body_contacts: Option<(f64, f64)>,
    /// Collision groups of the shapes, when body contacts are on.
    pub groups: bool,
    /// passive, pulse or momentum impulse (scaled to three kinds), and four numbers.
    pub controller: (f64, [f64; 4]),
    /// The cane's mode: retracted, extended, timed (scaled), and its timing.
    pub cane: (f64, f64, f64),
    /// `Δt`, log-uniform 1e-4 … 1e-3 s.
    pub dt: f64,
    pub warm_start: bool,
    pub strict: bool,
    /// Rest the first tree on the terrain (when it is floating).
    pub rest_on_ground: bool,
}

/// All genes of one mechanism.
#[derive(Clone, Debug)]
pub struct Genes {
    pub world: WorldGene,
    pub bodies: Vec<BodyGene>,
    pub shapes: Vec<ShapeGene>,
    pub springs: Vec<SpringGene>,
    pub pairs: Vec<PairGene>,
}

fn unit() -> impl Strategy<Value = f64> {
    0.0..1.0f64
}

fn signed() -> impl Strategy<Value = f64> {
    -1.0..1.0f64
}

fn body_gene() -> impl Strategy<Value = BodyGene> {
    (
        (unit(), unit(), any::<bool>(), any::<bool>()),
        (unit(), unit(), unit()),
        ((signed(), signed()), (signed(), signed()), unit()),
        (
            option::weighted(0.3, (unit(), unit())),
            unit(),
            option::weighted(0.3, (unit(), unit())),
            option::weighted(0.3, unit()),
            option::weighted(0.3, unit()),
        ),
        (unit(), signed(), (unit(), unit(), unit())),
    )
        .prop_map(
            |(
                (attach, base, prismatic, absolute),
                (mass, size, inertia),
                (pivot, com, axis),
                (limits, limit_restitution, spring, damping, dry_friction),
                (start, rate, place),
            )| BodyGene {
                attach,
                base,
                prismatic,
                absolute,
                mass,
                size,
                inertia,
                pivot,
                com,
                axis,
                limits,
                limit_restitution,
                spring,
                damping,
                dry_friction,
                start,
                rate,
                place,
            },
        )
}

fn shape_gene() -> impl Strategy<Value = ShapeGene> {
    (
        unit(),
        unit(),
        [unit(), unit(), unit(), unit(), unit(), unit()],
        option::weighted(0.3, (unit(), unit(), signed())),
        proptest::bool::weighted(0.15),
    )
        .prop_map(|(body, kind, p, material, cane)| ShapeGene {
            body,
            kind,
            p,
            material,
            cane,
        })
}

fn spring_gene() -> impl Strategy<Value = SpringGene> {
    (
        (unit(), unit()),
        (signed(), signed(), signed(), signed()),
        (unit(), unit(), option::weighted(0.4, unit()), any::<bool>()),
    )
        .prop_map(
            |(bodies, points, (stiffness, rest, damping, tension_only))| SpringGene {
                bodies,
                points,
                stiffness,
                rest,
                damping,
                tension_only,
            },
        )
}

fn world_gene() -> impl Strategy<Value = WorldGene> {
    (
        (
            (unit(), signed(), unit()),
            unit(),
            unit(),
            option::weighted(0.5, signed()),
        ),
        (option::weighted(0.4, (unit(), unit())), any::<bool>()),
        (
            (unit(), [unit(), unit(), unit(), unit()]),
            (unit(), unit(), unit()),
        ),
        (
            unit(),
            proptest::bool::weighted(0.8),
            proptest::bool::weighted(0.1),
            any::<bool>(),
        ),
    )
        .prop_map(
            |(
                (terrain, friction, restitution, tangential),
                (body_contacts, groups),
                (controller, cane),
                (dt, warm_start, strict, rest_on_ground),
            )| WorldGene {
                terrain,
                friction,
                restitution,
                tangential,
                body_contacts,
                groups,
                controller,
                cane,
                dt,
                warm_start,
                strict,
                rest_on_ground,
            },
        )
}

fn pair_gene() -> impl Strategy<Value = PairGene> {
    (
        (unit(), unit()),
        option::weighted(0.7, (unit(), unit(), signed())),
    )
        .prop_map(|(shapes, material)| PairGene { shapes, material })
}

/// Genes of mechanisms with 1 … [`MAX_GENERATED_BODIES`] bodies, up to ten shapes, three
/// springs and three explicit contact pairs.
pub fn genes() -> impl Strategy<Value = Genes> {
    (
        world_gene(),
        vec(body_gene(), 1..=MAX_GENERATED_BODIES),
        vec(shape_gene(), 1..=10),
        vec(spring_gene(), 0..=3),
        vec(pair_gene(), 0..=3),
    )
        .prop_map(|(world, bodies, shapes, springs, pairs)| Genes {
            world,
            bodies,
            shapes,
            springs,
            pairs,
        })
}

//! A generated mechanism: the genes of [`crate::genes`] read into the pieces of a scene
//! (docs/scene-format.md), written out as TOML so that it passes the same validation as
//! any scene file.

use crate::genes::{BodyGene, Genes, ShapeGene};
use std::f64::consts::{PI, TAU};
use std::fmt::Write;

/// How a body hangs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mount {
    Floating,
    Pinned,
    Fixed,
    Revolute { parent: usize, absolute: bool },
    Prismatic { parent: usize },
}

impl Mount {
    /// Generalised coordinates the body adds.
    pub fn coordinates(self) -> usize {
        match self {
            Mount::Floating => 3,
            Mount::Fixed => 0,
            _ => 1,
        }
    }

    fn parent(self) -> Option<usize> {
        match self {
            Mount::Revolute { parent, .. } | Mount::Prismatic { parent } => Some(parent),
            _ => None,
        }
    }
}

/// One body of a generated mechanism.
#[derive(Clone, Debug)]
pub struct Body {
    pub mount: Mount,
    pub mass: f64,
    pub inertia: f64,
    /// Its size `L`, m: the scale of its shapes and joint offsets.
    pub size: f64,
    pub gene: BodyGene,
}

/// One shape, already written as the body of its `[[shapes]]` table (without `name`, `body`).
#[derive(Clone, Debug)]
pub struct Shape {
    pub body: usize,
    /// `circle`, `arc`, `ellipse`, `point`, `polygon`, `box` or `capsule`.
    pub kind: &'static str,
    pub keys: String,
    pub switchable: bool,
    pub group: usize,
}

/// A generated mechanism, ready to be written as a scene.
#[derive(Clone, Debug)]
pub struct Mechanism {
    pub genes: Genes,
    pub bodies: Vec<Body>,
    pub shapes: Vec<Shape>,
    /// Added to every base's height, m ([`Mechanism::lift`]).
    pub lift: f64,
    /// The steps a run of it takes.
    pub steps: u64,
}

fn log_range(u: f64, low: f64, high: f64) -> f64 {
    low * (high / low).powf(u)
}

fn lerp(u: f64, low: f64, high: f64) -> f64 {
    low + (high - low) * u
}

/// A number as TOML (always with a decimal point or exponent).
fn num(x: f64) -> String {
    format!("{x:?}")
}

fn pair(x: f64, y: f64) -> String {
    format!("[{}, {}]", num(x), num(y))
}

impl Mechanism {
    /// Reads `genes` into a mechanism (every combination is one; see [`crate::genes`]).
    pub fn from_genes(genes: &Genes) -> Self {
        let mut bodies: Vec<Body> = Vec::new();
        for (i, g) in genes.bodies.iter().enumerate() {
            let mount = if i > 0 && g.attach < 0.7 {
                let parent = ((g.attach / 0.7) * i as f64) as usize;
                if g.prismatic {
                    Mount::Prismatic { parent }
                } else {
                    Mount::Revolute {
                        parent,
                        absolute: g.absolute && g.limits.is_none(),
                    }
                }
            } else if g.base < 0.6 {
                Mount::Floating
            } else if g.base < 0.85 {
                Mount::Pinned
            } else {
                Mount::Fixed
            };
            let size = lerp(g.size, 0.05, 0.5);
            let mass = log_range(g.mass, 0.01, 10.0);
            bodies.push(Body {
                mount,
                mass,
                inertia: mass * size * size / 12.0 * lerp(g.inertia, 0.5, 2.0),
                size,
                gene: g.clone(),
            });
        }
        // A model needs a coordinate: the first body floats if nothing else moves.
        if bodies.iter().all(|b| b.mount.coordinates() == 0) {
            bodies[0].mount = Mount::Floating;
        }
        let pulse = controller_kind(genes) == 1;
        let count = bodies.len();
        let mut shapes: Vec<Shape> = genes
            .shapes
            .iter()
            .map(|g| {
                shape(
                    g,
                    ((g.body * count as f64) as usize).min(count - 1),
                    &bodies,
                )
            })
            .map(|mut s| {
                s.switchable &= pulse;
                s
            })
            .collect();
        // One cane at most, and only on a body that moves.
        let mut cane_seen = false;
        for s in &mut shapes {
            if s.switchable {
                s.switchable = !cane_seen && bodies[s.body].mount != Mount::Fixed;
                cane_seen |= s.switchable;
            }
        }
        let dt = log_range(genes.world.dt, 1e-4, 1e-3);
        Self {
            genes: genes.clone(),
            bodies,
            shapes,
            lift: 0.0,
            steps: (0.3 / dt).round().clamp(300.0, 3000.0) as u64,
        }
    }

    /// Step size `Δt`, s.
    pub fn dt(&self) -> f64 {
        log_range(self.genes.world.dt, 1e-4, 1e-3)
    }

    /// Raises every base (and so every tree) by `dy` m: a start that overlapped the terrain
    /// or another body is tried higher up.
    pub fn lift(&mut self, dy: f64) {
        self.lift += dy;
    }

    /// Whether the run has no actuation (passive controller).
    pub fn is_passive(&self) -> bool {
        controller_kind(&self.genes) == 0
            || self.pulse_joint().is_none() && self.flywheel().is_none()
    }

    /// The scene as TOML text.
    pub fn to_toml(&self) -> String {
        let w = &self.genes.world;
        let mut t = String::new();
        let dt = self.dt();
        let _ = writeln!(t, "[meta]\ntitle = \"generated mechanism\"\n");
        let _ = writeln!(
            t,
            "[simulation]\nduration = {}\ndt = {}\nwarm_start = {}\nstrict = {}\n",
            num(self.steps as f64 * dt),
            num(dt),
            w.warm_start,
            w.strict
        );
        let _ = writeln!(t, "[environment]");
        let (kind, a, b) = w.terrain;
        if kind < 0.5 {
            let _ = writeln!(t, "terrain = \"flat\"\nheight = {}", num(0.1 * a));
        } else if kind < 0.75 {
            let _ = writeln!(t, "terrain = \"incline\"\nangle = {}", num(0.5 * a));
        } else {
            let _ = writeln!(
                t,
                "terrain = \"step\"\nstep_x = {}\nstep_height = {}",
                num(0.3 * a),
                num(lerp(b, 0.01, 0.2))
            );
        }
        let _ = writeln!(
            t,
            "friction = {}\nrestitution = {}",
            num(2.0 * w.friction),
            num(w.restitution)
        );
        if let Some(e_t) = w.tangential {
            let _ = writeln!(t, "tangential_restitution = {}", num(e_t));
        }
        t.push('\n');
        for (i, body) in self.bodies.iter().enumerate() {
            self.write_body(&mut t, i, body);
        }
        for (i, s) in self.shapes.iter().enumerate() {
            let _ = writeln!(
                t,
                "[[shapes]]\nname = \"s{i}\"\nbody = \"b{}\"\ntype = \"{}\"\n{}",
                s.body, s.kind, s.keys
            );
            if let Some((mu, e, e_t)) = self.genes.shapes[i].material {
                let _ = writeln!(
                    t,
                    "friction = {}\nrestitution = {}\ntangential_restitution = {}",
                    num(2.0 * mu),
                    num(e),
                    num(e_t)
                );
            }
            if s.switchable {
                let _ = writeln!(t, "switchable = true");
            } else if w.body_contacts.is_some() && w.groups {
                let _ = writeln!(
                    t,
                    "group = {}\ncollides_with = [{}]",
                    s.group,
                    (s.group + 1) % 3
                );
            }
            t.push('\n');
        }
        self.write_springs(&mut t);
        self.write_pairs(&mut t);
        if let Some((mu, e)) = w.body_contacts {
            let _ = writeln!(
                t,
                "[body_contacts]\nall = true\nfriction = {}\nrestitution = {}\n",
                num(2.0 * mu),
                num(e)
            );
        }
        self.write_controller(&mut t);
        self.write_initial(&mut t);
        t
    }

    fn write_body(&self, t: &mut String, i: usize, body: &Body) {
        let g = &body.gene;
        let _ = writeln!(
            t,
            "[[bodies]]\nname = \"b{i}\"\nmass = {}\ninertia = {}",
            num(body.mass),
            num(body.inertia)
        );
        let com = pair(0.5 * body.size * g.com.0, 0.5 * body.size * g.com.1);
        match body.mount {
            Mount::Floating if i > 0 => {
                let _ = writeln!(t, "base = \"floating\"");
            }
            Mount::Floating => {}
            Mount::Pinned => {
                let (x, y) = self.base_place(g);
                let _ = writeln!(t, "base = \"pinned\"\npivot = {}\ncom = {com}", pair(x, y));
            }
            Mount::Fixed => {
                let (x, y) = self.base_place(g);
                let _ = writeln!(
                    t,
                    "base = \"fixed\"\nposition = {}\nangle = {}",
                    pair(x, y),
                    num(lerp(g.place.2, -PI, PI))
                );
            }
            Mount::Revolute { parent, absolute } => {
                let _ = writeln!(
                    t,
                    "parent = \"b{parent}\"\njoint = \"revolute\"\ncom = {com}"
                );
                if absolute {
                    let _ = writeln!(t, "coordinate = \"absolute\"");
                }
            }
            Mount::Prismatic { parent } => {
                let angle = TAU * g.axis;
                let _ = writeln!(
                    t,
                    "parent = \"b{parent}\"\njoint = \"prismatic\"\naxis = {}\ncom = {com}",
                    pair(angle.cos(), angle.sin())
                );
            }
        }
        if let Some(parent) = body.mount.parent() {
            let s = 0.5 * self.bodies[parent].size;
            let _ = writeln!(t, "pivot = {}", pair(s * g.pivot.0, s * g.pivot.1));
        }
        if body.mount.coordinates() == 1 {
            let prismatic = matches!(body.mount, Mount::Prismatic { .. });
            if let Some((lower, upper)) = self.limits(body) {
                let _ = writeln!(
                    t,
                    "limits = {}\nlimit_restitution = {}",
                    pair(lower, upper),
                    num(g.limit_restitution)
                );
            }
            if let Some((k, rest)) = g.spring {
                // About one oscillation per 20 ms at the most for the body's own inertia.
                let scale = if prismatic { body.mass } else { body.inertia };
                let stiffness = scale * log_range(k, 1.0, 1e5);
                let rest = if prismatic {
                    lerp(rest, -0.1, 0.3)
                } else {
                    lerp(rest, -1.0, 1.0)
                };
                let _ = writeln!(
                    t,
                    "stiffness = {}\nrest_position = {}",
                    num(stiffness),
                    num(rest)
                );
            }
            if let Some(c) = g.damping {
                let scale = if prismatic { body.mass } else { body.inertia };
                let _ = writeln!(t, "damping = {}", num(scale * log_range(c, 0.01, 1e4)));
            }
            if let Some(d) = g.dry_friction {
                // From a hundredth of the body's weight (times its size) to twice it: joints
                // that slip and joints that hold against gravity.
                let weight = body.mass * 9.81 * if prismatic { 1.0 } else { body.size };
                let _ = writeln!(
                    t,
                    "dry_friction = {}",
                    num(weight * log_range(d, 0.01, 2.0))
                );
            }
        }
        t.push('\n');
    }

    /// A base's place: `x` in `[-0.5, 0.5]` m, `y` in `[0.05, 1.2]` m plus the lift.
    fn base_place(&self, g: &BodyGene) -> (f64, f64) {
        (
            lerp(g.place.0, -0.5, 0.5),
            lerp(g.place.1, 0.05, 1.2) + self.lift,
        )
    }

    /// A jointed body's stops, when its genes give it some.
    fn limits(&self, body: &Body) -> Option<(f64, f64)> {
        let (lo, hi) = body.gene.limits?;
        match body.mount {
            Mount::Prismatic { .. } => Some((-0.2 * lo, lerp(hi, 0.05, 0.35))),
            Mount::Revolute {
                absolute: false, ..
            }
            | Mount::Pinned => Some((-lerp(lo, 0.1, 2.5), lerp(hi, 0.1, 2.5))),
            _ => None,
        }
    }

    fn write_springs(&self, t: &mut String) {
        let count = self.bodies.len();
        if count < 2 {
            return;
        }
        for (i, g) in self.genes.springs.iter().enumerate() {
            let a = ((g.bodies.0 * count as f64) as usize).min(count - 1);
            let mut b = ((g.bodies.1 * (count - 1) as f64) as usize).min(count - 2);
            if b >= a {
                b += 1;
            }
            if self.bodies[a].mount == Mount::Fixed && self.bodies[b].mount == Mount::Fixed {
                continue;
            }
            let (sa, sb) = (0.5 * self.bodies[a].size, 0.5 * self.bodies[b].size);
            let mass = self.bodies[a]
                .mass
                .min(self.bodies[b].mass.max(1e-9))
                .max(0.01);
            let _ = writeln!(
                t,
                "[[springs]]\nname = \"spring{i}\"\nbody_a = \"b{a}\"\nbody_b = \"b{b}\"\n\
                 point_a = {}\npoint_b = {}\nstiffness = {}\nrest_length = {}\ntension_only = {}",
                pair(sa * g.points.0, sa * g.points.1),
                pair(sb * g.points.2, sb * g.points.3),
                num(mass * log_range(g.stiffness, 1.0, 1e4)),
                num(lerp(g.rest, 0.0, 0.5)),
                g.tension_only
            );
            if let Some(c) = g.damping {
                let _ = writeln!(t, "damping = {}", num(mass * log_range(c, 0.01, 100.0)));
            }
            t.push('\n');
        }
    }

    /// The explicit contact pairs that make a valid pair (see [`crate::genes::PairGene`]).
    fn write_pairs(&self, t: &mut String) {
        let count = self.shapes.len();
        let mut written: Vec<(usize, usize)> = Vec::new();
        for g in &self.genes.pairs {
            let pick = |u: f64| ((u * count as f64) as usize).min(count - 1);
            let (a, b) = (pick(g.shapes.0), pick(g.shapes.1));
            let (sa, sb) = (&self.shapes[a], &self.shapes[b]);
            let exact = !matches!(
                (sa.kind, sb.kind),
                ("ellipse", "ellipse" | "polygon" | "box" | "capsule")
                    | ("polygon" | "box" | "capsule", "ellipse")
                    | ("point", "point")
            );
            let fixed = |s: &Shape| self.bodies[s.body].mount == Mount::Fixed;
            let key = (a.min(b), a.max(b));
            if sa.body == sb.body
                || (fixed(sa) && fixed(sb))
                || sa.switchable
                || sb.switchable
                || !exact
                || written.contains(&key)
            {
                continue;
            }
            written.push(key);
            let _ = writeln!(t, "[[contact_pairs]]\nshapes = [\"s{a}\", \"s{b}\"]");
            if let Some((mu, e, e_t)) = g.material {
                let _ = writeln!(
                    t,
                    "friction = {}\nrestitution = {}\ntangential_restitution = {}",
                    num(2.0 * mu),
                    num(e),
                    num(e_t)
                );
            }
            t.push('\n');
        }
    }

    /// The root of body `b`'s tree.
    fn root(&self, mut b: usize) -> usize {
        while let Some(parent) = self.bodies[b].mount.parent() {
            b = parent;
        }
        b
    }

    /// The body a pulse drives: the first with a joint coordinate (revolute, prismatic or a
    /// pinned base) at or after the controller's choice.
    fn pulse_joint(&self) -> Option<usize> {
        let count = self.bodies.len();
        let first = ((self.genes.world.controller.1[0] * count as f64) as usize).min(count - 1);
        (0..count)
            .map(|k| (first + k) % count)
            .find(|&b| self.bodies[b].mount.coordinates() == 1)
    }

    /// A flywheel for the momentum-impulse controller: a revolute body on a body.
    fn flywheel(&self) -> Option<usize> {
        self.bodies
            .iter()
            .position(|b| matches!(b.mount, Mount::Revolute { .. }))
    }

    fn write_controller(&self, t: &mut String) {
        let w = &self.genes.world;
        let c = w.controller.1;
        match controller_kind(&self.genes) {
            1 => {
                let Some(joint) = self.pulse_joint() else {
                    return;
                };
                let body = &self.bodies[joint];
                let (key, amplitude) = match body.mount {
                    Mount::Prismatic { .. } => ("force", body.mass * 9.81 * lerp(c[1], 0.1, 20.0)),
                    _ => (
                        "torque",
                        body.mass * 9.81 * body.size * lerp(c[1], 0.1, 20.0),
                    ),
                };
                let pulse = lerp(c[2], 0.01, 0.1);
                let _ = writeln!(
                    t,
                    "[controller]\ntype = \"pulse\"\njoint = \"b{joint}\"\n{key} = {}\n\
                     pulse_duration = {}\nperiod = {}",
                    num(amplitude),
                    num(pulse),
                    num(2.0 * pulse + lerp(c[3], 0.01, 0.5))
                );
                if let Some(cane) = self.shapes.iter().position(|s| s.switchable) {
                    let (mode, delay, duration) = w.cane;
                    let mode = ["retracted", "extended", "timed"][((mode * 3.0) as usize).min(2)];
                    let _ = writeln!(t, "cane = \"s{cane}\"\ncane_mode = \"{mode}\"");
                    if mode == "timed" {
                        let _ = writeln!(
                            t,
                            "cane_delay = {}\ncane_duration = {}",
                            num(delay),
                            num(duration)
                        );
                    }
                }
                t.push('\n');
            }
            2 => {
                let Some(flywheel) = self.flywheel() else {
                    return;
                };
                let body = &self.bodies[flywheel];
                let torque = body.inertia * log_range(c[1], 10.0, 1e3);
                let _ = writeln!(
                    t,
                    "[controller]\ntype = \"momentum_impulse\"\nflywheel = \"b{flywheel}\"\n\
                     torque = {}\nimpulse_limit = {}\n",
                    num(torque),
                    num(torque * lerp(c[2], 0.02, 0.3))
                );
            }
            _ => {}
        }
    }

    fn write_initial(&self, t: &mut String) {
        let mut q = Vec::new();
        let mut u = Vec::new();
        for body in &self.bodies {
            let g = &body.gene;
            match body.mount {
                Mount::Floating => {
                    let (x, y) = self.base_place(g);
                    q.extend([x, y, lerp(g.place.2, -PI, PI)]);
                    u.extend([g.rate, 0.5 * g.rate, 2.0 * g.rate]);
                }
                Mount::Fixed => {}
                Mount::Prismatic { .. } => {
                    let (lo, hi) = self.limits(body).unwrap_or((-0.1, 0.3));
                    q.push(lerp(g.start, lo, hi));
                    u.push(g.rate);
                }
                _ => {
                    let (lo, hi) = self.limits(body).unwrap_or((-PI, PI));
                    q.push(lerp(g.start, lo, hi));
                    u.push(3.0 * g.rate);
                }
            }
        }
        let list = |v: &[f64]| v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ");
        let _ = writeln!(t, "[initial]\nq = [{}]\nu = [{}]", list(&q), list(&u));
        let first_tree_touches = self
            .shapes
            .iter()
            .any(|s| !s.switchable && self.root(s.body) == 0);
        if self.genes.world.rest_on_ground
            && self.bodies[0].mount == Mount::Floating
            && first_tree_touches
        {
            let _ = writeln!(t, "rest_on_ground = true");
        }
    }
}

/// passive (0), pulse (1) or momentum impulse (2).
fn controller_kind(genes: &Genes) -> usize {
    ((genes.world.controller.0 * 3.0) as usize).min(2)
}

/// A shape of kind `g.kind` on `body`, sized by the body.
fn shape(g: &ShapeGene, body: usize, bodies: &[Body]) -> Shape {
    let l = 0.5 * bodies[body].size;
    let p = g.p;
    let center = pair(l * (p[0] - 0.5), l * (p[1] - 0.5));
    let r = |u: f64| lerp(u, 0.1, 1.0) * l;
    let kinds = [
        "circle", "arc", "ellipse", "point", "polygon", "box", "capsule",
    ];
    let kind = kinds[((g.kind * kinds.len() as f64) as usize).min(kinds.len() - 1)];
    let keys = match kind {
        "circle" => format!("center = {center}\nradius = {}", num(r(p[2]))),
        "arc" => {
            let start = lerp(p[3], -PI, PI);
            format!(
                "center = {center}\nradius = {}\nstart = {}\nend = {}",
                num(r(p[2])),
                num(start),
                num(start + lerp(p[4], 0.3, TAU))
            )
        }
        "ellipse" => format!(
            "center = {center}\nsemi_x = {}\nsemi_y = {}",
            num(r(p[2])),
            num(r(p[3]))
        ),
        "point" => format!(
            "position = {}",
            pair(l * (2.0 * p[0] - 1.0), l * (2.0 * p[1] - 1.0))
        ),
        "polygon" => {
            // Corners on an ellipse at increasing angles: convex, counter-clockwise.
            let k = 3 + ((p[5] * 4.0) as usize).min(3);
            let (rx, ry, turn) = (r(p[2]), r(p[3]), TAU * p[4]);
            let corners: Vec<String> = (0..k)
                .map(|j| {
                    let a = turn + TAU * j as f64 / k as f64;
                    pair(
                        l * (p[0] - 0.5) + rx * a.cos(),
                        l * (p[1] - 0.5) + ry * a.sin(),
                    )
                })
                .collect();
            format!("vertices = [{}]", corners.join(", "))
        }
        "capsule" => {
            // A segment through the centre at any angle.
            let (half, turn) = (r(p[2]) * lerp(p[5], 0.2, 1.0), TAU * p[4]);
            let (dx, dy) = (half * turn.cos(), half * turn.sin());
            let (cx, cy) = (l * (p[0] - 0.5), l * (p[1] - 0.5));
            format!(
                "from = {}\nto = {}\nradius = {}",
                pair(cx - dx, cy - dy),
                pair(cx + dx, cy + dy),
                num(0.5 * r(p[3]))
            )
        }
        _ => format!(
            "center = {center}\nhalf_width = {}\nhalf_height = {}",
            num(r(p[2])),
            num(r(p[3]))
        ),
    };
    Shape {
        body,
        kind,
        keys,
        switchable: g.cane && kind == "point",
        group: ((p[5] * 3.0) as usize).min(2),
    }
}

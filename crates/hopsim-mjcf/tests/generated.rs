//! Generated documents: random valid planar MJCF trees read without error and obey the
//! physics of rigid bodies (masses add up; turning and moving the whole mechanism in its
//! plane changes no body's mass or inertia about its centre of mass); random damage to
//! them, and random text, gives located errors and never a panic.

use hopsim_mjcf::{read_str, PlanarModel, ReadOptions};
use proptest::prelude::*;

#[derive(Debug, Clone)]
struct GeomSpec {
    kind: u8,
    size: [f64; 3],
    pos: [f64; 2],
    turn: f64,
    mass: f64,
}

#[derive(Debug, Clone)]
struct BodySpec {
    parent: usize,
    pos: [f64; 3],
    turn: f64,
    /// 0: hinge about ±y, 1: slide in the x–z plane, 2: no joint (welded).
    joint: u8,
    axis_sign: bool,
    slide_angle: f64,
    geoms: Vec<GeomSpec>,
}

fn geom() -> impl Strategy<Value = GeomSpec> {
    (
        0u8..5,
        [0.01f64..0.3, 0.01f64..0.3, 0.01f64..0.3],
        [-0.5f64..0.5, -0.5f64..0.5],
        -180.0f64..180.0,
        0.1f64..5.0,
    )
        .prop_map(|(kind, size, pos, turn, mass)| GeomSpec {
            kind,
            size,
            pos,
            turn,
            mass,
        })
}

fn body(index: usize) -> impl Strategy<Value = BodySpec> {
    (
        0..index.max(1),
        [-1.0f64..1.0, -0.1f64..0.1, -1.0f64..1.0],
        -180.0f64..180.0,
        0u8..3,
        any::<bool>(),
        -3.0f64..3.0,
        prop::collection::vec(geom(), 1..4),
    )
        .prop_map(
            move |(parent, pos, turn, joint, axis_sign, slide_angle, geoms)| BodySpec {
                parent: if index == 0 { 0 } else { parent },
                pos,
                turn,
                joint: if index == 0 { 0 } else { joint },
                axis_sign,
                slide_angle,
                geoms,
            },
        )
}

fn mechanism() -> impl Strategy<Value = (Vec<BodySpec>, bool)> {
    (1usize..6, any::<bool>()).prop_flat_map(|(n, radian)| {
        let bodies: Vec<_> = (0..n).map(body).collect();
        (bodies, Just(radian))
    })
}

/// The document, with the root turned by `root_turn` degrees about y and moved by `shift`.
fn document(bodies: &[BodySpec], radian: bool, root_turn: f64, shift: [f64; 2]) -> String {
    let angle = |deg: f64| if radian { deg.to_radians() } else { deg };
    let mut xml = format!(
        "<mujoco model=\"generated\">\n<compiler angle=\"{}\"/>\n<worldbody>\n",
        if radian { "radian" } else { "degree" }
    );
    fn close_to(xml: &mut String, open: &mut Vec<usize>, parent: usize) {
        while open.last().is_some_and(|&top| top != parent) {
            open.pop();
            xml.push_str("</body>\n");
        }
    }
    let mut open: Vec<usize> = Vec::new();
    for (i, b) in bodies.iter().enumerate() {
        // Bodies are written depth first: close those that are not this one's parent.
        if i > 0 {
            let parent = b.parent.min(i - 1);
            if !open.contains(&parent) {
                // Not an ancestor still open: hang it on the innermost open body instead.
                let p = *open.last().unwrap_or(&0);
                close_to(&mut xml, &mut open, p);
            } else {
                close_to(&mut xml, &mut open, parent);
            }
        }
        let (pos, turn) = if i == 0 {
            (
                [b.pos[0] + shift[0], b.pos[1], b.pos[2] + shift[1]],
                b.turn + root_turn,
            )
        } else {
            (b.pos, b.turn)
        };
        xml.push_str(&format!(
            "<body name=\"b{i}\" pos=\"{} {} {}\" euler=\"0 {} 0\">\n",
            pos[0],
            pos[1],
            pos[2],
            angle(turn)
        ));
        match b.joint {
            0 => xml.push_str(&format!(
                "<joint name=\"j{i}\" type=\"hinge\" axis=\"0 {} 0\" pos=\"0.1 0 0\"/>\n",
                if b.axis_sign { 1 } else { -1 }
            )),
            1 => xml.push_str(&format!(
                "<joint name=\"j{i}\" type=\"slide\" axis=\"{} 0 {}\"/>\n",
                b.slide_angle.cos(),
                b.slide_angle.sin()
            )),
            _ => {}
        }
        for g in &b.geoms {
            let [x, z] = g.pos;
            let [a, bb, c] = g.size;
            let body = match g.kind {
                0 => format!("type=\"sphere\" size=\"{a}\" pos=\"{x} 0 {z}\""),
                1 => format!("type=\"capsule\" size=\"{a}\" fromto=\"{x} 0 {z} {} 0 {}\"", x + bb, z - c),
                2 => format!("type=\"box\" size=\"{a} {bb} {c}\" pos=\"{x} 0 {z}\" euler=\"0 {} 0\"", angle(g.turn)),
                3 => format!("type=\"cylinder\" size=\"{a} {bb}\" pos=\"{x} 0 {z}\" zaxis=\"0 1 0\""),
                _ => format!("type=\"ellipsoid\" size=\"{a} {bb} {c}\" pos=\"{x} 0 {z}\" axisangle=\"0 1 0 {}\"", angle(g.turn)),
            };
            xml.push_str(&format!("<geom {body} mass=\"{}\"/>\n", g.mass));
        }
        open.push(i);
    }
    for _ in open {
        xml.push_str("</body>\n");
    }
    xml.push_str("</worldbody>\n</mujoco>\n");
    xml
}

fn read(xml: &str) -> Result<PlanarModel, hopsim_mjcf::MjcfError> {
    read_str(xml, "generated.xml", None, &ReadOptions::default())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn valid_planar_documents_read_and_obey_rigid_body_physics(
        (bodies, radian) in mechanism(),
        root_turn in -180.0f64..180.0,
        shift in [-2.0f64..2.0, -2.0f64..2.0],
    ) {
        let xml = document(&bodies, radian, 0.0, [0.0, 0.0]);
        let model = read(&xml).map_err(|e| TestCaseError::fail(format!("{e}\n{xml}")))?;
        // Masses add up: every geom's given mass is in exactly one body.
        let given: f64 = bodies.iter().flat_map(|b| &b.geoms).map(|g| g.mass).sum();
        let total: f64 = model.bodies.iter().map(|b| b.mass).sum::<f64>() + model.world.iter().map(|p| p.mass).sum::<f64>();
        prop_assert!((total - given).abs() <= 1e-12 * given, "{total} against {given}");
        // The whole mechanism turned and moved in its plane: the same bodies, masses and
        // inertias about their centres of mass.
        let moved = read(&document(&bodies, radian, root_turn, shift)).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(moved.bodies.len(), model.bodies.len());
        for (a, b) in model.bodies.iter().zip(&moved.bodies) {
            prop_assert!((a.mass - b.mass).abs() <= 1e-12 * a.mass);
            prop_assert!((a.inertia - b.inertia).abs() <= 1e-9 * a.inertia.max(1e-12), "{} against {}", a.inertia, b.inertia);
            prop_assert!((a.com.norm() - b.com.norm()).abs() <= 1e-9);
        }
        prop_assert_eq!(model.joints.iter().map(|j| j.qpos).collect::<Vec<_>>(), (0..model.joints.len()).collect::<Vec<_>>());
    }

    #[test]
    fn damaged_documents_give_located_errors_without_panicking(
        (bodies, radian) in mechanism(),
        edits in prop::collection::vec((any::<prop::sample::Index>(), 0u8..3, prop::sample::select(vec!['<', '>', '"', '=', ' ', 'x', '1', '-', '/', 'é', '\0', 'e'])), 1..6),
    ) {
        let mut text: Vec<char> = document(&bodies, radian, 0.0, [0.0, 0.0]).chars().collect();
        for (at, op, c) in edits {
            let i = at.index(text.len());
            match op {
                0 => { text.remove(i); }
                1 => text.insert(i, c),
                _ => text[i] = c,
            }
        }
        let text: String = text.into_iter().collect();
        if let Err(e) = read(&text) {
            let lines = text.lines().count() as u32 + 1;
            prop_assert!(e.location.line >= 1 && e.location.line <= lines && e.location.column >= 1, "{e}");
            prop_assert!(!e.message.is_empty());
        }
    }

    #[test]
    fn random_text_gives_located_errors(text in "\\PC{0,200}", tag in prop::sample::select(vec!["", "<mujoco>", "<mujoco><worldbody><body>"])) {
        let text = format!("{tag}{text}");
        if let Err(e) = read(&text) {
            prop_assert!(e.location.line >= 1 && e.location.column >= 1 && !e.to_string().is_empty());
        }
    }
}

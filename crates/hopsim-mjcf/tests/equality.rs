//! `<equality>` read as loop closures (docs/mjcf.md, "Closed loops"), against closed forms
//! written from the MJCF text: a connect's points, a weld's points and angle with and
//! without `relpose`, MuJoCo's defaults (`body2` the world, `active`), and what is not
//! supported, as located errors and notices.

use hopsim_mjcf::{read_str, EqualityKind, MjcfError, NoticeKind, PlanarModel, ReadOptions};
use nalgebra::Vector2;

fn parse(xml: &str) -> Result<PlanarModel, MjcfError> {
    read_str(xml, "test.xml", None, &ReadOptions::default())
}

/// Two pendulums in the x–z plane (hinge axes along −y, the plane's normal): `a` hinged at
/// the origin, `b` at (1, 0, 0) with a jointless `tip` welded into it, and `equality`.
fn pendulums(equality: &str) -> String {
    format!(
        r#"<mujoco><compiler angle="degree"/><worldbody>
          <body name="a"><joint name="ja" axis="0 -1 0"/><geom size="0.1" mass="1"/></body>
          <body name="b" pos="1 0 0"><joint name="jb" axis="0 -1 0"/><geom size="0.1" mass="1"/>
            <body name="tip" pos="0 0 0.5"><geom size="0.05" mass="1"/></body>
          </body>
        </worldbody>{equality}</mujoco>"#
    )
}

fn close(a: Vector2<f64>, b: Vector2<f64>) -> bool {
    (a - b).norm() < 1e-15
}

#[test]
fn a_connect_holds_body1s_anchor_on_the_point_of_body2_under_it_at_qpos0() {
    let m = parse(&pendulums(
        r#"<equality><connect name="pin" body1="a" body2="tip" anchor="0.75 0 0.25"/></equality>"#,
    ))
    .unwrap();
    let [eq] = m.equalities.as_slice() else {
        panic!("{:?}", m.equalities)
    };
    assert_eq!(eq.name.as_deref(), Some("pin"));
    assert_eq!(eq.kind, EqualityKind::Connect);
    // body1 is `a` (origin at 0); `tip` is welded into `b` (origin at (1, 0)).
    assert_eq!((eq.body1, eq.body2), (Some(0), Some(1)));
    assert!(close(eq.point1, Vector2::new(0.75, 0.25)), "{}", eq.point1);
    assert!(close(eq.point2, Vector2::new(-0.25, 0.25)), "{}", eq.point2);
}

#[test]
fn body2_defaults_to_the_world() {
    let m = parse(&pendulums(
        r#"<equality><connect body1="b" anchor="0 0 -1"/></equality>"#,
    ))
    .unwrap();
    let eq = &m.equalities[0];
    assert_eq!((eq.body1, eq.body2), (Some(1), None));
    assert!(close(eq.point1, Vector2::new(0.0, -1.0)));
    // The world's point is a world point.
    assert!(close(eq.point2, Vector2::new(1.0, -1.0)), "{}", eq.point2);
}

#[test]
fn a_weld_without_relpose_holds_the_pose_at_qpos0() {
    let m = parse(&pendulums(
        r#"<equality><weld body1="a" body2="b" anchor="0 0 0.2"/></equality>"#,
    ))
    .unwrap();
    let eq = &m.equalities[0];
    assert_eq!(eq.kind, EqualityKind::Weld { angle: 0.0 });
    // The anchor is in body2's frame; body1's point is the same world point at qpos0.
    assert!(close(eq.point2, Vector2::new(0.0, 0.2)));
    assert!(close(eq.point1, Vector2::new(1.0, 0.2)), "{}", eq.point1);
}

/// `relpose` turns body2 by +30° about +y relative to body1: in the x–z plane, whose
/// normal is −y, that is −30°, so the weld holds `θ_a − θ_b = +30°`; body2's anchor seen
/// from body1 is `pos + R anchor = (0.5 + 0.2 sin 30°, 0.2 cos 30°)`.
#[test]
fn a_weld_with_relpose_holds_that_pose() {
    let half = 15f64.to_radians();
    let m = parse(&pendulums(&format!(
        r#"<equality><weld body1="a" body2="b" anchor="0 0 0.2"
             relpose="0.5 0 0 {} 0 {} 0" torquescale="2"/></equality>"#,
        half.cos(),
        half.sin()
    )))
    .unwrap();
    let eq = &m.equalities[0];
    let EqualityKind::Weld { angle } = eq.kind else {
        panic!("{:?}", eq.kind)
    };
    assert!((angle - 30f64.to_radians()).abs() < 1e-15, "{angle}");
    assert!(close(eq.point2, Vector2::new(0.0, 0.2)));
    let expected = Vector2::new(0.5 + 0.2 * 0.5, 0.2 * 30f64.to_radians().cos());
    assert!((eq.point1 - expected).norm() < 1e-15, "{}", eq.point1);
    assert!(m.notices.iter().any(|n| n.kind == NoticeKind::NotApplicable
        && n.subject.attribute.as_deref() == Some("torquescale")));
}

#[test]
fn a_relpose_out_of_the_plane_is_an_error() {
    let e = parse(&pendulums(
        r#"<equality><weld body1="a" body2="b" relpose="0 0 0 0.9 0.1 0 0"/></equality>"#,
    ))
    .unwrap_err();
    assert_eq!(e.subject.unwrap().attribute.as_deref(), Some("relpose"));
    assert!(e.message.contains("out of the plane"), "{}", e.message);
}

#[test]
fn soft_parameters_are_notices_and_inactive_equalities_are_left_out() {
    let m = parse(&pendulums(
        r#"<default><equality solimp="0.9 0.95 0.001"/></default>
        <equality>
          <connect body1="a" body2="b" anchor="1 0 0" solref="0.01 1"/>
          <connect body1="a" body2="tip" anchor="1 0 0.5" active="false"/>
        </equality>"#,
    ))
    .unwrap();
    assert_eq!(m.equalities.len(), 1);
    for attribute in ["solref", "solimp"] {
        assert!(
            m.notices.iter().any(|n| n.kind == NoticeKind::NotApplicable
                && n.subject.attribute.as_deref() == Some(attribute)),
            "{attribute}: {:?}",
            m.notices
        );
    }
    assert!(m
        .notices
        .iter()
        .any(|n| n.subject.attribute.as_deref() == Some("active")));
}

#[test]
fn a_default_class_can_switch_equalities_off() {
    let m = parse(&pendulums(
        r#"<default><default class="off"><equality active="false"/></default></default>
        <equality><connect class="off" body1="a" body2="b" anchor="1 0 0"/></equality>"#,
    ))
    .unwrap();
    assert!(m.equalities.is_empty());
}

#[test]
fn the_equality_flag_disables_them_with_a_notice() {
    let m = parse(&pendulums(
        r#"<option><flag equality="disable"/></option>
        <equality><connect body1="a" body2="b" anchor="1 0 0"/></equality>"#,
    ))
    .unwrap();
    assert!(m.equalities.is_empty());
    assert!(m.notices.iter().any(|n| n.subject.element == "connect"));
}

#[test]
fn unsupported_equalities_are_located_errors_naming_element_and_attribute() {
    for (xml, element, attribute) in [
        (
            r#"<joint joint1="ja" joint2="jb"/>"#,
            "joint",
            Some("joint1"),
        ),
        (r#"<tendon tendon1="t"/>"#, "tendon", Some("tendon1")),
        (r#"<flex flex="f"/>"#, "flex", Some("flex")),
        (
            r#"<connect body1="a" site1="s" site2="t"/>"#,
            "connect",
            Some("site1"),
        ),
        (r#"<connect body1="nobody"/>"#, "connect", Some("body1")),
        (
            r#"<connect body1="a" body2="b" ancor="1 0 0"/>"#,
            "connect",
            Some("ancor"),
        ),
        (
            r#"<connect body1="b" body2="tip"/>"#,
            "connect",
            Some("body2"),
        ),
        (r#"<weld body2="b"/>"#, "weld", None),
        (
            r#"<connect body1="a" relpose="0 0 0 1 0 0 0"/>"#,
            "connect",
            Some("relpose"),
        ),
    ] {
        let e = parse(&pendulums(&format!("<equality>{xml}</equality>"))).unwrap_err();
        let subject = e.subject.clone().unwrap();
        assert_eq!(subject.element, element, "{e}");
        assert_eq!(subject.attribute.as_deref(), attribute, "{e}");
        assert_eq!(e.location.line, 6, "{e}");
        assert!(e.location.column > 1, "{e}");
    }
}

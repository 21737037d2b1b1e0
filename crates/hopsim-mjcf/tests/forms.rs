//! Every attribute form the reader accepts, checked against closed forms: orientations
//! (quat, euler with each sequence, axisangle, xyaxes, zaxis; degrees and radians),
//! default classes and `childclass`, includes, `fromto` capsules, masses and inertias of
//! the solids, welded bodies, the plane found from the joints, units, and located errors.

use std::f64::consts::PI;

use hopsim_mjcf::{
    read_file, read_str, ActuatorKind, JointKind, MjcfError, NoticeKind, PlanarModel, ReadOptions,
    Shape, Vec2,
};

fn read(xml: &str) -> PlanarModel {
    read_str(xml, "test.xml", None, &ReadOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn fails(xml: &str) -> MjcfError {
    match read_str(xml, "test.xml", None, &ReadOptions::default()) {
        Ok(_) => panic!("read without error:\n{xml}"),
        Err(e) => e,
    }
}

/// A model with one body on a hinge about `y` (the x–z plane) holding `geom`.
fn one_body(compiler: &str, geom: &str) -> String {
    format!(
        r#"<mujoco><compiler {compiler}/><worldbody><body name="b"><joint type="hinge" axis="0 -1 0"/>{geom}</body></worldbody></mujoco>"#
    )
}

fn capsule_ends(m: &PlanarModel) -> (Vec2, Vec2) {
    match &m.geoms[0].shape {
        Shape::Capsule { a, b, .. } => (*a, *b),
        s => panic!("not a capsule: {s:?}"),
    }
}

fn near(a: Vec2, b: Vec2) -> bool {
    (a - b).norm() < 1e-12
}

#[test]
fn every_orientation_form_turns_a_capsule_by_thirty_degrees_about_y() {
    // A turn by θ about +y takes the capsule's axis z to (sin θ, 0, cos θ): in the x–z
    // plane the end b is h (sin θ, cos θ).
    let (h, t) = (0.5, PI / 6.0);
    let expected = Vec2::new(h * t.sin(), h * t.cos());
    let (s, c) = ((t / 2.0).sin(), (t / 2.0).cos());
    let forms = [
        ("", format!(r#"quat="{c} 0 {s} 0""#)),
        ("", format!(r#"quat="{} 0 {} 0""#, 2.0 * c, 2.0 * s)), // normalised
        ("", r#"euler="0 30 0""#.into()),
        (r#"angle="radian""#, format!(r#"euler="0 {t} 0""#)),
        (r#"eulerseq="zyx""#, r#"euler="0 30 0""#.into()),
        (r#"eulerseq="XYZ""#, r#"euler="0 30 0""#.into()),
        ("", r#"axisangle="0 2 0 30""#.into()),
        (r#"angle="radian""#, format!(r#"axisangle="0 1 0 {t}""#)),
        ("", format!(r#"xyaxes="{} 0 {} 0 3 0""#, t.cos(), -t.sin())),
        (
            "",
            format!(r#"zaxis="{} 0 {}""#, 2.0 * t.sin(), 2.0 * t.cos()),
        ),
    ];
    for (compiler, orientation) in forms {
        let m = read(&one_body(
            compiler,
            &format!(r#"<geom type="capsule" size="0.1 {h}" {orientation}/>"#),
        ));
        let (a, b) = capsule_ends(&m);
        assert!(
            near(b, expected) && near(a, -expected),
            "{compiler} {orientation}: ends {a:?} {b:?}"
        );
    }
}

#[test]
fn euler_sequences_differ_between_rotating_and_fixed_axes() {
    // Rotating axes "xyz": R = Ry(30°) Rz(90°) takes the box's x to y (the normal) and its
    // z to (sin 30°, 0, cos 30°): a 0.2 × 0.6 rectangle turned by 30° in the plane.
    let geom = r#"<geom type="box" size="0.1 0.2 0.3" euler="0 30 90"/>"#;
    let m = read(&one_body("", geom));
    let Shape::Polygon { vertices } = &m.geoms[0].shape else {
        panic!()
    };
    let (s, c) = (0.5, 3f64.sqrt() / 2.0);
    for v in vertices {
        // Each corner is ±0.2 along the box's y (now −(cos 30°, −sin 30°)) and ±0.3 along z.
        let along_z = v.x * s + v.y * c;
        let along_y = -(v.x * c - v.y * s);
        assert!(
            (along_z.abs() - 0.3).abs() < 1e-12 && (along_y.abs() - 0.2).abs() < 1e-12,
            "{v:?}"
        );
    }
    // Fixed axes "XYZ": R = Rz(90°) Ry(30°) tilts the box out of the x–z plane.
    let e = fails(&one_body(r#"eulerseq="XYZ""#, geom));
    assert!(e.to_string().contains("leaves the plane"), "{e}");
}

#[test]
fn two_orientations_on_one_element_are_an_error() {
    let e = fails(&one_body(
        "",
        r#"<geom type="sphere" size="0.1" quat="1 0 0 0" euler="0 0 0"/>"#,
    ));
    assert!(
        e.to_string().contains("given twice") && e.location.line == 1,
        "{e}"
    );
}

#[test]
fn defaults_nest_and_childclass_reaches_descendants() {
    let xml = r#"<mujoco>
  <default>
    <geom density="500"/>
    <joint damping="1"/>
    <default class="a">
      <joint damping="3" armature="0.5"/>
      <default class="b">
        <joint damping="5"/>
        <geom type="capsule" size="0.1 0.2"/>
      </default>
    </default>
  </default>
  <worldbody>
    <body name="p" childclass="b">
      <joint name="j1" axis="0 1 0"/>
      <geom/>
      <body name="q">
        <joint name="j2" class="a" axis="0 1 0"/>
        <joint name="j3" class="main" type="slide" axis="1 0 0"/>
        <geom class="main" type="sphere" size="0.1"/>
      </body>
    </body>
  </worldbody>
</mujoco>"#;
    let m = read(xml);
    let damping: Vec<f64> = m.joints.iter().map(|j| j.damping).collect();
    let armature: Vec<f64> = m.joints.iter().map(|j| j.armature).collect();
    assert_eq!(damping, [5.0, 3.0, 1.0]); // b's own, a's, main's
    assert_eq!(armature, [0.5, 0.5, 0.0]); // b inherits a's armature
                                           // The capsule from class b with main's density 500: ρ π r² (2h + 4r/3).
    let capsule = 500.0 * PI * 0.01 * (0.4 + 0.4 / 3.0);
    assert!((m.bodies[0].mass - capsule).abs() < 1e-12 * capsule);
    let sphere = 500.0 * 4.0 / 3.0 * PI * 1e-3;
    assert!((m.bodies[1].mass - sphere).abs() < 1e-12 * sphere);
    assert!(
        matches!(m.geoms[0].shape, Shape::Capsule { .. })
            && matches!(m.geoms[1].shape, Shape::Circle { .. })
    );
}

#[test]
fn an_unknown_class_and_a_class_defined_twice_are_errors() {
    let e = fails(&one_body("", r#"<geom class="nope" size="0.1"/>"#));
    assert!(e.to_string().contains("no default class `nope`"), "{e}");
    let e =
        fails(r#"<mujoco><default><default class="x"/><default class="x"/></default></mujoco>"#);
    assert!(
        e.to_string().contains("defined twice") && e.location.line == 1,
        "{e}"
    );
}

#[test]
fn includes_are_spliced_relative_to_the_main_file_and_errors_name_the_included_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("parts")).unwrap();
    std::fs::write(
        dir.path().join("parts/arm.xml"),
        "<mujocoinclude>\n  <body name=\"arm\">\n    <joint axis=\"0 1 0\"/>\n    <geom size=\"0.1\" mass=\"3\"/>\n  </body>\n</mujocoinclude>\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("parts/bad.xml"),
        "<mujoco>\n  <worldbody>\n    <geom sise=\"1\"/>\n  </worldbody>\n</mujoco>\n",
    )
    .unwrap();
    let main = dir.path().join("main.xml");
    std::fs::write(
        &main,
        r#"<mujoco><worldbody><include file="parts/arm.xml"/></worldbody></mujoco>"#,
    )
    .unwrap();
    let m = read_file(&main, &ReadOptions::default()).unwrap();
    assert_eq!((m.bodies[0].name.as_str(), m.bodies[0].mass), ("arm", 3.0));

    std::fs::write(&main, r#"<mujoco><include file="parts/bad.xml"/></mujoco>"#).unwrap();
    let e = read_file(&main, &ReadOptions::default()).unwrap_err();
    assert!(
        e.location.file.ends_with("bad.xml") && (e.location.line, e.location.column) == (3, 11),
        "{e}"
    );
    assert!(e.to_string().contains("did you mean `size`"), "{e}");

    std::fs::write(
        &main,
        r#"<mujoco><include file="parts/arm.xml"/><include file="parts/arm.xml"/></mujoco>"#,
    )
    .unwrap();
    let e = read_file(&main, &ReadOptions::default()).unwrap_err();
    assert!(e.to_string().contains("included more than once"), "{e}");
    std::fs::write(&main, "<mujoco>\n<include file=\"missing.xml\"/></mujoco>").unwrap();
    let e = read_file(&main, &ReadOptions::default()).unwrap_err();
    assert!(
        e.location.line == 2 && e.to_string().contains("cannot include"),
        "{e}"
    );
    let e = read_str(
        r#"<mujoco><include file="x.xml"/></mujoco>"#,
        "s",
        None,
        &ReadOptions::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("no folder"), "{e}");
}

#[test]
fn a_fromto_capsule_has_the_exact_mass_ends_and_inertia_of_a_capsule() {
    // From (0.1, 0, 0.2) to (0.5, 0, 0.5): length 0.5, half-length h = 0.25, r = 0.05.
    let m = read(&one_body(
        "",
        r#"<geom type="capsule" fromto="0.1 0 0.2 0.5 0 0.5" size="0.05" density="800"/>"#,
    ));
    let (a, b) = capsule_ends(&m);
    let ends = [Vec2::new(0.1, 0.2), Vec2::new(0.5, 0.5)];
    assert!(
        (near(a, ends[0]) && near(b, ends[1])) || (near(a, ends[1]) && near(b, ends[0])),
        "{a:?} {b:?}"
    );
    let (r, h) = (0.05_f64, 0.25_f64);
    let (cylinder, spheres) = (
        800.0 * PI * r * r * 2.0 * h,
        800.0 * 4.0 / 3.0 * PI * r.powi(3),
    );
    let mass = cylinder + spheres;
    // About a transverse axis through the centre: the cylinder's, and the two hemispheres'
    // (2r²/5 about their centre of curvature, which is h from the middle, with their
    // centroids 3r/8 beyond it).
    let inertia = cylinder * (3.0 * r * r + 4.0 * h * h) / 12.0
        + spheres * (2.0 * r * r / 5.0 + h * h + 3.0 * h * r / 4.0);
    let body = &m.bodies[0];
    assert!((body.mass - mass).abs() < 1e-12 * mass);
    assert!(
        (body.inertia - inertia).abs() < 1e-12 * inertia,
        "{} against {inertia}",
        body.inertia
    );
    assert!(near(body.com, Vec2::new(0.3, 0.35)));
}

#[test]
fn solids_seen_end_on_and_side_on_have_their_closed_form_inertias() {
    let cases = [
        // (geom, mass, in-plane inertia about the normal through the centre)
        (
            r#"type="sphere" size="0.2" mass="2""#,
            2.0,
            0.4 * 2.0 * 0.04,
        ),
        (
            r#"type="box" size="0.1 0.2 0.3" mass="3""#,
            3.0,
            3.0 * (0.01 + 0.09) / 3.0,
        ), // y is the normal
        (
            r#"type="cylinder" size="0.1 0.3" mass="2" zaxis="0 1 0""#,
            2.0,
            2.0 * 0.01 / 2.0,
        ), // end on: a disc
        (
            r#"type="cylinder" size="0.1 0.3" mass="2""#,
            2.0,
            2.0 * (3.0 * 0.01 + 0.36) / 12.0,
        ),
        (
            r#"type="ellipsoid" size="0.1 0.2 0.3" mass="5""#,
            5.0,
            5.0 * (0.01 + 0.09) / 5.0,
        ),
    ];
    for (geom, mass, inertia) in cases {
        let m = read(&one_body("", &format!("<geom {geom}/>")));
        let b = &m.bodies[0];
        assert!(
            (b.mass - mass).abs() < 1e-15 && (b.inertia - inertia).abs() < 1e-14,
            "{geom}: {} {}",
            b.mass,
            b.inertia
        );
    }
    let m = read(&one_body(
        "",
        r#"<geom type="cylinder" size="0.1 0.3" zaxis="0 1 0"/>"#,
    ));
    assert!(matches!(m.geoms[0].shape, Shape::Circle { radius, .. } if radius == 0.1));
    let m = read(&one_body(
        "",
        r#"<geom type="ellipsoid" size="0.1 0.2 0.3" euler="0 90 0"/>"#,
    ));
    let Shape::Ellipse {
        semi_axes, angle, ..
    } = m.geoms[0].shape
    else {
        panic!()
    };
    assert_eq!(semi_axes, [0.1, 0.3]);
    assert!(
        (angle + PI / 2.0).abs() < 1e-12,
        "x turned by 90° about y points down: {angle}"
    );
}

#[test]
fn jointless_bodies_are_welded_with_the_parallel_axis_theorem() {
    // Two point-like spheres of 1 kg at ±0.5 on x, one in a welded child: com at 0, and
    // I = 2 (2/5 m r² + m d²).
    let xml = r#"<mujoco><worldbody><body name="a"><joint axis="0 1 0"/>
        <geom size="0.01" mass="1" pos="-0.5 0 0"/>
        <body name="w" pos="0.5 0 0"><geom size="0.01" mass="1"/></body>
      </body>
      <body name="static" pos="0 0 -1"><geom size="0.1" mass="9"/></body>
    </worldbody></mujoco>"#;
    let m = read(xml);
    assert_eq!(m.bodies.len(), 1);
    let b = &m.bodies[0];
    assert_eq!(
        b.parts.iter().map(|p| p.name.as_str()).collect::<Vec<_>>(),
        ["a", "w"]
    );
    assert!(b.mass == 2.0 && b.com.norm() < 1e-15);
    assert!((b.inertia - 2.0 * (0.4 * 1e-4 + 0.25)).abs() < 1e-15);
    assert!(m.world.iter().any(|p| p.name == "static"));
    assert_eq!(m.geoms.iter().filter(|g| g.body.is_none()).count(), 1);
}

#[test]
fn an_inertial_overrides_geoms_unless_inertiafromgeom_is_true() {
    let inertial =
        r#"<inertial pos="0 0 0.1" mass="4" diaginertia="1 2 3"/><geom size="0.1" mass="1"/>"#;
    let m = read(&one_body("", inertial));
    assert_eq!((m.bodies[0].mass, m.bodies[0].inertia), (4.0, 2.0)); // y is the normal
    assert!(near(m.bodies[0].com, Vec2::new(0.0, 0.1)));
    let m = read(&one_body(r#"inertiafromgeom="true""#, inertial));
    assert_eq!(m.bodies[0].mass, 1.0);
    let m = read(&one_body(
        "",
        r#"<inertial pos="0 0 0" mass="1" fullinertia="1 2 3 0.1 0.2 0.3"/>"#,
    ));
    assert_eq!(m.bodies[0].inertia, 2.0);
}

#[test]
fn the_plane_is_found_from_the_joints() {
    // Reacher's: hinges about z, the x–y plane, e1 = x, e2 = y.
    let xml = r#"<mujoco><worldbody><body><joint axis="0 0 1"/><geom size="0.1"/>
        <body pos="0.1 0 0"><joint axis="0 0 -1"/><geom size="0.1"/></body></body></worldbody></mujoco>"#;
    let m = read(xml);
    assert_eq!(
        (m.plane.normal.z, m.plane.e1.x, m.plane.e2.y),
        (1.0, 1.0, 1.0)
    );
    assert_eq!(
        m.joints.iter().map(|j| j.sign).collect::<Vec<_>>(),
        [1.0, -1.0]
    );
    assert!(near(m.bodies[1].origin, Vec2::new(0.1, 0.0)));
    // The y–z plane: hinges about x; e2 is z (up) and e1 = e2 × n is +y.
    let m = read(
        r#"<mujoco><worldbody><body><joint axis="1 0 0"/><geom size="0.1"/></body></worldbody></mujoco>"#,
    );
    assert_eq!(
        (m.plane.e1.y, m.plane.e2.z, m.plane.normal.x),
        (1.0, 1.0, 1.0)
    );
    assert_eq!(m.joints[0].sign, 1.0);
    // Slides only: the plane of two slides.
    let m = read(
        r#"<mujoco><worldbody><body><joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 0 1"/><geom size="0.1"/></body></worldbody></mujoco>"#,
    );
    assert_eq!(m.plane.normal.y.abs(), 1.0);
}

#[test]
fn a_model_that_leaves_the_plane_is_a_located_error_naming_the_joint_or_geom() {
    let e = fails("<mujoco><worldbody><body><joint name=\"a\" axis=\"0 1 0\"/><geom size=\"0.1\"/>\n<body><joint name=\"b\" axis=\"1 0 0\"/><geom size=\"0.1\"/></body></body></worldbody></mujoco>");
    assert!(
        e.location.line == 2 && e.to_string().contains("joint `b` leaves the plane"),
        "{e}"
    );
    let e = fails(
        r#"<mujoco><worldbody><body><joint axis="0 1 0"/><joint name="s" type="slide" axis="0 1 0"/><geom size="0.1"/></body></worldbody></mujoco>"#,
    );
    assert!(e.to_string().contains("joint `s` leaves the plane"), "{e}");
    let e = fails(&one_body(
        "",
        r#"<geom name="tilted" type="capsule" size="0.1 0.2" euler="20 0 0"/>"#,
    ));
    assert!(
        e.to_string().contains("geom `tilted` leaves the plane"),
        "{e}"
    );
    // A free joint is 3-D motion.
    let e = fails(
        r#"<mujoco><worldbody><body><freejoint/><geom size="0.1"/></body></worldbody></mujoco>"#,
    );
    assert!(e.to_string().contains("free joint"), "{e}");
}

#[test]
fn joints_take_mujocos_units_order_and_reference() {
    // Walker's root order (rootz, rootx, rooty), degrees for hinges only.
    let xml = r#"<mujoco><worldbody><body pos="0 0 1.25">
        <joint name="rootz" type="slide" axis="0 0 1" ref="1.25" pos="0 0 -1.25"/>
        <joint name="rootx" type="slide" axis="1 0 0" range="-2 2"/>
        <joint name="rooty" axis="0 1 0" range="-90 45" ref="10" springref="20" stiffness="3"/>
        <geom size="0.1"/></body></worldbody></mujoco>"#;
    let m = read(xml);
    let names: Vec<(&str, usize)> = m.joints.iter().map(|j| (j.name.as_str(), j.qpos)).collect();
    assert_eq!(names, [("rootz", 0), ("rootx", 1), ("rooty", 2)]);
    assert!(
        matches!(m.joints[0].kind, JointKind::Slide { axis } if near(axis, Vec2::new(0.0, 1.0)))
    );
    assert!(near(m.joints[0].anchor, Vec2::new(0.0, -1.25)));
    assert_eq!(m.joints[0].reference, 1.25);
    assert_eq!(m.joints[1].range, Some([-2.0, 2.0]));
    let d = PI / 180.0;
    let r = &m.joints[2];
    assert_eq!(
        (r.range, r.reference, r.spring_reference, r.stiffness),
        (Some([-90.0 * d, 45.0 * d]), 10.0 * d, 20.0 * d, 3.0)
    );
    assert_eq!(r.sign, -1.0);
    // limited without a range is an error; a range without limited needs autolimits.
    let e = fails(&one_body("", "").replace(r#"axis="0 -1 0""#, r#"axis="0 -1 0" limited="true""#));
    assert!(e.to_string().contains("lower bound below"), "{e}");
    let e = fails(
        &one_body(r#"autolimits="false""#, "")
            .replace(r#"axis="0 -1 0""#, r#"axis="0 -1 0" range="0 1""#),
    );
    assert!(e.to_string().contains("autolimits"), "{e}");
}

#[test]
fn actuators_read_their_kinds_gears_and_ranges() {
    let xml = r#"<mujoco><default><motor ctrlrange="-1 1"/></default><worldbody><body><joint name="j" axis="0 1 0"/><geom size="0.1"/></body></worldbody>
      <actuator><motor joint="j" gear="50"/><position joint="j" kp="10" kv="2" forcerange="-3 3"/><velocity joint="j" kv="4" ctrllimited="false"/></actuator></mujoco>"#;
    let m = read(xml);
    let a = &m.actuators;
    assert_eq!(
        (a[0].kind, a[0].gear, a[0].ctrl_range),
        (ActuatorKind::Motor, 50.0, Some([-1.0, 1.0]))
    );
    assert_eq!(
        (a[1].kind, a[1].force_range),
        (
            ActuatorKind::Position { kp: 10.0, kv: 2.0 },
            Some([-3.0, 3.0])
        )
    );
    assert_eq!(
        (a[2].kind, a[2].ctrl_range),
        (ActuatorKind::Velocity { kv: 4.0 }, None)
    );
    let e = fails(r#"<mujoco><worldbody/><actuator><motor joint="nope"/></actuator></mujoco>"#);
    assert!(e.to_string().contains("no joint named `nope`"), "{e}");
    let e = fails(r#"<mujoco><actuator><general joint="j"/></actuator></mujoco>"#);
    assert!(e.to_string().contains("only <motor>"), "{e}");
}

#[test]
fn options_flags_and_notices() {
    let xml = r#"<mujoco><option timestep="0.005" gravity="1e-5 0 -9.81" integrator="RK4"><flag contact="disable" energy="enable"/></option>
      <worldbody><geom type="plane" size="1 1 1" solref="0.02 1"/><body><joint axis="0 1 0"/><geom size="0.1"/></body></worldbody></mujoco>"#;
    let m = read(xml);
    assert_eq!(m.options.timestep, 0.005);
    assert!(near(m.options.gravity, Vec2::new(1e-5, -9.81)));
    assert!(!m.options.contact && m.options.limits);
    let kinds: Vec<(NoticeKind, &str)> = m
        .notices
        .iter()
        .map(|n| (n.kind, n.subject.attribute.as_deref().unwrap_or("")))
        .collect();
    assert!(
        kinds.contains(&(NoticeKind::Ignored, "integrator"))
            && kinds.contains(&(NoticeKind::NotApplicable, "solref")),
        "{kinds:?}"
    );
    assert!(
        matches!(m.geoms[0].shape, Shape::Line { normal, .. } if near(normal, Vec2::new(0.0, 1.0)))
    );
    let m =
        read(r#"<mujoco><option><flag constraint="disable" gravity="disable"/></option></mujoco>"#);
    assert!(
        !m.options.contact
            && !m.options.limits
            && !m.options.frictionloss
            && m.options.gravity == Vec2::zeros()
    );
}

#[test]
fn physics_outside_the_subset_is_an_error_unless_allowed() {
    let e = fails("<mujoco>\n  <equality><joint joint1=\"a\" joint2=\"b\"/></equality></mujoco>");
    assert!(
        e.location.line == 2 && e.to_string().contains("polynomial coupling"),
        "{e}"
    );
    let viscous = r#"<mujoco><option viscosity="0.1"/></mujoco>"#;
    let e = fails(viscous);
    assert!(
        e.to_string()
            .contains("<option> attribute `viscosity`: not supported: fluid"),
        "{e}"
    );
    let m = read_str(viscous, "v.xml", None, &ReadOptions { unmodelled: true }).unwrap();
    assert_eq!(m.notices[0].kind, NoticeKind::Unmodelled);
    let e = fails(&one_body("", r#"<geom type="mesh" mesh="m"/>"#));
    assert!(e.to_string().contains("mesh"), "{e}");
    let e = fails(&one_body("", r#"<geom size="0.1" gravcomp="1"/>"#));
    assert!(e.to_string().contains("unknown attribute"), "{e}");
    let e = fails(r#"<mujoco><worldbody><body gravcomp="1"/></worldbody></mujoco>"#);
    assert!(
        e.to_string()
            .contains("not supported: gravity compensation"),
        "{e}"
    );
    read(r#"<mujoco><worldbody><body gravcomp="0"/></worldbody></mujoco>"#);
    let e = fails(
        r#"<mujoco><worldbody><geom type="plane" size="1 1 1"/><body><joint axis="0 0 1"/><geom size="0.1"/></body></worldbody></mujoco>"#,
    );
    assert!(
        e.to_string().contains("parallel to the plane of motion"),
        "{e}"
    );
}

#[test]
fn names_are_unique() {
    let e = fails("<mujoco><worldbody><body><joint name=\"j\" axis=\"0 1 0\"/><geom size=\"0.1\"/>\n<body><joint name=\"j\" axis=\"0 1 0\"/><geom size=\"0.1\"/></body></body></worldbody></mujoco>");
    assert!(
        e.location.line == 2 && e.to_string().contains("a second joint named `j`"),
        "{e}"
    );
    let e = fails(r#"<mujoco><worldbody><body name="world"/></worldbody></mujoco>"#);
    assert!(e.to_string().contains("a second body named `world`"), "{e}");
}

#[test]
fn malformed_files_are_located() {
    let e = fails("<mujoco>\n  <worldbody>\n    <body pos=\"0 0\"/>\n  </worldbody>\n</mujoco>");
    assert_eq!((e.location.line, e.location.column), (3, 11), "{e}");
    assert!(
        e.to_string()
            .contains("<body> attribute `pos`: expected 3 numbers, found 2"),
        "{e}"
    );
    let e = fails("<mujoco>\n  <worldbody>\n</mujoco>");
    assert!(e.location.line == 3 && e.subject.is_none(), "{e}");
    let e = fails(r#"<mujoco><worldbody><body pos="0 0 nan"/></worldbody></mujoco>"#);
    assert!(e.to_string().contains("finite numbers"), "{e}");
    let e = fails("<robot/>");
    assert!(e.to_string().contains("<mujoco>"), "{e}");
}

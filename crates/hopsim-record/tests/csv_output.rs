//! CSV output: header with units, one row per frame with exact numbers, events file.

mod common;

use common::{events, feed, frames, info};
use hopsim_record::{CsvRecorder, Recorder};

#[test]
fn csv_has_one_row_per_frame_with_units_in_the_header() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.csv");
    let (frames, events) = (frames(7), events());
    let mut recorder = Box::new(CsvRecorder::create(&path, &info()).unwrap());
    feed(recorder.as_mut(), &frames, &events);
    recorder.finish().unwrap();

    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t_s,step,x_m,y_m,phi_rad,psi_rad,x_dot_m_s,y_dot_m_s,phi_dot_rad_s,psi_dot_rad_s,\
         com_x_m,com_y_m,kinetic_J,potential_J,spring_J,actuator_work_J,dissipated_J,\
         balance_error_J,actuator_torque_Nm,control_flywheel_motor,effort_flywheel_motor_Nm"
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), frames.len());
    for (row, f) in rows.iter().zip(&frames) {
        assert_eq!(row.len(), 21);
        let number = |i: usize| row[i].parse::<f64>().unwrap();
        assert_eq!(number(0), f.t);
        assert_eq!(row[1], f.step.to_string());
        let e = f.energy;
        let expected = f.q.iter().chain(&f.u).chain(&f.com).copied().chain([
            e.kinetic,
            e.potential,
            e.spring,
            e.actuator_work,
            e.dissipated,
            e.balance_error,
            f.actuator_torque,
            f.controls[0],
            f.actuator_efforts[0],
        ]);
        for (i, x) in expected.enumerate() {
            assert_eq!(number(i + 2).to_bits(), x.to_bits(), "column {}", i + 2);
        }
    }

    let events_text = std::fs::read_to_string(dir.path().join("run.events.csv")).unwrap();
    let lines: Vec<&str> = events_text.lines().collect();
    assert_eq!(lines[0], "t_s,step,kind,details");
    assert_eq!(lines.len(), 1 + events.len());
    assert_eq!(lines[1], format!("{:?},11,take_off,", events[0].t));
    assert_eq!(
        lines[2],
        format!("{:?},21,touchdown,contact=disc/ground", events[1].t)
    );
    assert_eq!(
        lines[3],
        format!("{:?},31,brake,impulse_Nms=0.059", events[2].t)
    );
    assert_eq!(
        lines[4],
        format!("{:?},41,shape_switch,shape=cane active=false", events[3].t)
    );
}

#[test]
fn names_with_commas_are_quoted() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("odd.csv");
    let mut info = info();
    info.coordinates[2] = "phi,body".into();
    let recorder = Box::new(CsvRecorder::create(&path, &info).unwrap());
    recorder.finish().unwrap();
    let header = std::fs::read_to_string(&path).unwrap();
    assert!(
        header.starts_with("t_s,step,x_m,y_m,\"phi,body_rad\","),
        "{header}"
    );
    assert_eq!(
        CsvRecorder::events_path(&path),
        dir.path().join("odd.events.csv")
    );
}

//! The recording's layout (blueprint): which views the viewer opens with.

use super::columns::{
    scene_series, Series, PLOT_ANGLE, PLOT_BALANCE, PLOT_ENERGY, PLOT_IMPULSE, PLOT_NORMAL_IMPULSE,
    PLOT_POSITION, PLOT_TANGENT_IMPULSE,
};
use super::{EVENTS_ENTITY, TIME_TIMELINE};
use crate::RecordingInfo;
use rerun::blueprint::{
    Blueprint, ContainerLike, Horizontal, Spatial2DView, TextLogView, TimePanel, TimeSeriesView,
    Vertical,
};
use rerun::RecordingStreamBuilder;

/// Application id and blueprint shared by file and viewer recordings.
pub(super) fn builder(info: &RecordingInfo) -> RecordingStreamBuilder {
    RecordingStreamBuilder::new("hopsim")
        .recording_name(info.scene.clone())
        .enabled(true)
        .with_blueprint(blueprint(&scene_series(info)))
}

/// Title of the panel of a time-series entity, with its unit.
pub(super) fn panel_title(entity: &str) -> &'static str {
    match entity {
        PLOT_POSITION => "position, m",
        PLOT_ANGLE => "angles wrapped to (−π, π], rad",
        PLOT_ENERGY => "energy, J",
        PLOT_BALANCE => "energy balance error, J",
        PLOT_NORMAL_IMPULSE | PLOT_TANGENT_IMPULSE => "contact impulses Λ_N, Λ_T, N s",
        _ => "actuator torque, N m",
    }
}

/// The robot on the left; on the right one panel per time series the scene has (both
/// impulse components in one) and the event log; on the simulation time (the viewer
/// would otherwise pick the step timeline).
pub(super) fn blueprint(series: &[Series]) -> Blueprint {
    let mut panels: Vec<ContainerLike> = Vec::new();
    for s in series {
        let origin = match s.entity {
            PLOT_TANGENT_IMPULSE => continue,
            PLOT_NORMAL_IMPULSE => PLOT_IMPULSE,
            entity => entity,
        };
        panels.push(
            TimeSeriesView::new(panel_title(s.entity))
                .with_origin(origin)
                .into(),
        );
    }
    panels.push(TextLogView::new("events").with_origin(EVENTS_ENTITY).into());
    let robot = Spatial2DView::new("robot")
        .with_origin("/")
        .with_contents(["/world/**"]);
    let right = Vertical::new(panels);
    Blueprint::new(Horizontal::new([robot.into(), right.into()]).with_column_shares([2.0_f32, 1.0]))
        .with_time_panel(TimePanel::new().with_timeline(TIME_TIMELINE))
}

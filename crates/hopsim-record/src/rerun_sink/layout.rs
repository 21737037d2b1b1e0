//! The recording's layout (blueprint): which views the viewer opens with.
//!
//! On the left the robot large, in a view centred on its centre of mass (`world/com/view`,
//! bounds a few robot sizes wide), above the whole track; on the right one panel per time
//! series the scene has and the event log; the time panel on the simulation time.
//!
//! The SDK's blueprint builder cannot set a 2D view's bounds, so the blueprint's entities
//! (containers, views and their properties, the viewport, the time panel) are logged here
//! to a blueprint store of their own and sent ahead of the recording's data, as the SDK
//! sends its own.

use super::columns::{
    Series, PLOT_ANGLE, PLOT_BALANCE, PLOT_CONTROLS, PLOT_EFFORTS, PLOT_ENERGY, PLOT_POSITION,
};
use super::drawing::{CONTACTS_ENTITY, ROBOT_VIEW_ENTITY};
use super::{EVENTS_ENTITY, TIME_TIMELINE};
use rerun::blueprint::components::{
    ColumnShare, ContainerKind, IncludedContent, QueryExpression, RootContainer, RowShare,
    ViewClass,
};
use rerun::external::re_log_types::{BlueprintActivationCommand, RecordingId};
use rerun::external::re_sdk_types::blueprint::archetypes::{
    ContainerBlueprint, TimePanelBlueprint, ViewBlueprint, ViewContents, ViewportBlueprint,
    VisualBounds2D,
};
use rerun::external::re_sdk_types::datatypes::{Range1D, Range2D};
use rerun::{AsComponents, RecordingStream, RecordingStreamBuilder};

/// Application id of every hopsim recording (the viewer keeps one layout per id).
pub(super) const APPLICATION_ID: &str = "hopsim";
/// The robot view's half width and half height, in robot extents (the largest distance of
/// a shape from the robot's centre of mass at the first frame).
const ROBOT_VIEW_HALF_SIZE: [f64; 2] = [2.5, 1.6];

/// Title of the panel of a time-series entity, with its unit.
pub(super) fn panel_title(entity: &str) -> &'static str {
    match entity {
        PLOT_POSITION => "position, m",
        PLOT_ANGLE => "angles wrapped to (−π, π], rad",
        PLOT_ENERGY => "energy, J",
        PLOT_BALANCE => "energy balance error, J",
        CONTACTS_ENTITY => "contact impulses Λ_N, Λ_T, N s",
        "plots/actuator_force_N" => "actuator force, N",
        PLOT_CONTROLS => "actuator controls",
        PLOT_EFFORTS => "actuator efforts: torque, N m, or force, N",
        _ => "actuator torque, N m",
    }
}

/// The bounds of the robot view around the centre of mass for a robot of `extent_m`, m:
/// `[[x_min, x_max], [y_min, y_max]]` in the frame of `world/com`.
pub(super) fn robot_view_bounds(extent_m: f64) -> [[f64; 2]; 2] {
    ROBOT_VIEW_HALF_SIZE.map(|h| [-h * extent_m, h * extent_m])
}

/// Sends the layout to `stream` and makes it the active one: the robot view with the
/// bounds of [`robot_view_bounds`] for `extent_m`, the panels of `series`.
pub(super) fn send_layout(
    stream: &RecordingStream,
    series: &[Series],
    extent_m: f64,
) -> Result<(), String> {
    let text = |e: &dyn std::fmt::Display| e.to_string();
    let (store, storage) = RecordingStreamBuilder::new(APPLICATION_ID)
        .recording_id(RecordingId::random())
        .blueprint()
        .memory()
        .map_err(|e| text(&e))?;
    store.set_time_sequence("blueprint", 0);
    let mut layout = Layout {
        store: &store,
        next_id: 0,
    };
    layout.log_all(series, extent_m).map_err(|e| text(&e))?;
    let messages = storage.take();
    let blueprint_id = messages
        .first()
        .map(|m| m.store_id().clone())
        .ok_or("the layout has no messages")?;
    stream.send_blueprint(
        messages,
        BlueprintActivationCommand {
            blueprint_id,
            make_active: true,
            make_default: true,
        },
    );
    Ok(())
}

/// Logs the blueprint's entities to its store, numbering containers and views.
struct Layout<'a> {
    store: &'a RecordingStream,
    next_id: u8,
}

type Logged<T> = Result<T, rerun::RecordingStreamError>;

impl Layout<'_> {
    fn log_all(&mut self, series: &[Series], extent_m: f64) -> Logged<()> {
        let robot = self.view(
            "2D",
            "robot (view centred on its centre of mass)",
            &format!("/{ROBOT_VIEW_ENTITY}"),
        )?;
        let [x, y] = robot_view_bounds(extent_m);
        let bounds = Range2D {
            x_range: Range1D(x),
            y_range: Range1D(y),
        };
        self.log(
            &format!("{}/VisualBounds2D", robot.0),
            &VisualBounds2D::new(bounds),
        )?;
        let track = self.view("2D", "whole track", "/")?;
        let left = self.container(ContainerKind::Vertical, [robot, track], &[3.0, 1.0])?;
        let mut panels = Vec::new();
        for s in series {
            let view = self.view(
                "TimeSeries",
                panel_title(s.entity),
                &format!("/{}", s.entity),
            )?;
            panels.push(view);
        }
        panels.push(self.view("TextLog", "events", &format!("/{EVENTS_ENTITY}"))?);
        let right = self.container(ContainerKind::Vertical, panels, &[])?;
        let root = self.container(ContainerKind::Horizontal, [left, right], &[2.0, 1.0])?;
        let root = RootContainer(root.1.into());
        self.log(
            "viewport",
            &ViewportBlueprint::new().with_root_container(root),
        )?;
        self.log(
            "time_panel",
            &TimePanelBlueprint::new().with_timeline(TIME_TIMELINE),
        )
    }

    fn log(&self, path: &str, what: &impl AsComponents) -> Logged<()> {
        self.store.log(path, what)
    }

    /// A fresh id: its entity-path text (a UUID's form) and bytes.
    fn id(&mut self) -> (String, [u8; 16]) {
        self.next_id += 1;
        let mut bytes = *b"hopsim-layout-\x40\x00";
        bytes[15] = self.next_id;
        let hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
        let text = [
            &hex[..8],
            &hex[8..12],
            &hex[12..16],
            &hex[16..20],
            &hex[20..],
        ]
        .join("-");
        (text, bytes)
    }

    /// A view of `class` showing the world (2D views) or `origin` and below.
    fn view(&mut self, class: &str, name: &str, origin: &str) -> Logged<(String, [u8; 16])> {
        let (id, bytes) = self.id();
        let path = format!("view/{id}");
        let contents = if class == "2D" {
            "/world/**"
        } else {
            "$origin/**"
        };
        self.log(
            &format!("{path}/ViewContents"),
            &ViewContents::new([QueryExpression(contents.into())]),
        )?;
        self.log(
            &path,
            &ViewBlueprint::new(ViewClass(class.into()))
                .with_display_name(name)
                .with_space_origin(origin),
        )?;
        Ok((path, bytes))
    }

    /// A container of `kind` holding `children`, sized by `shares` (none: equal).
    fn container(
        &mut self,
        kind: ContainerKind,
        children: impl IntoIterator<Item = (String, [u8; 16])>,
        shares: &[f32],
    ) -> Logged<(String, [u8; 16])> {
        let (id, bytes) = self.id();
        let path = format!("container/{id}");
        let contents = children
            .into_iter()
            .map(|(child, _)| IncludedContent(child.as_str().into()));
        let mut container = ContainerBlueprint::new(kind).with_contents(contents);
        if !shares.is_empty() {
            container = match kind {
                ContainerKind::Horizontal => {
                    container.with_col_shares(shares.iter().map(|&s| ColumnShare(s.into())))
                }
                _ => container.with_row_shares(shares.iter().map(|&s| RowShare(s.into()))),
            };
        }
        self.log(&path, &container)?;
        Ok((path, bytes))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_ids_are_distinct_uuids() {
        let (store, _storage) = RecordingStreamBuilder::new(APPLICATION_ID)
            .blueprint()
            .memory()
            .unwrap();
        let mut layout = Layout {
            store: &store,
            next_id: 0,
        };
        let (a, bytes) = layout.id();
        let (b, _) = layout.id();
        assert_ne!(a, b);
        let parts: Vec<usize> = a.split('-').map(str::len).collect();
        assert_eq!(parts, [8, 4, 4, 4, 12], "{a}");
        assert_eq!(a.replace('-', "").len(), 2 * bytes.len());
    }
}

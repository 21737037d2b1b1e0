//! Plots are written as PNG and SVG, atomically, with rendered text.

use hopsim_studies::plot::{
    free_legend_place, robust_range, write_png_and_svg, CategoryMap, ColourScale, Figure, Heatmap,
    LinePlot, Series, SeriesStyle, Typeset,
};
use plotters::prelude::*;

/// The figure drawn into an RGB buffer.
fn render<F: Figure>(figure: &F) -> (u32, u32, Vec<u8>) {
    let (w, h) = figure.size();
    let mut buffer = vec![0u8; (w * h * 3) as usize];
    {
        let backend = BitMapBackend::with_buffer(&mut buffer, (w, h));
        let root = Typeset::raster(backend).into_drawing_area();
        figure.draw(&root).unwrap();
        root.present().unwrap();
    }
    (w, h, buffer)
}

fn is_dark(px: &[u8]) -> bool {
    px.iter().all(|&c| c < 128)
}

/// Dark pixels in the rows `rows` and columns `columns` of the rendered figure.
fn dark_pixels<F: Figure>(
    figure: &F,
    rows: std::ops::Range<u32>,
    columns: std::ops::Range<u32>,
) -> usize {
    let (w, _, buffer) = render(figure);
    rows.flat_map(|y| columns.clone().map(move |x| (y * w + x) as usize * 3))
        .filter(|&i| is_dark(&buffer[i..i + 3]))
        .count()
}

/// The caption's band: the top 1/16 of the figure.
fn title_band<F: Figure>(figure: &F) -> std::ops::Range<u32> {
    0..figure.size().1 / 16
}

#[test]
fn captions_render_with_a_font() {
    let line = || Series::line("s", vec![(0.0, 0.0), (1.0, 1.0)]).unlabelled();
    let with_title = LinePlot::new("A caption with text φ", "x", "y").with_series(line());
    let without = LinePlot::new("", "x", "y").with_series(line());
    // The middle third of the caption's band: the title, not the y axis.
    let w = with_title.size().0;
    let text = dark_pixels(&with_title, title_band(&with_title), w / 3..2 * w / 3);
    assert!(text > 500, "caption drew {text} dark pixels");
    let none = dark_pixels(&without, title_band(&without), w / 3..2 * w / 3);
    assert!(none < text / 4, "{none} dark pixels without a caption");
}

/// A title longer than the figure is wide is wrapped onto several lines, none reaching the
/// figure's edges.
#[test]
fn long_titles_wrap_inside_the_figure() {
    let words =
        "kangaroo rat: stride against dimensionless speed (ΔE 0.001…0.05 J; ×: not converged)";
    let title = format!("{words} {words}");
    let plot = LinePlot::new(title, "x (m)", "y (m)")
        .with_series(Series::line("s", vec![(0.0, 0.0), (1.0, 1.0)]));
    let (w, h, buffer) = render(&plot);
    let edge = w / 100;
    let rows_with_text: Vec<u32> = (0..h / 5)
        .filter(|&y| {
            (0..w).any(|x| {
                let i = (y * w + x) as usize * 3;
                is_dark(&buffer[i..i + 3])
            })
        })
        .collect();
    // Nothing drawn at the left and right edges of the top fifth (the axes start lower).
    assert_eq!(dark_pixels(&plot, 0..h / 8, 0..edge), 0);
    assert_eq!(dark_pixels(&plot, 0..h / 8, w - edge..w), 0);
    // Two lines of text: a gap of blank rows between two runs of text rows.
    let runs = rows_with_text
        .windows(2)
        .filter(|p| p[1] > p[0] + 1)
        .count()
        + 1;
    assert!(runs >= 2, "title rows {rows_with_text:?}");
}

/// A heatmap's colour bar says when values lie beyond its colour range (`≥ 2` at the top,
/// `≤ 0.5` at the bottom) and nothing when none does; a diverging scale ticks its centre.
#[test]
fn colour_bars_mark_values_beyond_their_range() {
    let map = |values: Vec<Option<f64>>| {
        Heatmap::new("m", "x", "y", "v", vec![0.0, 1.0], vec![0.0, 1.0], values)
    };
    let labels = |h: &Heatmap| -> Vec<String> {
        h.colour_bar_labels().into_iter().map(|(_, l)| l).collect()
    };
    let capped = map(vec![Some(0.6), Some(1.0), Some(1.5), Some(5.0)]).with_value_range(0.6, 2.0);
    let all = labels(&capped);
    assert_eq!(all.last().map(String::as_str), Some("≥ 2"), "{all:?}");
    assert!(all.iter().all(|l| !l.starts_with('≤')), "{all:?}");
    let below = map(vec![Some(0.1), Some(1.0), Some(1.5), Some(2.0)]).with_value_range(0.5, 2.0);
    assert_eq!(labels(&below)[0], "≤ 0.5");
    // Values within the range: plain ticks, every one inside it.
    let plain = map(vec![Some(0.6), Some(1.0), Some(1.5), Some(2.0)]);
    let ticks = plain.colour_bar_labels();
    assert!(ticks
        .iter()
        .all(|(v, l)| (0.6..=2.0).contains(v) && !l.contains(['≥', '≤'])));
    // A diverging scale about 1 reaches 1 and labels it.
    let diverging = map(vec![Some(0.3), Some(0.45), Some(0.7), Some(0.8)])
        .with_colour_scale(ColourScale::Diverging { centre: 1.0 });
    assert_eq!(diverging.colour_range(), (0.3, 1.0));
    assert!(diverging
        .colour_bar_labels()
        .contains(&(1.0, "1".to_string())));
}

/// One far outlier does not stretch the range; a spread of data does.
#[test]
fn robust_ranges_leave_out_far_outliers_only() {
    let mut values: Vec<f64> = (0..100).map(|i| 0.1 + 0.001 * f64::from(i)).collect();
    assert_eq!(robust_range(values.iter().copied()), Some((0.1, 0.199)));
    values.push(8.7);
    assert_eq!(robust_range(values.iter().copied()), Some((0.1, 0.199)));
    // A peak just above the rest is data, even beyond the fences.
    let mut peaked: Vec<f64> = (0..100).map(|i| 0.1 + 0.001 * f64::from(i)).collect();
    peaked.push(0.25);
    assert_eq!(robust_range(peaked.iter().copied()), Some((0.1, 0.25)));
    // Two clusters far apart are both data: the range covers them.
    let clusters: Vec<f64> = (0..50).map(|i| f64::from(i % 2) * 10.0).collect();
    assert_eq!(robust_range(clusters.into_iter()), Some((0.0, 10.0)));
    assert_eq!(robust_range([f64::NAN].into_iter()), None);
}

/// A legend goes where it covers no data point, or nowhere inside the plot.
#[test]
fn legends_avoid_the_data() {
    let (dim, size) = ((1000, 600), (200, 100));
    // Data in the upper right: the legend moves to the upper left.
    let place = free_legend_place(dim, size, &[(900, 50)]).unwrap();
    assert!(place.0 < 500 && place.1 < 300, "{place:?}");
    // Data everywhere: no place inside.
    let everywhere: Vec<(i32, i32)> = (0..1000)
        .step_by(20)
        .flat_map(|x| (0..600).step_by(20).map(move |y| (x, y)))
        .collect();
    assert_eq!(free_legend_place(dim, size, &everywhere), None);
}

#[test]
fn figures_are_written_as_png_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    let line = LinePlot::new("line", "x (m)", "y (m)")
        .with_series(Series::line(
            "a",
            vec![(0.0, 1.0), (f64::NAN, f64::NAN), (2.0, 3.0), (3.0, 2.0)],
        ))
        .with_series(Series::points("b", vec![(1.0, 1.5)]).style(SeriesStyle::Crosses));
    let heat = Heatmap::new(
        "heat",
        "x",
        "y",
        "value",
        vec![0.0, 1.0, 2.0],
        vec![-1.0, 0.0],
        vec![
            Some(1.0),
            None,
            Some(2.0),
            Some(f64::NAN),
            Some(0.5),
            Some(3.0),
        ],
    )
    .with_overlay(Series::points("marked", vec![(1.0, 0.0)]).style(SeriesStyle::Crosses));
    let cats = CategoryMap::new(
        "cats",
        "x",
        "y",
        vec!["a".into(), "b".into()],
        vec![0.0, 1.0],
        vec![0.0, 1.0],
        vec![Some(0), Some(1), None, Some(1)],
    );
    for (name, paths) in [
        (
            "line",
            write_png_and_svg(&line, &dir.path().join("line")).unwrap(),
        ),
        (
            "heat",
            write_png_and_svg(&heat, &dir.path().join("heat")).unwrap(),
        ),
        (
            "cats",
            write_png_and_svg(&cats, &dir.path().join("cats")).unwrap(),
        ),
    ] {
        let png = std::fs::read(&paths[0]).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n", "{name}");
        let svg = std::fs::read_to_string(&paths[1]).unwrap();
        assert!(svg.contains("<svg") && svg.contains(name), "{name}");
    }
    // Only the six figures, no temporary files left behind.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 6);
    // A malformed heatmap is an error, not a panic, and leaves nothing behind.
    let bad = Heatmap::new(
        "bad",
        "x",
        "y",
        "v",
        vec![0.0, 1.0],
        vec![0.0],
        vec![Some(1.0)],
    );
    assert!(write_png_and_svg(&bad, &dir.path().join("bad")).is_err());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 6);
}

/// Tables come before figures, and a figure never costs data: a figure that cannot be
/// drawn, listed before a CSV table and a good figure, leaves its own two files out and is
/// reported, while the table and the good figure are written (and no temporary file stays).
#[test]
fn a_figure_that_cannot_be_drawn_leaves_the_tables_written() {
    use hopsim_io::CsvTable;
    use hopsim_studies::{write_files, ReportFile};
    let dir = tempfile::tempdir().unwrap();
    let mut table = CsvTable::new(&["a"]);
    table.push(vec![1.0.into()]);
    let good = LinePlot::new("good", "x (m)", "y (m)")
        .with_series(Series::line("s", vec![(0.0, 0.0), (1.0, 1.0)]));
    // Two cell centres along x, one along y, but a single value: it cannot be drawn.
    let bad = Heatmap::new(
        "bad",
        "x",
        "y",
        "v",
        vec![0.0, 1.0],
        vec![0.0],
        vec![Some(1.0)],
    );
    let files = [
        ReportFile::figure("bad", bad),
        ReportFile::csv("table.csv", table),
        ReportFile::figure("good", good),
    ];
    let written = write_files(dir.path(), &files).unwrap();
    let names = |paths: &[std::path::PathBuf]| -> Vec<String> {
        (paths.iter())
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect()
    };
    assert_eq!(names(&written.files), ["table.csv", "good.png", "good.svg"]);
    assert_eq!(written.missing_figures.len(), 1);
    let missing = &written.missing_figures[0];
    assert_eq!(missing.figure, "bad");
    assert_eq!(names(&missing.files), ["bad.png", "bad.svg"]);
    assert!(
        missing
            .reason
            .contains("heatmap needs 2×1 = 2 values, got 1"),
        "{missing}"
    );
    let warning = missing.to_string();
    assert!(
        warning.contains("`bad`") && warning.contains("bad.svg"),
        "{warning}"
    );
    let mut on_disk: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    on_disk.sort();
    assert_eq!(on_disk, ["good.png", "good.svg", "table.csv"]);
}

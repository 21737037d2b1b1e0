//! Plots are written as PNG and SVG, atomically, with rendered text.

use hopsim_studies::plot::{
    write_png_and_svg, CategoryMap, Figure, Heatmap, LinePlot, Series, SeriesStyle,
};
use plotters::prelude::*;

fn dark_pixels_in_top_band<F: Figure>(figure: &F) -> usize {
    let (w, h) = figure.size();
    let mut buffer = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
        figure.draw(&root).unwrap();
        root.present().unwrap();
    }
    // The caption sits in the top 40 pixel rows.
    buffer[..(w * 40 * 3) as usize]
        .chunks(3)
        .filter(|px| px.iter().all(|&c| c < 128))
        .count()
}

#[test]
fn captions_render_with_a_font() {
    let with_title = LinePlot::new("A caption with text φ", "x", "y")
        .with_series(Series::line("s", vec![(0.0, 0.0), (1.0, 1.0)]));
    let without =
        LinePlot::new("", "x", "y").with_series(Series::line("s", vec![(0.0, 0.0), (1.0, 1.0)]));
    let text = dark_pixels_in_top_band(&with_title);
    assert!(text > 100, "caption drew {text} dark pixels");
    assert!(dark_pixels_in_top_band(&without) < text / 4);
}

#[test]
fn figures_are_written_as_png_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    let line = LinePlot::new("line", "x [m]", "y [m]")
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

/// A set of report files is written whole or not at all: a figure that cannot be drawn,
/// listed after a CSV table and a good figure, leaves none of them (and no temporary file).
#[test]
fn a_failed_file_leaves_none_of_its_set() {
    use hopsim_io::CsvTable;
    use hopsim_studies::{write_files, ReportFile};
    let dir = tempfile::tempdir().unwrap();
    let mut table = CsvTable::new(&["a"]);
    table.push(vec![1.0.into()]);
    let good = LinePlot::new("good", "x [m]", "y [m]")
        .with_series(Series::line("s", vec![(0.0, 0.0), (1.0, 1.0)]));
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
        ReportFile::csv("table.csv", table),
        ReportFile::figure("good", good),
        ReportFile::figure("bad", bad),
    ];
    assert!(write_files(dir.path(), &files).is_err());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    // Without the bad figure the whole set appears.
    let written = write_files(dir.path(), &files[..2]).unwrap();
    assert_eq!(written.len(), 3);
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 3);
}

//! Convergence figures: both files written whole, with the requested content and size.

use damfem::io::plot::{write_figure, Figure, Series, SIZE};
use std::fs;
use std::path::{Path, PathBuf};

/// A fresh empty directory for test `name`.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("plot").join(name);
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

fn figure(series: Vec<Series>) -> Figure {
    Figure {
        title: "Scene A: estimators".into(),
        x_label: "unknowns".into(),
        y_label: "estimator".into(),
        series,
        ..Default::default()
    }
}

fn series(label: &str, points: Vec<(f64, f64)>, dashed: bool) -> Series {
    Series { label: label.into(), points, dashed }
}

/// Sorted file names in `dir`.
fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    names.sort();
    names
}

/// Width and height from the IHDR chunk of a PNG file.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&bytes[12..16], b"IHDR");
    let word = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    (word(16), word(20))
}

/// Adaptive and uniform refinement: η ~ N^-1/2 and N^-1/4, and a component with a zero value.
fn three_series() -> Vec<Series> {
    let unknowns: [f64; 6] = [1.2e2, 5.0e2, 2.1e3, 8.4e3, 3.3e4, 1.3e5];
    let eta = unknowns.iter().map(|&n| (n, 3.0 * n.powf(-0.5))).collect();
    let uniform = unknowns.iter().map(|&n| (n, 1.5 * n.powf(-0.25))).collect();
    let mut osc: Vec<(f64, f64)> = unknowns.iter().map(|&n| (n, 20.0 / n)).collect();
    osc[2].1 = 0.0;
    osc[4].1 = -1.0e-3;
    vec![series("η adaptive", eta, false), series("η uniform", uniform, true), series("η_osc", osc, false)]
}

#[test]
fn writes_svg_and_png() {
    let dir = scratch("three");
    let stem = dir.join("estimators");
    let paths = write_figure(&stem, &figure(three_series())).unwrap();
    assert_eq!(paths, [dir.join("estimators.svg"), dir.join("estimators.png")]);
    assert_eq!(entries(&dir), ["estimators.png", "estimators.svg"]);

    let svg = fs::read_to_string(&paths[0]).unwrap();
    assert!(svg.starts_with("<svg") || svg.starts_with("<?xml"), "{}", &svg[..60]);
    assert!(svg.trim_end().ends_with("</svg>"));
    for text in ["Scene A: estimators", "unknowns", "estimator", "η adaptive", "η uniform", "η_osc", "10⁻¹"] {
        assert!(svg.contains(text), "{text} missing from the SVG");
    }
    // A solid series is one polyline and its legend sample another; a dashed one is one per dash.
    let polylines =
        |colour: &str| svg.matches(&format!("<polyline fill=\"none\" opacity=\"1\" stroke=\"{colour}\"")).count();
    assert_eq!(polylines("#1F77B4"), 2);
    assert!(polylines("#D62728") > 10, "the uniform series is not dashed");

    let png = fs::read(&paths[1]).unwrap();
    assert_eq!(png_size(&png), SIZE);
}

#[test]
fn rewriting_replaces_both_files() {
    let dir = scratch("rewrite");
    let stem = dir.join("eta");
    write_figure(&stem, &figure(three_series())).unwrap();
    write_figure(&stem, &figure(three_series()[..1].to_vec())).unwrap();
    assert_eq!(entries(&dir), ["eta.png", "eta.svg"]);
    assert!(!fs::read_to_string(dir.join("eta.svg")).unwrap().contains("η uniform"));
}

#[test]
fn degenerate_figures_are_valid_plots() {
    let dir = scratch("degenerate");
    let single = vec![series("one step", vec![(1.0e3, 0.25)], false)];
    let skipped = vec![series("nothing plottable", vec![(0.0, 1.0), (1.0, f64::NAN)], true)];
    for (name, series) in [("single", single), ("empty", Vec::new()), ("skipped", skipped)] {
        let paths = write_figure(&dir.join(name), &figure(series)).unwrap();
        assert_eq!(png_size(&fs::read(&paths[1]).unwrap()), SIZE);
    }
    assert_eq!(entries(&dir).len(), 6);
}

#[test]
fn unwritable_target_is_an_error() {
    let dir = scratch("unwritable");
    let err = write_figure(&dir.join("missing").join("eta"), &figure(three_series())).unwrap_err();
    assert!(err.to_string().contains("eta.svg"), "{err}");
    assert_eq!(entries(&dir), Vec::<String>::new());
}

//! Log–log convergence figures (estimators against unknowns or wall time) and figures on linear
//! axes (stresses along the joint), written as SVG and PNG.
//!
//! Figures are drawn with `plotters`, rendered in memory and written atomically. Both formats
//! are [`SIZE`] pixels. Log axes span at least two whole decades around the data and are
//! labelled at powers of ten; linear axes span the data with a margin. Each series gets its
//! own colour and marker, dashed series a dashed line.
//!
//! Text is laid out (for both formats) and rasterised (for PNG) with DejaVu Sans, read once per
//! process from [`FONT_PATH`] (Debian package `fonts-dejavu-core`, installed by the Makefile).
//! Its licence would allow embedding it, but it would add 760 kB to every binary. The SVG files
//! name the generic `sans-serif` family. A missing font file is an [`OutputError::Font`] naming it.

use super::atomic::{write_output, OutputError};
use plotters::chart::MeshStyle;
use plotters::coord::Shift;
use plotters::element::{DashedPathElement, DynElement};
use plotters::prelude::*;
use plotters::style::register_font;
use std::ffi::OsString;
use std::fs;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

/// Width and height of every figure, in pixels.
pub const SIZE: (u32, u32) = (960, 720);

/// The TrueType font used to lay out and draw text.
pub const FONT_PATH: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// Gap between the data and the frame before rounding out to decades, in decades.
const MARGIN: f64 = 0.05;

/// Line and marker colours, cycled over the series: series k has colour k whether or not an
/// earlier one has points, so the same list of series keeps its colours across figures.
const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// One curve: label and (x, y) points; points with non-positive or non-finite coordinates are skipped on log axes.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub dashed: bool,
}

/// A log–log figure.
///
/// A figure without any plottable point (no series, or only skipped points) is drawn as empty
/// axes over [1, 100] × [1, 100]; a single point gets two decades around it.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
}

/// Writes `<stem>.svg` and `<stem>.png` (stem is a path without extension); returns both paths.
///
/// Both images are rendered before either file is written.
pub fn write_figure(stem: &Path, figure: &Figure) -> Result<Vec<PathBuf>, OutputError> {
    write_with_axes(stem, figure, Axes::LogLog)
}

/// As [`write_figure`], on linear axes.
pub fn write_linear_figure(stem: &Path, figure: &Figure) -> Result<Vec<PathBuf>, OutputError> {
    write_with_axes(stem, figure, Axes::Linear)
}

/// The scale of both axes.
#[derive(Clone, Copy)]
enum Axes {
    LogLog,
    Linear,
}

fn write_with_axes(stem: &Path, figure: &Figure, axes: Axes) -> Result<Vec<PathBuf>, OutputError> {
    let svg_path = with_suffix(stem, ".svg");
    let png_path = with_suffix(stem, ".png");
    load_font(Path::new(FONT_PATH), &svg_path)?;
    let svg = render_svg(figure, axes).map_err(|message| OutputError::Render { path: svg_path.clone(), message })?;
    let png = render_png(figure, axes).map_err(|message| OutputError::Render { path: png_path.clone(), message })?;
    write_output(&svg_path, svg.as_bytes())?;
    write_output(&png_path, &png)?;
    Ok(vec![svg_path, png_path])
}

/// `stem` with `suffix` appended to its file name.
fn with_suffix(stem: &Path, suffix: &str) -> PathBuf {
    let mut name = OsString::from(stem.as_os_str());
    name.push(suffix);
    PathBuf::from(name)
}

/// Registers the font file `font` as `sans-serif`, once per process; errors name `path`, the
/// file about to be written.
fn load_font(font: &Path, path: &Path) -> Result<(), OutputError> {
    static LOADED: Mutex<bool> = Mutex::new(false);
    let error = |reason: String| OutputError::Font { path: path.to_path_buf(), font: font.to_path_buf(), reason };
    let mut loaded = LOADED.lock().unwrap_or_else(PoisonError::into_inner);
    if !*loaded {
        let bytes = fs::read(font).map_err(|e| error(format!("{e} (Debian package fonts-dejavu-core)")))?;
        // plotters keeps registered fonts for the whole process: the bytes live as long.
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        register_font("sans-serif", FontStyle::Normal, bytes).map_err(|_| error("not a TrueType font".into()))?;
        *loaded = true;
    }
    Ok(())
}

/// The figure as an SVG document.
fn render_svg(figure: &Figure, axes: Axes) -> Result<String, String> {
    let mut svg = String::new();
    draw(SVGBackend::with_string(&mut svg, SIZE).into_drawing_area(), figure, axes).map_err(|e| e.to_string())?;
    Ok(svg)
}

/// The figure as a PNG file (8-bit RGB).
fn render_png(figure: &Figure, axes: Axes) -> Result<Vec<u8>, String> {
    let (width, height) = SIZE;
    let mut rgb = vec![0; 3 * width as usize * height as usize];
    draw(BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area(), figure, axes).map_err(|e| e.to_string())?;
    let mut png = Vec::new();
    let mut encoder = png::Encoder::new(&mut png, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
    writer.write_image_data(&rgb).map_err(|e| e.to_string())?;
    writer.finish().map_err(|e| e.to_string())?;
    Ok(png)
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// Draws axes, series and legend on `root`.
fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, figure: &Figure, axes: Axes) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let mut builder = ChartBuilder::on(&root);
    builder.caption(&figure.title, ("sans-serif", 26)).margin(24).x_label_area_size(64).y_label_area_size(84);
    match axes {
        Axes::LogLog => {
            let points: Vec<Vec<(f64, f64)>> = figure.series.iter().map(|s| plottable(&s.points)).collect();
            let all = || points.iter().flatten();
            let (x_range, y_range) = (decades(all().map(|p| p.0)), decades(all().map(|p| p.1)));
            let mut chart = builder.build_cartesian_2d(x_range.log_scale(), y_range.log_scale())?;
            let mut mesh = chart.configure_mesh();
            mesh.x_label_formatter(&power_of_ten).y_label_formatter(&power_of_ten);
            style_mesh(&mut mesh, figure).draw()?;
            draw_all(&mut chart, figure, points)?;
        }
        Axes::Linear => {
            let points: Vec<Vec<(f64, f64)>> = figure.series.iter().map(|s| finite(&s.points)).collect();
            let all = || points.iter().flatten();
            let (x_range, y_range) = (span(all().map(|p| p.0)), span(all().map(|p| p.1)));
            let mut chart = builder.build_cartesian_2d(x_range, y_range)?;
            let mut mesh = chart.configure_mesh();
            style_mesh(&mut mesh, figure).draw()?;
            draw_all(&mut chart, figure, points)?;
        }
    }
    root.present()
}

/// Axis descriptions, label fonts and grid lines of `figure`.
fn style_mesh<'m, 'a, 'b, DB: DrawingBackend, X: Ranged, Y: Ranged>(
    mesh: &'m mut MeshStyle<'a, 'b, X, Y, DB>,
    figure: &Figure,
) -> &'m mut MeshStyle<'a, 'b, X, Y, DB> {
    mesh.x_desc(&figure.x_label)
        .y_desc(&figure.y_label)
        .label_style(("sans-serif", 18))
        .axis_desc_style(("sans-serif", 20))
        .bold_line_style(BLACK.mix(0.25))
        .light_line_style(BLACK.mix(0.07))
}

/// Every series of `figure` through its drawable `points`, and the legend.
fn draw_all<'a, DB: DrawingBackend + 'a, CT: CoordTranslate<From = (f64, f64)>>(
    chart: &mut ChartContext<'a, DB, CT>,
    figure: &Figure,
    points: Vec<Vec<(f64, f64)>>,
) -> DrawResult<DB> {
    for (index, (series, points)) in figure.series.iter().zip(points).enumerate() {
        draw_curve(chart, index, series, points)?;
    }
    if figure.series.iter().any(|s| !s.label.is_empty()) {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font(("sans-serif", 18))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.5))
            .legend_area_size(36)
            .draw()?;
    }
    Ok(())
}

/// Draws series `index` through its plottable `points`, with markers and a legend entry if
/// labelled and not empty.
fn draw_curve<'a, DB: DrawingBackend + 'a, CT: CoordTranslate<From = (f64, f64)>>(
    chart: &mut ChartContext<'a, DB, CT>,
    index: usize,
    series: &Series,
    points: Vec<(f64, f64)>,
) -> DrawResult<DB> {
    let style = PALETTE[index % PALETTE.len()].stroke_width(2);
    let dashed = series.dashed;
    let curve = if dashed {
        chart.draw_series(DashedLineSeries::new(points.clone(), 10, 6, style))?
    } else {
        chart.draw_series(LineSeries::new(points.clone(), style))?
    };
    if !series.label.is_empty() && !points.is_empty() {
        curve.label(&series.label).legend(move |(x, y)| {
            EmptyElement::at((x, y)) + line_sample(dashed, style) + marker((12, 0), index, style)
        });
    }
    chart.draw_series(points.into_iter().map(|p| EmptyElement::at(p) + marker((0, 0), index, style)))?;
    Ok(())
}

/// The points of a series that a log–log plot can show.
fn plottable(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    points.iter().copied().filter(|&(x, y)| positive(x) && positive(y)).collect()
}

/// The points of a series with finite coordinates.
fn finite(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    points.iter().copied().filter(|&(x, y)| x.is_finite() && y.is_finite()).collect()
}

/// The range of `values` widened by [`LINEAR_MARGIN`] of its width on both sides; [0, 1]
/// without values, ± 1 around a single value.
fn span(values: impl Iterator<Item = f64>) -> Range<f64> {
    let (min, max) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if min > max {
        return 0.0..1.0;
    }
    let margin = if max > min { LINEAR_MARGIN * (max - min) } else { 1.0 };
    min - margin..max + margin
}

/// Gap between the data and the frame on linear axes, as a fraction of the data's range.
const LINEAR_MARGIN: f64 = 0.05;

/// The smallest range of at least two whole decades holding `values` with a margin; [1, 100]
/// without values.
///
/// Two decades give every axis at least three labels and the same grid of minor ticks.
fn decades(values: impl Iterator<Item = f64>) -> Range<f64> {
    let (min, max) = values.fold((f64::INFINITY, 0.0_f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if max == 0.0 {
        return 1.0..100.0;
    }
    let (min, max) = (min.log10(), max.log10());
    let mut low = (min - MARGIN).floor();
    let mut high = (max + MARGIN).ceil();
    if high - low < 2.0 {
        // One decade: widen on the side nearer to the data.
        if min - low < high - max {
            low -= 1.0;
        } else {
            high += 1.0;
        }
    }
    let (low, high) = (low.clamp(-300.0, 298.0), high.clamp(-298.0, 300.0));
    // Nudged outwards so that rounding in the axis does not drop the ticks at both ends.
    10f64.powf(low) * (1.0 - 1e-9)..10f64.powf(high) * (1.0 + 1e-9)
}

/// `10ᵏ` at powers of ten, nothing at the intermediate ticks.
fn power_of_ten(value: &f64) -> String {
    let exponent = value.log10().round();
    if (value.log10() - exponent).abs() > 1e-6 {
        return String::new();
    }
    const SUPERSCRIPTS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let digits = (exponent.abs() as u32).to_string();
    let superscript: String = digits.bytes().map(|d| SUPERSCRIPTS[usize::from(d - b'0')]).collect();
    let sign = if exponent < 0.0 { "⁻" } else { "" };
    format!("10{sign}{superscript}")
}

/// A 24-pixel stretch of a series' line for the legend, starting at the anchor.
fn line_sample<DB: DrawingBackend>(dashed: bool, style: ShapeStyle) -> DynElement<'static, DB, (i32, i32)> {
    let ends = vec![(0, 0), (24, 0)];
    if dashed {
        DashedPathElement::new(ends, 7, 4, style).into_dyn()
    } else {
        PathElement::new(ends, style).into_dyn()
    }
}

/// The marker of series `index` at `at` (pixels from the anchor): circle, triangle or square.
fn marker<DB: DrawingBackend>(at: (i32, i32), index: usize, style: ShapeStyle) -> DynElement<'static, DB, (i32, i32)> {
    let filled = style.filled();
    match index % 3 {
        0 => Circle::new(at, 4, filled).into_dyn(),
        1 => TriangleMarker::new(at, 5, filled).into_dyn(),
        _ => Rectangle::new([(at.0 - 4, at.1 - 4), (at.0 + 4, at.1 + 4)], filled).into_dyn(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_font_is_named() {
        let error = load_font(Path::new("/nonexistent/font.ttf"), Path::new("eta.svg")).unwrap_err();
        let message = error.to_string();
        assert!(message.starts_with("cannot write eta.svg: cannot use font file /nonexistent/font.ttf: "), "{message}");
        assert!(message.ends_with("(Debian package fonts-dejavu-core)"), "{message}");
    }

    #[test]
    fn ranges_are_whole_decades() {
        let close = |r: Range<f64>, start: f64, end: f64| {
            assert!((r.start / start - 1.0).abs() < 1e-6 && (r.end / end - 1.0).abs() < 1e-6, "{r:?}");
        };
        close(decades([2.0e3, 4.0e5].into_iter()), 1e3, 1e6);
        close(decades([1.0e3, 1.0e5].into_iter()), 1e2, 1e6);
        close(decades(std::iter::once(0.25)), 1e-2, 1.0);
        close(decades(std::iter::once(0.5)), 1e-1, 10.0);
        close(decades(std::iter::empty()), 1.0, 100.0);
    }

    #[test]
    fn labels_only_at_powers_of_ten() {
        assert_eq!(power_of_ten(&1e-3), "10⁻³");
        assert_eq!(power_of_ten(&1.0), "10⁰");
        assert_eq!(power_of_ten(&1e12), "10¹²");
        assert_eq!(power_of_ten(&2e3), "");
    }
}

//! Log–log convergence figures (estimators against unknowns or wall time) and figures on linear
//! axes (stresses along the joint), written as SVG and PNG.
//!
//! Figures are drawn with `plotters`, rendered in memory and written atomically. Both formats
//! are [`SIZE`] pixels. Log axes span at least two whole decades around the data and are
//! labelled at powers of ten; linear axes span the data with a margin, labelled with the
//! fewest decimals. Each series gets its own colour and marker, dashed series a dashed line;
//! the legend lies in a strip below the axes. Marks (dashed grey lines with a label) show
//! places along an axis; a lower panel gives series of another scale their own y axis.
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
use plotters::style::text_anchor::{HPos, Pos, VPos};
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
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub dashed: bool,
}

/// A labelled dashed line across the plot: vertical at x = `at` (a drain line, a crack tip) or
/// horizontal at y = `at` (an allowable stress). The axes always show it.
#[derive(Debug, Clone, PartialEq)]
pub struct Mark {
    pub label: String,
    pub vertical: bool,
    pub at: f64,
}

impl Mark {
    pub fn vertical(label: impl Into<String>, x: f64) -> Self {
        Mark { label: label.into(), vertical: true, at: x }
    }

    pub fn horizontal(label: impl Into<String>, y: f64) -> Self {
        Mark { label: label.into(), vertical: false, at: y }
    }
}

/// Series on their own y axis, in a panel below the figure's and sharing its x axis.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    pub y_label: String,
    pub series: Vec<Series>,
}

/// A figure: series on one pair of axes, marks across them, and perhaps a lower panel.
///
/// A figure without any plottable point (no series, or only skipped points) is drawn as empty
/// axes over [1, 100] × [1, 100] (log) or [0, 1] × [0, 1] (linear); a single point gets two
/// decades around it. The legend lies in a strip below the axes, off the data.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Figure {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    pub marks: Vec<Mark>,
    /// Series whose values would stretch the y axis of `series` over many decades (solver
    /// tolerances beside discretisation errors) get their own axis here.
    pub lower: Option<Panel>,
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

/// The font of tick labels and legend entries.
const LABEL_FONT: (&str, u32) = ("sans-serif", 18);

/// Height of a row of the legend, in pixels.
const LEGEND_ROW: u32 = 28;

/// Share of the axes' height that the upper panel takes when there is a lower one.
const UPPER_SHARE: f64 = 0.64;

/// One pair of axes: its labels, its series (the first with colour `first`) and marks.
struct Plot<'f> {
    x_label: &'f str,
    y_label: &'f str,
    series: &'f [Series],
    first: usize,
    marks: &'f [Mark],
}

/// Draws the title, the panels and the legend strip on `root`.
fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, figure: &Figure, axes: Axes) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let root = root.titled(&figure.title, ("sans-serif", 26))?;
    let entries = legend_entries(figure, axes);
    let columns = legend_columns(&root, &entries)?;
    let rows = entries.len().div_ceil(columns) as u32;
    let height = root.dim_in_pixel().1;
    let (plots, legend) = root.split_vertically(height - rows * LEGEND_ROW - if rows > 0 { 12 } else { 0 });
    let lower = figure.lower.as_ref();
    let upper = Plot {
        x_label: if lower.is_some() { "" } else { &figure.x_label },
        y_label: &figure.y_label,
        series: &figure.series,
        first: 0,
        marks: &figure.marks,
    };
    let all: Vec<&Series> = figure.series.iter().chain(lower.iter().flat_map(|p| &p.series)).collect();
    let x_range = x_range(&all, &figure.marks, axes);
    match lower {
        None => draw_axes(&plots, &upper, axes, x_range)?,
        Some(panel) => {
            let (top, bottom) = plots.split_vertically((UPPER_SHARE * plots.dim_in_pixel().1 as f64) as u32);
            draw_axes(&top, &upper, axes, x_range.clone())?;
            let below = Plot {
                x_label: &figure.x_label,
                y_label: &panel.y_label,
                series: &panel.series,
                first: figure.series.len(),
                marks: &[],
            };
            draw_axes(&bottom, &below, axes, x_range)?;
        }
    }
    draw_legend(&legend, &entries, columns)?;
    root.present()
}

/// The x range shared by the panels: the points the axes can show and the vertical marks.
fn x_range(series: &[&Series], marks: &[Mark], axes: Axes) -> Range<f64> {
    let marked = marks.iter().filter(|m| m.vertical).map(|m| (m.at, 1.0));
    let points = series.iter().flat_map(|s| s.points.iter().copied()).chain(marked).collect::<Vec<_>>();
    match axes {
        Axes::LogLog => decades(plottable(&points).into_iter().map(|p| p.0)),
        Axes::Linear => span(finite(&points).into_iter().map(|p| p.0)),
    }
}

/// Draws one pair of axes with its series and marks on `area`.
fn draw_axes<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    spec: &Plot,
    axes: Axes,
    x_range: Range<f64>,
) -> DrawResult<DB> {
    let mut builder = ChartBuilder::on(area);
    let x_area = if spec.x_label.is_empty() { 36 } else { 64 };
    builder.margin(24).x_label_area_size(x_area).y_label_area_size(84);
    let marked = spec.marks.iter().filter(|m| !m.vertical).map(|m| m.at);
    match axes {
        Axes::LogLog => {
            let points: Vec<Vec<(f64, f64)>> = spec.series.iter().map(|s| plottable(&s.points)).collect();
            let ys = points.iter().flatten().map(|p| p.1).chain(marked.filter(|&y| y > 0.0));
            let y_range = decades(ys);
            let mut chart = builder.build_cartesian_2d(x_range.clone().log_scale(), y_range.clone().log_scale())?;
            let mut mesh = chart.configure_mesh();
            let (x_step, y_step) = (decade_step(&x_range), decade_step(&y_range));
            let x_label = move |v: &f64| every_decade(v, x_step);
            let y_label = move |v: &f64| every_decade(v, y_step);
            mesh.x_label_formatter(&x_label).y_label_formatter(&y_label);
            style_mesh(&mut mesh, spec).draw()?;
            draw_marks(&mut chart, spec.marks, &x_range, &y_range, y_range.end)?;
            draw_all(&mut chart, spec, points)
        }
        Axes::Linear => {
            let points: Vec<Vec<(f64, f64)>> = spec.series.iter().map(|s| finite(&s.points)).collect();
            let y_range = span(points.iter().flatten().map(|p| p.1).chain(marked));
            // room above the data for the labels of the vertical marks, a row each
            let rows = spec.marks.iter().filter(|m| m.vertical).count() as f64;
            let top = y_range.end;
            let y_range = y_range.start..top + MARK_ROOM * rows * (top - y_range.start);
            let mut chart = builder.build_cartesian_2d(x_range.clone(), y_range.clone())?;
            let mut mesh = chart.configure_mesh();
            let (x_width, y_width) = (x_range.end - x_range.start, y_range.end - y_range.start);
            let x_label = move |v: &f64| tick_label(*v, x_width);
            let y_label = move |v: &f64| tick_label(*v, y_width);
            mesh.x_label_formatter(&x_label).y_label_formatter(&y_label);
            style_mesh(&mut mesh, spec).draw()?;
            draw_marks(&mut chart, spec.marks, &x_range, &y_range, top)?;
            draw_all(&mut chart, spec, points)
        }
    }
}

/// Axis descriptions, label fonts and grid lines of `spec`.
fn style_mesh<'m, 'a, 'b, DB: DrawingBackend, X: Ranged, Y: Ranged>(
    mesh: &'m mut MeshStyle<'a, 'b, X, Y, DB>,
    spec: &Plot,
) -> &'m mut MeshStyle<'a, 'b, X, Y, DB> {
    mesh.x_desc(spec.x_label)
        .y_desc(spec.y_label)
        .label_style(LABEL_FONT)
        .axis_desc_style(("sans-serif", 20))
        .bold_line_style(BLACK.mix(0.25))
        .light_line_style(BLACK.mix(0.07))
}

/// A tick value of a linear axis `width` wide, with the fewest decimals that write it to
/// 10⁻⁶ of the width (rounding noise such as 10⁻¹⁷ for 0 is dropped), never "-0".
fn tick_label(value: f64, width: f64) -> String {
    let decimals = (0..12).find(|&d| {
        let scale = 10f64.powi(d);
        ((value * scale).round() / scale - value).abs() <= 1e-6 * width
    });
    let text = format!("{:.*}", decimals.unwrap_or(12) as usize, value);
    match text.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => text,
    }
}

/// Every series of `spec` through its drawable `points`.
fn draw_all<'a, DB: DrawingBackend + 'a, CT: CoordTranslate<From = (f64, f64)>>(
    chart: &mut ChartContext<'a, DB, CT>,
    spec: &Plot,
    points: Vec<Vec<(f64, f64)>>,
) -> DrawResult<DB> {
    for (index, (series, points)) in spec.series.iter().zip(points).enumerate() {
        draw_curve(chart, spec.first + index, series, points)?;
    }
    Ok(())
}

/// Room above the data for each row of mark labels, as a share of the y range.
const MARK_ROOM: f64 = 0.07;

/// Most labelled decades on a log axis.
const MOST_DECADES: f64 = 5.0;

/// Every how many decades a log axis over `range` is labelled: at most [`MOST_DECADES`] labels.
fn decade_step(range: &Range<f64>) -> i64 {
    ((range.end / range.start).log10() / MOST_DECADES).ceil().max(1.0) as i64
}

/// `10ᵏ` at the powers of ten whose exponent is a multiple of `step`, nothing elsewhere.
fn every_decade(value: &f64, step: i64) -> String {
    match (value.log10().round() as i64).rem_euclid(step) {
        0 => power_of_ten(value),
        _ => String::new(),
    }
}

/// Colour of the marks and of their labels.
const MARK_COLOUR: RGBColor = RGBColor(90, 90, 90);

/// The marks as dashed lines across the ranges, each labelled at its end: vertical marks up
/// to `top`, their labels above it a row apart so that neighbours do not overlap, on the
/// side with room; horizontal marks above their right end.
fn draw_marks<'a, DB: DrawingBackend + 'a, CT: CoordTranslate<From = (f64, f64)>>(
    chart: &mut ChartContext<'a, DB, CT>,
    marks: &[Mark],
    x: &Range<f64>,
    y: &Range<f64>,
    top: f64,
) -> DrawResult<DB> {
    let style = MARK_COLOUR.stroke_width(2);
    let font = TextStyle::from(LABEL_FONT).color(&MARK_COLOUR);
    for (row, mark) in marks.iter().enumerate() {
        let (ends, text) = if mark.vertical {
            let right = (mark.at - x.start) > 0.7 * (x.end - x.start);
            let (h, dx) = if right { (HPos::Right, -6) } else { (HPos::Left, 6) };
            let at = (mark.at, y.end);
            ([(mark.at, y.start), (mark.at, top)], (at, (dx, 6 + 22 * row as i32), font.pos(Pos::new(h, VPos::Top))))
        } else {
            let at = (x.end, mark.at);
            ([(x.start, mark.at), at], (at, (-6, -4), font.pos(Pos::new(HPos::Right, VPos::Bottom))))
        };
        chart.draw_series(DashedLineSeries::new(ends, 8, 5, style))?;
        let (at, offset, font) = text;
        chart.draw_series(std::iter::once(EmptyElement::at(at) + Text::new(mark.label.clone(), offset, font)))?;
    }
    Ok(())
}

/// The legend's entries: (label, colour index, dashed) of every labelled series with points
/// that the axes show.
fn legend_entries(figure: &Figure, axes: Axes) -> Vec<(String, usize, bool)> {
    let lower = figure.lower.iter().flat_map(|p| &p.series);
    let shown = |s: &Series| match axes {
        Axes::LogLog => !plottable(&s.points).is_empty(),
        Axes::Linear => !finite(&s.points).is_empty(),
    };
    (figure.series.iter().chain(lower).enumerate())
        .filter(|(_, s)| !s.label.is_empty() && shown(s))
        .map(|(index, s)| (s.label.clone(), index, s.dashed))
        .collect()
}

/// Left margin of the legend, and the room of its line sample before the label, in pixels.
const LEGEND_INDENT: (i32, i32) = (40, 34);

/// How many columns of legend entries fit across `area`.
fn legend_columns<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[(String, usize, bool)],
) -> Result<usize, DrawingAreaErrorKind<DB::ErrorType>> {
    let font = TextStyle::from(LABEL_FONT);
    let mut widest = 0;
    for (label, _, _) in entries {
        widest = widest.max(area.estimate_text_size(label, &font)?.0);
    }
    let column = widest as i32 + LEGEND_INDENT.1 + 30;
    let room = area.dim_in_pixel().0 as i32 - 2 * LEGEND_INDENT.0;
    Ok((room / column).clamp(1, entries.len().max(1) as i32) as usize)
}

/// The legend entries in rows of `columns`, each its line sample, marker and label.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[(String, usize, bool)],
    columns: usize,
) -> DrawResult<DB> {
    let font = TextStyle::from(LABEL_FONT).pos(Pos::new(HPos::Left, VPos::Center));
    let width = (area.dim_in_pixel().0 as i32 - 2 * LEGEND_INDENT.0) / columns as i32;
    for (k, (label, index, dashed)) in entries.iter().enumerate() {
        let style = PALETTE[index % PALETTE.len()].stroke_width(2);
        let x = LEGEND_INDENT.0 + (k % columns) as i32 * width;
        let y = (k / columns) as i32 * LEGEND_ROW as i32 + LEGEND_ROW as i32 / 2;
        let text = Text::new(label.clone(), (LEGEND_INDENT.1, 0), font.clone());
        area.draw(&(EmptyElement::at((x, y)) + line_sample(*dashed, style) + marker((12, 0), *index, style) + text))?;
    }
    Ok(())
}

/// Draws series `index` through its plottable `points`, with markers.
fn draw_curve<'a, DB: DrawingBackend + 'a, CT: CoordTranslate<From = (f64, f64)>>(
    chart: &mut ChartContext<'a, DB, CT>,
    index: usize,
    series: &Series,
    points: Vec<(f64, f64)>,
) -> DrawResult<DB> {
    let style = PALETTE[index % PALETTE.len()].stroke_width(2);
    if series.dashed {
        chart.draw_series(DashedLineSeries::new(points.clone(), 10, 6, style))?;
    } else {
        chart.draw_series(LineSeries::new(points.clone(), style))?;
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

    #[test]
    fn long_log_axes_label_every_few_decades() {
        assert_eq!(decade_step(&(1e3..1e6)), 1);
        let step = decade_step(&(1e-7..1e2));
        assert_eq!(step, 2);
        assert_eq!(every_decade(&1e-6, step), "10⁻⁶");
        assert_eq!(every_decade(&1e-7, step), "");
        assert_eq!(every_decade(&1.0, step), "10⁰");
    }

    #[test]
    fn linear_ticks_are_short_and_never_minus_zero() {
        assert_eq!(tick_label(-0.0, 4.0), "0");
        assert_eq!(tick_label(-1e-17, 4.0), "0");
        assert_eq!(tick_label(5.0, 40.0), "5");
        assert_eq!(tick_label(-0.5, 4.0), "-0.5");
        assert_eq!(tick_label(0.25, 1.0), "0.25");
        assert_eq!(tick_label(3e-10, 1e-9), "0.0000000003");
    }
}

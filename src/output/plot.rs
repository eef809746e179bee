//! Plots of the error bench as SVG (plotters; SVG text needs no font files and shows in any
//! browser and in rendered markdown): titled, with labelled axes, units, tick values and a
//! legend. Methods by colour: full blue, paper green, constant-brdf orange, no-filter red.

use crate::error::{Error, Result};
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

const SIZE: (u32, u32) = (900, 560);
const FONT: &str = "sans-serif";

fn colour(method: &str) -> RGBColor {
    match method {
        "full" => RGBColor(31, 119, 180),
        "paper" => RGBColor(44, 160, 44),
        "constant-brdf" => RGBColor(255, 127, 14),
        _ => RGBColor(214, 39, 40),
    }
}

fn plot_error(path: &Path) -> impl Fn(String) -> Error + '_ {
    move |message| Error::Io { path: path.to_owned(), message: format!("plot: {message}") }
}

/// The legend of every labelled series, in a light box at `position`.
fn legend<'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, SVGBackend<'a>, CT>,
    position: SeriesLabelPosition,
    font_size: u32,
) -> Result<(), String> {
    chart
        .configure_series_labels()
        .position(position)
        .label_font((FONT, font_size))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK.mix(0.4))
        .draw()
        .map_err(|e| e.to_string())
}

/// A value with three significant digits (plain notation from 0.001 up).
pub fn three_digits(v: f64) -> String {
    let decimals = (2 - v.abs().max(1e-3).log10().floor() as i32).max(0) as usize;
    format!("{v:.decimals$}")
}

/// The smallest and largest positive finite value ((0.1, 10) where there is none).
fn value_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if lo.is_finite() {
        (lo, hi)
    } else {
        (0.1, 10.0)
    }
}

/// One measured setting: its method (the colour), its label, GPU time (ms) and total RMSE.
pub struct Point<'a> {
    pub method: &'a str,
    pub setting: &'a str,
    pub gpu_ms: f64,
    pub rmse: f64,
}

/// Total RMSE against GPU time, one point per method and setting (labelled with the setting),
/// the Pareto front joined and ringed, and the ground truth's own noise floor as a dashed line:
/// no method can measure below it. The RMSE axis is logarithmic where the values span more than
/// a decade.
pub fn error_vs_time(
    path: &Path,
    title: &str,
    rows: &[Point],
    front: &[usize],
    noise_floor: Option<f64>,
    what: &str,
) -> Result<()> {
    let fail = plot_error(path);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(e.to_string()))?;
        let (lo, hi) = value_range(rows.iter().map(|r| r.rmse).chain(noise_floor));
        let plot = ErrorPlot { title, rows, front, noise_floor, what };
        if hi / lo > 10.0 {
            plot.draw(&root, (lo / 1.25..hi * 1.25).log_scale(), "log scale")
        } else {
            let pad = 0.08 * (hi - lo).max(1e-6 * hi);
            plot.draw(&root, (lo - pad).max(0.0)..hi + pad, "")
        }
        .map_err(&fail)?;
        root.present().map_err(|e| fail(e.to_string()))?;
    }
    super::write_text(path, &svg)
}

struct ErrorPlot<'a> {
    title: &'a str,
    rows: &'a [Point<'a>],
    front: &'a [usize],
    noise_floor: Option<f64>,
    /// What the RMSE axis measures, as its label says it.
    what: &'a str,
}

impl ErrorPlot<'_> {
    /// Draws on `root` with the RMSE axis `y` (linear or log), `scale` naming it in the label.
    fn draw<Y>(&self, root: &DrawingArea<SVGBackend, Shift>, y: Y, scale: &str) -> Result<(), String>
    where
        Y: AsRangedCoord<Value = f64>,
        Y::CoordDescType: ValueFormatter<f64>,
    {
        let e = |e: DrawingAreaErrorKind<_>| e.to_string();
        let rmse = |r: &Point| r.rmse;
        let max_ms = self.rows.iter().map(|r| r.gpu_ms).fold(0.0, f64::max).max(1e-3) * 1.15;
        let mut chart = ChartBuilder::on(root)
            .caption(self.title, (FONT, 20))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..max_ms, y)
            .map_err(e)?;
        let unit = if scale.is_empty() { "kcd/m²".to_owned() } else { format!("kcd/m², {scale}") };
        chart
            .configure_mesh()
            .x_desc("GPU time per frame (ms)")
            .y_desc(format!("{} ({unit})", self.what))
            .axis_desc_style((FONT, 15))
            .label_style((FONT, 13))
            .y_labels(10)
            .draw()
            .map_err(e)?;
        if let Some(floor) = self.noise_floor {
            let grey = BLACK.mix(0.6);
            chart
                .draw_series(DashedLineSeries::new([(0.0, floor), (max_ms, floor)], 8, 5, grey.stroke_width(1)))
                .map_err(e)?
                .label(format!("ground truth's noise floor ({})", three_digits(floor)))
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], grey));
        }
        let mut on_front: Vec<&Point> = self.front.iter().map(|&i| &self.rows[i]).collect();
        on_front.sort_by(|a, b| a.gpu_ms.total_cmp(&b.gpu_ms));
        chart
            .draw_series(LineSeries::new(on_front.iter().map(|r| (r.gpu_ms, rmse(r))), BLACK.stroke_width(1)))
            .map_err(e)?
            .label("Pareto front (ringed)")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLACK));
        chart
            .draw_series(on_front.iter().map(|r| Circle::new((r.gpu_ms, rmse(r)), 8, BLACK.stroke_width(1))))
            .map_err(e)?;
        for method in ["full", "paper", "constant-brdf", "no-filter"] {
            let points: Vec<&Point> = self.rows.iter().filter(|r| r.method == method && rmse(r).is_finite()).collect();
            if points.is_empty() {
                continue;
            }
            let c = colour(method);
            chart
                .draw_series(points.iter().map(|r| Circle::new((r.gpu_ms, rmse(r)), 5, c.filled())))
                .map_err(e)?
                .label(method)
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, c.filled()));
            // Settings named beside their points, alternately above and below: neighbours overlap less.
            chart
                .draw_series(points.iter().enumerate().map(|(i, r)| {
                    let dy = if i % 2 == 0 { -16 } else { 6 };
                    EmptyElement::at((r.gpu_ms, rmse(r)))
                        + Text::new(r.setting.to_owned(), (7, dy), (FONT, 11).into_font().color(&c))
                }))
                .map_err(e)?;
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight, 13)
    }
}

/// Relative energy error per distance band (named by `band_labels`) of the reflected sun (left)
/// and the reflected sky (right), one line per method, with the ±5% target shaded; bands without
/// energy in the ground truth are gaps.
pub fn energy_by_distance(
    path: &Path,
    title: &str,
    band_labels: &[String],
    series: &[(&str, Vec<[f64; 2]>)],
) -> Result<()> {
    let mut svg = String::new();
    let area = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
    draw_energy(area, title, band_labels, series).map_err(plot_error(path))?;
    super::write_text(path, &svg)
}

fn draw_energy(
    root: DrawingArea<SVGBackend, Shift>,
    title: &str,
    band_labels: &[String],
    series: &[(&str, Vec<[f64; 2]>)],
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<_>| e.to_string();
    let bands = band_labels.len();
    {
        root.fill(&WHITE).map_err(e)?;
        let root = root.titled(title, (FONT, 20)).map_err(e)?;
        let panels = root.split_evenly((1, 2));
        for (term, panel) in panels.iter().enumerate() {
            let percent = |v: f64| 100.0 * v;
            let values = series.iter().flat_map(|(_, v)| v.iter().map(move |b| percent(b[term])));
            let (lo, hi) =
                values.filter(|v| v.is_finite()).fold((-10.0f64, 10.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
            let pad = 0.08 * (hi - lo);
            let mut chart = ChartBuilder::on(panel)
                .caption(["reflected sun", "reflected sky"][term], (FONT, 16))
                .margin(12)
                .x_label_area_size(60)
                .y_label_area_size(60)
                .build_cartesian_2d(-0.3..(bands as f64 - 0.7), (lo - pad)..(hi + pad))
                .map_err(e)?;
            band_mesh(&mut chart, band_labels, "energy error against the ground truth (%)")?;
            chart
                .draw_series([Rectangle::new(
                    [(-0.3, -5.0), (bands as f64 - 0.7, 5.0)],
                    RGBColor(0, 160, 0).mix(0.12).filled(),
                )])
                .map_err(e)?
                .label("±5% target")
                .legend(|(x, y)| Rectangle::new([(x, y - 5), (x + 20, y + 5)], RGBColor(0, 160, 0).mix(0.3).filled()));
            chart.draw_series(LineSeries::new([(-0.3, 0.0), (bands as f64 - 0.7, 0.0)], BLACK.mix(0.5))).map_err(e)?;
            for (method, values) in series {
                band_line(&mut chart, method, values.iter().map(|v| percent(v[term])))?;
            }
            legend(&mut chart, SeriesLabelPosition::UpperLeft, 12)?;
        }
        root.present().map_err(e)?;
    }
    Ok(())
}

/// The band axis (x, named by `band_labels`) and the value axis (`y_desc`) of a plot by distance.
fn band_mesh<'a>(
    chart: &mut ChartContext<'a, SVGBackend<'a>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    band_labels: &[String],
    y_desc: &str,
) -> Result<(), String> {
    let bands = band_labels.len();
    chart
        .configure_mesh()
        .x_labels(bands)
        .x_label_formatter(&|x| {
            let i = x.round();
            if (x - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < bands {
                band_labels[i as usize].clone()
            } else {
                String::new()
            }
        })
        .x_desc("distance from the eye (m)")
        .y_desc(y_desc)
        .axis_desc_style((FONT, 13))
        .label_style((FONT, 11))
        .draw()
        .map_err(|e| e.to_string())
}

/// One method's values by band as a line in its colour, split at missing (non-finite) values so
/// that a gap is not bridged.
fn band_line<'a>(
    chart: &mut ChartContext<'a, SVGBackend<'a>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    method: &str,
    values: impl Iterator<Item = f64>,
) -> Result<(), String> {
    let c = colour(method);
    let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
    for (b, v) in values.enumerate() {
        if v.is_finite() {
            runs.last_mut().expect("never empty").push((b as f64, v));
        } else if !runs.last().expect("never empty").is_empty() {
            runs.push(Vec::new());
        }
    }
    // The first run carries the legend even where empty: every method is named.
    for (i, run) in runs.iter().enumerate() {
        let line = chart
            .draw_series(LineSeries::new(run.iter().copied(), c.stroke_width(2)).point_size(4))
            .map_err(|e| e.to_string())?;
        if i == 0 {
            line.label(method.to_owned())
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], c.stroke_width(2)));
        }
    }
    Ok(())
}

/// A ratio to the ground truth per distance band (named by `band_labels`), one line per method,
/// with 1 (the ground truth's own) marked; `what` names the ratio on its axis. Bands without a
/// value are gaps.
pub fn ratio_by_distance(
    path: &Path,
    title: &str,
    what: &str,
    band_labels: &[String],
    series: &[(&str, Vec<f64>)],
) -> Result<()> {
    let mut svg = String::new();
    let area = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
    draw_ratio(area, title, what, band_labels, series).map_err(plot_error(path))?;
    super::write_text(path, &svg)
}

fn draw_ratio(
    root: DrawingArea<SVGBackend, Shift>,
    title: &str,
    what: &str,
    band_labels: &[String],
    series: &[(&str, Vec<f64>)],
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<_>| e.to_string();
    let right = band_labels.len() as f64 - 0.7;
    root.fill(&WHITE).map_err(e)?;
    // From 0 (no detail) to above both 1 and the largest ratio.
    let hi = series.iter().flat_map(|(_, v)| v.iter().copied()).filter(|v| v.is_finite()).fold(1.0f64, f64::max);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, 20))
        .margin(16)
        .x_label_area_size(60)
        .y_label_area_size(60)
        .build_cartesian_2d(-0.3..right, 0.0..hi * 1.1)
        .map_err(e)?;
    band_mesh(&mut chart, band_labels, what)?;
    let grey = BLACK.mix(0.6);
    chart
        .draw_series(DashedLineSeries::new([(-0.3, 1.0), (right, 1.0)], 8, 5, grey.stroke_width(1)))
        .map_err(e)?
        .label("as the ground truth (1)")
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], grey));
    for (method, values) in series {
        band_line(&mut chart, method, values.iter().copied())?;
    }
    legend(&mut chart, SeriesLabelPosition::UpperRight, 12)?;
    root.present().map_err(e)
}

//! Line charts as SVG, for trajectories and studies: a figure is a column of panels, each with
//! its series of `(x, y)` points. Rendered to a string (no fonts needed: the SVG names its font
//! family); write it with [`crate::files::write_atomically`].

use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;

use plotters::prelude::*;

/// One line of a panel.
#[derive(Clone, Debug)]
pub struct Series {
    /// Its name in the legend.
    pub label: String,
    /// Its points, in order of `x`.
    pub points: Vec<(f64, f64)>,
}

/// One chart of a figure.
#[derive(Clone, Debug)]
pub struct Panel {
    /// Its title.
    pub title: String,
    /// The horizontal axis' label, with its unit.
    pub x_label: String,
    /// The vertical axis' label, with its unit.
    pub y_label: String,
    /// Its lines.
    pub series: Vec<Series>,
}

impl Panel {
    /// A panel without lines yet.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Panel {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: Vec::new(),
        }
    }

    /// The panel with one more line.
    pub fn with(mut self, label: &str, points: Vec<(f64, f64)>) -> Self {
        self.series.push(Series {
            label: label.into(),
            points,
        });
        self
    }
}

/// Why a figure could not be drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotError(String);

impl fmt::Display for PlotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "cannot draw the figure: {}", self.0)
    }
}

impl std::error::Error for PlotError {}

/// The colours of the series, in order (then repeated).
const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

/// The panels one under the other, `width` pixels wide and `panel_height` each, as SVG.
///
/// # Errors
/// A panel without points, or a point that is not finite.
pub fn svg(panels: &[Panel], width: u32, panel_height: u32) -> Result<String, PlotError> {
    let err = |e: &dyn fmt::Display| PlotError(alloc::format!("{e}"));
    let height = panel_height * u32::try_from(panels.len().max(1)).map_err(|e| err(&e))?;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(&e))?;
        let areas = root.split_evenly((panels.len().max(1), 1));
        for (panel, area) in panels.iter().zip(&areas) {
            draw_panel(panel, area).map_err(|e| err(&e))?;
        }
        root.present().map_err(|e| err(&e))?;
    }
    Ok(out)
}

/// The range of `values` with a margin, never empty.
fn range(values: impl Iterator<Item = f64>) -> Result<(f64, f64), String> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
        (lo.min(x), hi.max(x))
    });
    if !(lo.is_finite() && hi.is_finite()) {
        return Err("a panel has no points, or a point that is not finite".into());
    }
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        lo.abs().max(1.0) * 0.05
    };
    Ok((lo - pad, hi + pad))
}

fn draw_panel<DB: DrawingBackend>(
    panel: &Panel,
    area: &DrawingArea<DB, plotters::coord::Shift>,
) -> Result<(), String> {
    let points = || panel.series.iter().flat_map(|s| s.points.iter());
    let (x0, x1) = range(points().map(|p| p.0))?;
    let (y0, y1) = range(points().map(|p| p.1))?;
    let text = |e: &dyn fmt::Display| alloc::format!("{e}");
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(36)
        .y_label_area_size(64)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| text(&e))?;
    chart
        .configure_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .draw()
        .map_err(|e| text(&e))?;
    for (s, &colour) in panel.series.iter().zip(PALETTE.iter().cycle()) {
        chart
            .draw_series(LineSeries::new(
                s.points.iter().copied(),
                colour.stroke_width(2),
            ))
            .map_err(|e| text(&e))?
            .label(s.label.as_str())
            .legend(move |(x, y)| PathElement::new(alloc::vec![(x, y), (x + 18, y)], colour));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| text(&e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_panels_and_refuses_empty_or_non_finite_ones() {
        let sine: Vec<(f64, f64)> = (0..50)
            .map(|i| (i as f64 * 0.1, (i as f64 * 0.1).sin()))
            .collect();
        let panel = Panel::new("sine", "t (s)", "q (rad)").with("q0", sine.clone());
        let text = svg(&[panel.clone(), panel], 640, 240).unwrap();
        assert!(text.starts_with("<svg") && text.contains("sine") && text.contains("q0"));
        assert!(svg(&[Panel::new("empty", "x", "y")], 640, 240).is_err());
        let bad = Panel::new("nan", "x", "y").with("q", vec![(0.0, f64::NAN)]);
        assert!(svg(&[bad], 640, 240).is_err());
    }
}

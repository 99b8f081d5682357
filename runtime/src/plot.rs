//! Line charts as SVG, for trajectories and studies: a figure is a column of panels, each with
//! its series of `(x, y)` points. Rendered to a string (no fonts needed: the SVG names its font
//! family); write it with [`crate::files::write_atomically`].

use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

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

/// The colours of the series, in order (then repeated): Tableau's ten, then their light
/// shades.
const PALETTE: [RGBColor; 20] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(174, 199, 232),
    RGBColor(255, 187, 120),
    RGBColor(152, 223, 138),
    RGBColor(255, 152, 150),
    RGBColor(197, 176, 213),
    RGBColor(196, 156, 148),
    RGBColor(247, 182, 210),
    RGBColor(199, 199, 199),
    RGBColor(219, 219, 141),
    RGBColor(158, 218, 229),
];

/// The caption's and the legend's font sizes (px).
const CAPTION_SIZE: u32 = 18;
const LEGEND_SIZE: u32 = 13;
/// A legend line's height, the top of the first one below the panel's top (clear of the
/// caption), and the length of its colour sample (px).
const LEGEND_ROW: u32 = 18;
const LEGEND_TOP: u32 = 44;
const SAMPLE: u32 = 22;

/// The width of `text` in a sans-serif font of `size` px as plotters sets it (at `size / 1.24`),
/// estimated (an SVG has no metrics): an average glyph is about 0.55 em of that, so half of
/// `size`, with a little to spare.
fn text_width(text: &str, size: u32) -> u32 {
    let chars = u32::try_from(text.chars().count()).unwrap_or(u32::MAX);
    chars.saturating_mul(size) / 2
}

/// `text` cut to about `width` px at `size`, with an ellipsis where it was cut.
fn fit(text: &str, width: u32, size: u32) -> String {
    if text_width(text, size) <= width {
        return text.into();
    }
    let keep = (width / (size / 2).max(1)).saturating_sub(1) as usize;
    let mut cut: String = text.chars().take(keep).collect();
    cut.push('…');
    cut
}

/// The panels one under the other, `width` pixels wide and `panel_height` each, as SVG. Each
/// panel has its caption above, its chart on the left and its legend to the right, outside the
/// data, in as many columns as its series need; a caption or a label too long for its place is
/// cut, with an ellipsis.
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
        // One legend width for all, so that the panels' time axes line up.
        let legend = panels
            .iter()
            .map(|p| LegendLayout::of(p, (width, panel_height)).width)
            .max()
            .unwrap_or(0);
        for (panel, area) in panels.iter().zip(&areas) {
            draw_panel(panel, area, legend).map_err(|e| err(&e))?;
        }
        root.present().map_err(|e| err(&e))?;
    }
    Ok(out)
}

/// The range of `values` with a margin, never empty. Values that vary by less than `1e-12`
/// of their size (or of 1) are drawn as the constant they are to rounding: the axis then spans
/// 10 % of that size (or of 1), where plotters would find no ticks.
fn range(values: impl Iterator<Item = f64>) -> Result<(f64, f64), String> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
        (lo.min(x), hi.max(x))
    });
    if !(lo.is_finite() && hi.is_finite()) {
        return Err("a panel has no points, or a point that is not finite".into());
    }
    let size = lo.abs().max(hi.abs()).max(1.0);
    let pad = if hi - lo > 1e-12 * size {
        0.05 * (hi - lo)
    } else {
        0.05 * size
    };
    Ok((lo - pad, hi + pad))
}

/// How an axis' tick labels are written: with the decimals its span needs (a range of a
/// thousandth gets three), or in scientific notation for very large or small values.
#[derive(Clone, Copy)]
enum Tick {
    Fixed(usize),
    Scientific,
}

impl Tick {
    /// The labels of an axis from `lo` to `hi`.
    fn over(lo: f64, hi: f64) -> Self {
        let magnitude = lo.abs().max(hi.abs());
        if magnitude >= 1e6 || (magnitude > 0.0 && magnitude < 1e-3) {
            return Tick::Scientific;
        }
        // Plotters puts about eight to ten ticks over the span: the decimals their spacing
        // needs.
        let spacing = (hi - lo) / 8.0;
        let decimals = if spacing > 0.0 {
            libm::ceil(-libm::log10(spacing)).clamp(0.0, 8.0)
        } else {
            1.0
        };
        Tick::Fixed(decimals as usize)
    }

    fn label(self, x: f64) -> String {
        let text = match self {
            Tick::Fixed(decimals) => alloc::format!("{x:.decimals$}"),
            Tick::Scientific => alloc::format!("{x:.1e}"),
        };
        // No "-0.0" for a value that rounds to zero.
        match text.strip_prefix('-') {
            Some(rest) if rest.chars().all(|c| matches!(c, '0' | '.')) => rest.into(),
            _ => text,
        }
    }
}

/// Where a panel's legend goes: lines per column, the columns' width, the whole width (px).
struct LegendLayout {
    rows: usize,
    column: u32,
    width: u32,
}

impl LegendLayout {
    /// The legend of `panel` in a panel `(width, height)`: as many lines as fit the height per
    /// column, columns as wide as the longest label, at most half the panel in all.
    fn of(panel: &Panel, (width, height): (u32, u32)) -> Self {
        let n = panel.series.len().max(1);
        let rows = (height.saturating_sub(LEGEND_TOP + 16) / LEGEND_ROW).max(1) as usize;
        let columns = u32::try_from(n.div_ceil(rows)).unwrap_or(u32::MAX);
        let longest = panel
            .series
            .iter()
            .map(|s| text_width(&s.label, LEGEND_SIZE))
            .max()
            .unwrap_or(0);
        let column = (SAMPLE + 14 + longest)
            .min(width / 2 / columns.max(1))
            .max(1);
        LegendLayout {
            rows,
            column,
            width: column.saturating_mul(columns).saturating_add(8),
        }
    }
}

/// Draws `panel` on `area`, its legend in the `legend_width` pixels on the right.
fn draw_panel<DB: DrawingBackend>(
    panel: &Panel,
    area: &DrawingArea<DB, plotters::coord::Shift>,
    legend_width: u32,
) -> Result<(), String> {
    let points = || panel.series.iter().flat_map(|s| s.points.iter());
    let (x0, x1) = range(points().map(|p| p.0))?;
    let (y0, y1) = range(points().map(|p| p.1))?;
    let text = |e: &dyn fmt::Display| alloc::format!("{e}");
    let (width, height) = area.dim_in_pixel();
    let legend = LegendLayout::of(panel, (width, height));
    let (plot_area, legend_area) =
        area.split_horizontally(width.saturating_sub(legend_width.max(legend.width)));
    let caption = fit(
        &panel.title,
        plot_area.dim_in_pixel().0.saturating_sub(24),
        CAPTION_SIZE,
    );
    let (x_tick, y_tick) = (Tick::over(x0, x1), Tick::over(y0, y1));
    let mut chart = ChartBuilder::on(&plot_area)
        .caption(caption, ("sans-serif", CAPTION_SIZE))
        .margin(12)
        .x_label_area_size(36)
        .y_label_area_size(match y_tick {
            Tick::Scientific => 80,
            Tick::Fixed(_) => 64,
        })
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| text(&e))?;
    chart
        .configure_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .x_label_formatter(&|x| x_tick.label(*x))
        .y_label_formatter(&|y| y_tick.label(*y))
        .draw()
        .map_err(|e| text(&e))?;
    let label_style = TextStyle::from(("sans-serif", LEGEND_SIZE).into_font())
        .pos(Pos::new(HPos::Left, VPos::Center));
    let label_width = legend.column.saturating_sub(SAMPLE + 12);
    for (i, (s, &colour)) in panel.series.iter().zip(PALETTE.iter().cycle()).enumerate() {
        chart
            .draw_series(LineSeries::new(
                s.points.iter().copied(),
                colour.stroke_width(2),
            ))
            .map_err(|e| text(&e))?;
        let column = u32::try_from(i / legend.rows).unwrap_or(u32::MAX);
        let row = u32::try_from(i % legend.rows).unwrap_or(u32::MAX);
        let x = i32::try_from(column.saturating_mul(legend.column)).unwrap_or(i32::MAX);
        let y = i32::try_from(LEGEND_TOP + row * LEGEND_ROW).unwrap_or(i32::MAX);
        let sample = i32::try_from(SAMPLE).unwrap_or(0);
        legend_area
            .draw(&PathElement::new(
                alloc::vec![(x, y), (x + sample, y)],
                colour.stroke_width(2),
            ))
            .map_err(|e| text(&e))?;
        legend_area
            .draw(&Text::new(
                fit(&s.label, label_width, LEGEND_SIZE),
                (x + sample + 6, y),
                label_style.clone(),
            ))
            .map_err(|e| text(&e))?;
    }
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

    /// The `x` of each `<polyline>` point in an SVG, per line.
    fn polylines(svg: &str) -> Vec<Vec<f64>> {
        svg.split("<polyline")
            .skip(1)
            .map(|l| {
                let points = l
                    .split("points=\"")
                    .nth(1)
                    .unwrap()
                    .split('"')
                    .next()
                    .unwrap();
                points
                    .split_whitespace()
                    .map(|p| p.split(',').next().unwrap().parse().unwrap())
                    .collect()
            })
            .collect()
    }

    /// The `x` of the `<text>` whose content is `label` (on a line of its own).
    fn text_x(svg: &str, label: &str) -> f64 {
        let end = svg.find(&format!(">\n{label}\n</text>")).expect(label);
        let start = svg[..end].rfind("<text").unwrap();
        let x = svg[start..end].split(" x=\"").nth(1).unwrap();
        x.split('"').next().unwrap().parse().unwrap()
    }

    /// Issue 31: the legend covered the curves. Each label now lies right of every point of
    /// every data line (the lines of more than two points; a legend sample has two), in as
    /// many columns as the panel's height needs, and a caption too long for the panel is cut.
    #[test]
    fn the_legend_is_outside_the_data_and_long_captions_are_cut() {
        let wave = |k: usize| -> Vec<(f64, f64)> {
            (0..50)
                .map(|i| (i as f64 * 0.1, (i as f64 * 0.1 + k as f64).sin()))
                .collect()
        };
        let title = format!("/very/long/absolute/path/{}", "x".repeat(300));
        let mut panel = Panel::new(&title, "t (s)", "q (rad)");
        for k in 0..24 {
            panel = panel.with(&format!("joint{k}.rx"), wave(k));
        }
        let text = svg(&[panel], 900, 330).unwrap();
        let lines = polylines(&text);
        let data: Vec<&Vec<f64>> = lines.iter().filter(|l| l.len() > 2).collect();
        assert_eq!(data.len(), 24);
        let right = data
            .iter()
            .flat_map(|l| l.iter())
            .fold(0.0f64, |m, &x| m.max(x));
        let xs: Vec<f64> = (0..24)
            .map(|k| text_x(&text, &format!("joint{k}.rx")))
            .collect();
        assert!(xs.iter().all(|&x| x > right && x < 900.0), "{right} {xs:?}");
        // More labels than one column holds at this height: two columns.
        assert!(xs.iter().any(|&x| x > xs[0] + 40.0), "{xs:?}");
        assert!(!text.contains(&title) && text.contains("/very/long/absolute/path/xx"));
        assert!(text.contains('…'));
    }
}

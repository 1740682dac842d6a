//! Pictures of tool paths in one plane, as SVG: polylines of positions
//! drawn to the same scale on both axes (a circle stays a circle), in a
//! frame with a millimetre grid, tick labels, axis names, a title and a
//! legend. Used for the documentation's pictures of executed paths
//! (docs/otc.md); any sequence of plane points can be drawn.
//!
//! ```
//! use plot::{Plot, Stroke};
//!
//! let svg = Plot::new("a square")
//!     .axes("X", "Y")
//!     .line("contour", Stroke::solid("#888", 2.0), vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]])
//!     .to_svg();
//! assert!(svg.starts_with("<svg"));
//! assert!(svg.contains("contour"));
//! ```

use svg::node::element::{Group, Line, Polyline, Rectangle, Text, Title};
use svg::Document;

/// Width of the whole picture in pixels.
const WIDTH: f64 = 720.0;
/// Margins around the plotting area: left, right, top, bottom (pixels).
const MARGIN: [f64; 4] = [56.0, 20.0, 36.0, 40.0];
/// Height of one legend or note row (pixels).
const ROW: f64 = 18.0;
/// Share of the data's extent left free around it.
const PAD: f64 = 0.04;
/// Font used for every text.
const FONT: &str = "sans-serif";

/// How a polyline is stroked.
#[derive(Debug, Clone, PartialEq)]
pub struct Stroke {
    /// An SVG colour, e.g. `#d22`.
    pub colour: String,
    /// Line width in pixels.
    pub width: f64,
    /// An SVG `stroke-dasharray`, or none for a solid line.
    pub dash: Option<String>,
}

impl Stroke {
    /// A solid line.
    pub fn solid(colour: &str, width: f64) -> Self {
        Self {
            colour: colour.to_owned(),
            width,
            dash: None,
        }
    }

    /// A dashed line (`dash` as SVG `stroke-dasharray`, e.g. `"6 3"`).
    pub fn dashed(colour: &str, width: f64, dash: &str) -> Self {
        Self {
            dash: Some(dash.to_owned()),
            ..Self::solid(colour, width)
        }
    }
}

/// One polyline of the picture and its legend entry.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// How it is drawn.
    pub stroke: Stroke,
    /// The points, in plane coordinates (horizontal, vertical).
    pub points: Vec<[f64; 2]>,
    /// Text shown on hover (an SVG `<title>`), if any.
    pub hover: Option<String>,
}

/// A picture of polylines in a plane.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Plot {
    title: String,
    axes: [String; 2],
    series: Vec<Series>,
    notes: Vec<String>,
}

/// Where the data lies and how it maps onto pixels.
#[derive(Debug, Clone, Copy)]
struct Frame {
    /// Data bounds: min h, min v, max h, max v.
    bounds: [f64; 4],
    /// Pixels per data unit.
    scale: f64,
    /// Height of the plotting area in pixels.
    height: f64,
}

impl Frame {
    /// The frame that holds every point with equal scales on both axes.
    fn around(series: &[Series]) -> Self {
        let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
        for p in series.iter().flat_map(|s| &s.points) {
            b = [
                b[0].min(p[0]),
                b[1].min(p[1]),
                b[2].max(p[0]),
                b[3].max(p[1]),
            ];
        }
        if b[0] > b[2] {
            b = [0.0, 0.0, 1.0, 1.0];
        }
        let pad = PAD * (b[2] - b[0]).max(b[3] - b[1]).max(1e-9);
        let bounds = [b[0] - pad, b[1] - pad, b[2] + pad, b[3] + pad];
        let scale = (WIDTH - MARGIN[0] - MARGIN[1]) / (bounds[2] - bounds[0]);
        Self {
            bounds,
            scale,
            height: (bounds[3] - bounds[1]) * scale,
        }
    }

    /// Pixel position of a plane point (vertical axis pointing up).
    fn pixel(&self, p: [f64; 2]) -> (f64, f64) {
        (
            MARGIN[0] + (p[0] - self.bounds[0]) * self.scale,
            MARGIN[2] + self.height - (p[1] - self.bounds[1]) * self.scale,
        )
    }
}

/// A tick spacing of 1, 2 or 5 times a power of ten giving about six
/// ticks over `extent`.
fn tick_step(extent: f64) -> f64 {
    let raw = extent.max(1e-9) / 6.0;
    let power = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * power)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * power)
}

/// Ticks: multiples of `step` within `lo..=hi`.
fn ticks(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// A number as a tick label (no `-0`, no trailing zeros).
fn label(v: f64) -> String {
    let v = if v.abs() < 1e-12 { 0.0 } else { v };
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_owned()
}

fn text(x: f64, y: f64, size: u32, anchor: &str, content: &str) -> Text {
    Text::new(content)
        .set("x", format!("{x:.1}"))
        .set("y", format!("{y:.1}"))
        .set("font-family", FONT)
        .set("font-size", size)
        .set("text-anchor", anchor)
}

fn line(a: (f64, f64), b: (f64, f64), colour: &str, width: f64) -> Line {
    Line::new()
        .set("x1", format!("{:.1}", a.0))
        .set("y1", format!("{:.1}", a.1))
        .set("x2", format!("{:.1}", b.0))
        .set("y2", format!("{:.1}", b.1))
        .set("stroke", colour)
        .set("stroke-width", width)
}

fn stroked(points: String, stroke: &Stroke) -> Polyline {
    let mut p = Polyline::new()
        .set("fill", "none")
        .set("stroke", stroke.colour.as_str())
        .set("stroke-width", stroke.width)
        .set("stroke-linejoin", "round")
        .set("points", points);
    if let Some(d) = &stroke.dash {
        p = p.set("stroke-dasharray", d.as_str());
    }
    p
}

impl Plot {
    /// An empty picture with a title.
    pub fn new(title: &str) -> Self {
        Self {
            title: title.to_owned(),
            axes: ["X".to_owned(), "Y".to_owned()],
            ..Self::default()
        }
    }

    /// Names the horizontal and the vertical axis (default `X`, `Y`).
    pub fn axes(mut self, horizontal: &str, vertical: &str) -> Self {
        self.axes = [horizontal.to_owned(), vertical.to_owned()];
        self
    }

    /// Adds a polyline with its legend text.
    pub fn line(mut self, label: &str, stroke: Stroke, points: Vec<[f64; 2]>) -> Self {
        self.series.push(Series {
            label: label.to_owned(),
            stroke,
            points,
            hover: None,
        });
        self
    }

    /// Adds a polyline that is part of a path drawn in pieces: `hover` is
    /// shown when the pointer is over it, and the legend names `label`
    /// once, for the first piece with that label.
    pub fn piece(
        &mut self,
        label: &str,
        stroke: Stroke,
        points: Vec<[f64; 2]>,
        hover: Option<String>,
    ) {
        self.series.push(Series {
            label: label.to_owned(),
            stroke,
            points,
            hover,
        });
    }

    /// Adds a line of small text under the legend.
    pub fn note(mut self, text: &str) -> Self {
        self.notes.push(text.to_owned());
        self
    }

    /// The picture as an SVG document (the same plot gives the same text).
    pub fn to_svg(&self) -> String {
        let frame = Frame::around(&self.series);
        let rows = (self.legend_entries().len() + self.notes.len()) as f64;
        let height = MARGIN[2] + frame.height + MARGIN[3] + rows * ROW + 8.0;
        let mut doc = Document::new()
            .set("width", WIDTH)
            .set("height", format!("{height:.0}"))
            .set("viewBox", format!("0 0 {WIDTH} {height:.0}"))
            .add(
                Rectangle::new()
                    .set("width", "100%")
                    .set("height", "100%")
                    .set("fill", "white"),
            )
            .add(text(WIDTH / 2.0, 22.0, 14, "middle", &self.title))
            .add(self.grid(&frame));
        for s in &self.series {
            let mut line = stroked(self.points(&frame, s), &s.stroke);
            if let Some(h) = &s.hover {
                line = line.add(Title::new(h.as_str()));
            }
            doc = doc.add(line);
        }
        doc.add(self.legend(MARGIN[2] + frame.height + MARGIN[3]))
            .to_string()
            + "\n"
    }

    /// The points of a series in pixels, 0.1 px resolution.
    fn points(&self, frame: &Frame, s: &Series) -> String {
        let mut out = String::with_capacity(12 * s.points.len());
        for p in &s.points {
            let (x, y) = frame.pixel(*p);
            if !out.is_empty() {
                out.push(' ');
            }
            out.push_str(&format!("{x:.1},{y:.1}"));
        }
        out
    }

    /// Frame, grid lines, tick labels and axis names.
    fn grid(&self, frame: &Frame) -> Group {
        let b = frame.bounds;
        let step = tick_step((b[2] - b[0]).max(b[3] - b[1]));
        let mut g = Group::new();
        for h in ticks(b[0], b[2], step) {
            let (x, y0) = frame.pixel([h, b[1]]);
            let (_, y1) = frame.pixel([h, b[3]]);
            g = g.add(line((x, y0), (x, y1), "#eee", 1.0));
            g = g.add(text(x, y0 + 14.0, 11, "middle", &label(h)));
        }
        for v in ticks(b[1], b[3], step) {
            let (x0, y) = frame.pixel([b[0], v]);
            let (x1, _) = frame.pixel([b[2], v]);
            g = g.add(line((x0, y), (x1, y), "#eee", 1.0));
            g = g.add(text(x0 - 6.0, y + 4.0, 11, "end", &label(v)));
        }
        let (left, bottom) = frame.pixel([b[0], b[1]]);
        let (right, top) = frame.pixel([b[2], b[3]]);
        let border = Rectangle::new()
            .set("x", format!("{left:.1}"))
            .set("y", format!("{top:.1}"))
            .set("width", format!("{:.1}", right - left))
            .set("height", format!("{:.1}", bottom - top))
            .set("fill", "none")
            .set("stroke", "#999");
        let mid = (left + right) / 2.0;
        g.add(border)
            .add(text(mid, bottom + 30.0, 12, "middle", &self.axes[0]))
            .add(
                text(14.0, (top + bottom) / 2.0, 12, "middle", &self.axes[1]).set(
                    "transform",
                    format!("rotate(-90 14 {:.1})", (top + bottom) / 2.0),
                ),
            )
    }

    /// The series the legend shows: the first of each label.
    fn legend_entries(&self) -> Vec<&Series> {
        let mut out: Vec<&Series> = Vec::new();
        for s in &self.series {
            if !out.iter().any(|o| o.label == s.label) {
                out.push(s);
            }
        }
        out
    }

    /// One row per label (a short sample of its stroke and its label),
    /// then the notes; a group of class `legend`, so that readers of the
    /// picture can tell its samples from the paths.
    fn legend(&self, top: f64) -> Group {
        let mut g = Group::new().set("class", "legend");
        let mut y = top + ROW / 2.0;
        for s in self.legend_entries() {
            let sample = format!("{:.1},{y:.1} {:.1},{y:.1}", MARGIN[0], MARGIN[0] + 36.0);
            g = g.add(stroked(sample, &s.stroke));
            g = g.add(text(MARGIN[0] + 44.0, y + 4.0, 12, "start", &s.label));
            y += ROW;
        }
        for n in &self.notes {
            g = g.add(text(MARGIN[0], y + 4.0, 11, "start", n));
            y += ROW;
        }
        g
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_scales_and_vertical_axis_up() {
        let s = Series {
            label: "l".into(),
            stroke: Stroke::solid("#000", 1.0),
            points: vec![[0.0, 0.0], [10.0, 5.0]],
            hover: None,
        };
        let f = Frame::around(std::slice::from_ref(&s));
        let (x0, y0) = f.pixel([0.0, 0.0]);
        let (x1, y1) = f.pixel([10.0, 5.0]);
        assert!(((x1 - x0) - 2.0 * (y0 - y1)).abs() < 1e-9);
        assert!(y1 < y0);
    }

    #[test]
    fn ticks_are_round_numbers() {
        assert_eq!(tick_step(60.0), 10.0);
        assert_eq!(tick_step(7.0), 2.0);
        assert!((tick_step(0.3) - 0.05).abs() < 1e-12);
        assert_eq!(ticks(-12.0, 31.0, 10.0), vec![-10.0, 0.0, 10.0, 20.0, 30.0]);
        assert_eq!(label(-0.0), "0");
        assert_eq!(label(2.50), "2.5");
        assert_eq!(label(-10.0), "-10");
    }

    #[test]
    fn the_same_plot_gives_the_same_text() {
        let plot = || {
            Plot::new("t")
                .line(
                    "a",
                    Stroke::dashed("#d22", 1.5, "6 3"),
                    vec![[0.0, 0.0], [3.0, 4.0]],
                )
                .note("n")
                .to_svg()
        };
        let svg = plot();
        assert_eq!(svg, plot());
        assert!(svg.contains(r#"stroke-dasharray="6 3""#));
        // The svg crate puts a text's content on a line of its own.
        assert!(svg.contains("\na\n</text>") && svg.contains("\nn\n</text>"));
    }
}

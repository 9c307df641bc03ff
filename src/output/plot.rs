//! Line charts of history columns against time, as SVG (vector, with text, and a tooltip on
//! each point that has one) and PNG (that SVG rendered by resvg, text in DejaVu Sans, which
//! the binary embeds). Log axes are
//! ticked at decades, or at 1, 2 and 5 times a power of ten where they span less than three. Every run writes `forces` (the contact forces, with any exact
//! curve the scene gives) and `energies`; `impact plot DIR --columns a,b` draws any columns.

use std::path::Path;

use crate::error::{ImpactError, Result};

pub(crate) const WIDTH: usize = 800;
pub(crate) const HEIGHT: usize = 480;
const LEFT: f64 = 84.0;
const RIGHT: f64 = 20.0;
const TOP: f64 = 36.0;
const BOTTOM: f64 = 48.0;

/// Series colours (RGB); exact curves are drawn dashed in black.
const PALETTE: [[u8; 3]; 10] = [
    [31, 119, 180],
    [214, 39, 40],
    [44, 160, 44],
    [255, 127, 14],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [188, 189, 34],
    [23, 190, 207],
    [127, 127, 127],
];
const BLACK: [u8; 3] = [0, 0, 0];

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    Line,
    /// Exact solutions: dashed, black.
    Exact,
    /// Points only (one per run of a study).
    Markers,
    /// Crosses without a line (failed runs).
    Crosses,
}

/// One curve.
#[derive(Debug, Clone)]
pub struct Series {
    pub name: String,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub style: Style,
    /// Each point's tooltip in the SVG (a study's run: its mesh and step); empty for none.
    pub labels: Vec<String>,
}

/// Crosses of failed runs: one colour per series of them (one per failure kind).
const FAILED: [[u8; 3]; 4] = [
    [110, 110, 110],
    [160, 20, 20],
    [230, 120, 0],
    [120, 40, 160],
];

#[derive(Debug, Clone)]
pub struct Chart {
    pub title: String,
    pub x_label: String,
    pub series: Vec<Series>,
    /// Logarithmic axes (non-positive values are left out).
    pub log_x: bool,
    pub log_y: bool,
}

/// Ticks of an axis from `lo` to `hi` in plotted coordinates (log10 on a log axis): their
/// positions and labels.
fn axis_ticks(lo: f64, hi: f64, log: bool) -> Vec<(f64, String)> {
    match log {
        true => log_ticks(lo, hi),
        false => ticks(lo, hi).into_iter().map(|t| (t, label(t))).collect(),
    }
}

/// Ticks of a log axis over [lo, hi] (decades): every decade where the axis spans three or
/// more (every second, fifth, ... where it spans many), else 1, 2 and 5 times each power of
/// ten inside it (then 1 to 9 times where those are too few), each labelled with its value.
fn log_ticks(lo: f64, hi: f64) -> Vec<(f64, String)> {
    let (a, b) = (lo.ceil() as i64, hi.floor() as i64);
    if b - a >= 3 {
        let every = (b - a) / 9 + 1;
        return (a..=b)
            .filter(|k| k.rem_euclid(every) == 0)
            .map(|k| (k as f64, power_label(1, k)))
            .collect();
    }
    let decades = (lo.floor() as i64)..=(hi.ceil() as i64);
    let within = |mantissas: &[i64]| -> Vec<(f64, String)> {
        decades
            .clone()
            .flat_map(|k| mantissas.iter().map(move |&m| (m, k)))
            .map(|(m, k)| ((m as f64).log10() + k as f64, m, k))
            .filter(|&(t, _, _)| t >= lo - 1e-9 && t <= hi + 1e-9)
            .map(|(t, m, k)| (t, power_label(m, k)))
            .collect()
    };
    let ticks = within(&[1, 2, 5]);
    if ticks.len() >= 3 {
        return ticks;
    }
    let ticks = within(&[1, 2, 3, 4, 5, 6, 7, 8, 9]);
    if ticks.len() >= 2 {
        return ticks;
    }
    // less than a step of the mantissa: round values, as on a linear axis
    let (a, b) = (10f64.powf(lo), 10f64.powf(hi));
    (ticks_between(a, b).into_iter())
        .map(|t| (t.log10(), label(t)))
        .collect()
}

/// `m` times ten to the `k`: plain from 1e-3 to 1e4, else `me k`.
fn power_label(m: i64, k: i64) -> String {
    if (-3..=4).contains(&k) {
        label(m as f64 * 10f64.powi(k as i32))
    } else {
        format!("{m}e{k}")
    }
}

/// [`ticks`] of a positive range.
fn ticks_between(lo: f64, hi: f64) -> Vec<f64> {
    ticks(lo, hi).into_iter().filter(|t| *t > 0.0).collect()
}

/// Tick positions covering [lo, hi] with a step of 1, 2 or 5 times a power of ten.
pub(crate) fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    // a span wider than f64 holds (values near 1e308 of both signs) is taken as the largest
    let span = hi - lo;
    let span = if span.is_finite() { span } else { f64::MAX };
    let range = span.max(f64::MIN_POSITIVE);
    let raw = range / 6.0;
    let p = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * p)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * p);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

fn label(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-3..1e4).contains(&a) {
        let s = format!("{v:.4}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.to_string()
    } else {
        format!("{v:.2e}")
    }
}

fn colour_hex(c: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

impl Chart {
    /// A data point in plotted coordinates (log10 on a log axis), if it can be drawn.
    fn tx(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        let x = if self.log_x { x.log10() } else { x };
        let y = if self.log_y { y.log10() } else { y };
        (x.is_finite() && y.is_finite()).then_some((x, y))
    }

    /// A series' drawable points in pixels (`map`: plotted coordinates to pixels).
    fn series_points(
        &self,
        ser: &Series,
        map: &impl Fn(f64, f64) -> (f64, f64),
    ) -> Vec<(f64, f64)> {
        self.labelled_points(ser, map)
            .into_iter()
            .map(|p| p.1)
            .collect()
    }

    /// [`Self::series_points`] with each point's tooltip.
    fn labelled_points<'a>(
        &self,
        ser: &'a Series,
        map: &impl Fn(f64, f64) -> (f64, f64),
    ) -> Vec<(Option<&'a str>, (f64, f64))> {
        (ser.x.iter().zip(&ser.y).enumerate())
            .filter_map(|(k, (&x, &y))| {
                let label = ser.labels.get(k).map(String::as_str);
                self.tx(x, y).map(|(x, y)| (label, map(x, y)))
            })
            .collect()
    }

    /// The plotted range, padded; zero included for a linear y.
    fn bounds(&self) -> (f64, f64, f64, f64) {
        let y_init = if self.log_y {
            [f64::INFINITY, f64::NEG_INFINITY]
        } else {
            [0.0, 0.0]
        };
        let mut b = [f64::INFINITY, f64::NEG_INFINITY, y_init[0], y_init[1]];
        for s in &self.series {
            for (&x, &y) in s.x.iter().zip(&s.y) {
                if let Some((x, y)) = self.tx(x, y) {
                    b[0] = b[0].min(x);
                    b[1] = b[1].max(x);
                    b[2] = b[2].min(y);
                    b[3] = b[3].max(y);
                }
            }
        }
        if !b[0].is_finite() {
            b[0] = 0.0;
            b[1] = 1.0;
        }
        if !b[2].is_finite() {
            b[2] = 0.0;
            b[3] = 1.0;
        }
        if b[1] <= b[0] {
            b[1] = b[0] + 1.0;
        }
        // halves, so that a span of values near 1e308 of both signs does not overflow
        let half = 0.5 * b[3] - 0.5 * b[2];
        let (y0, y1) = if half <= f64::MIN_POSITIVE {
            (b[2] - 1.0, b[3] + 1.0)
        } else {
            (b[2] - 0.1 * half, b[3] + 0.1 * half)
        };
        (b[0], b[1], y0.max(f64::MIN), y1.min(f64::MAX))
    }

    /// Maps plotted coordinates to pixels.
    fn mapping(&self) -> impl Fn(f64, f64) -> (f64, f64) {
        let (x0, x1, y0, y1) = self.bounds();
        let (w, h) = (WIDTH as f64 - LEFT - RIGHT, HEIGHT as f64 - TOP - BOTTOM);
        // the fraction of [a, b] at v, in halves (see `bounds`)
        let frac = |v: f64, a: f64, b: f64| (0.5 * v - 0.5 * a) / (0.5 * b - 0.5 * a);
        move |x, y| {
            (
                LEFT + frac(x, x0, x1) * w,
                TOP + (1.0 - frac(y, y0, y1)) * h,
            )
        }
    }

    /// Left end of the legend's line samples: room for the longest name in the 8 px font.
    fn legend_x(&self) -> f64 {
        let longest = self
            .series
            .iter()
            .map(|s| s.name.chars().count())
            .max()
            .unwrap_or(0);
        (WIDTH as f64 - RIGHT - 12.0 - 30.0 - 8.0 * longest as f64).max(LEFT + 8.0)
    }

    fn colour(&self, i: usize) -> [u8; 3] {
        match self.series[i].style {
            Style::Exact => BLACK,
            Style::Crosses => {
                let k = self.series[..i]
                    .iter()
                    .filter(|s| s.style == Style::Crosses)
                    .count();
                FAILED[k % FAILED.len()]
            }
            _ => {
                let k = self.series[..i]
                    .iter()
                    .filter(|s| matches!(s.style, Style::Line | Style::Markers))
                    .count();
                PALETTE[k % PALETTE.len()]
            }
        }
    }

    pub fn svg(&self) -> String {
        let (x0, x1, y0, y1) = self.bounds();
        let map = self.mapping();
        let (right, bottom) = (WIDTH as f64 - RIGHT, HEIGHT as f64 - BOTTOM);
        let mut s = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{WIDTH}\" height=\"{HEIGHT}\" font-family=\"sans-serif\" font-size=\"12\">\n\
<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
<text x=\"{}\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">{}</text>\n",
            WIDTH / 2,
            xml(&self.title)
        );
        for (t, l) in axis_ticks(x0, x1, self.log_x) {
            let (px, _) = map(t, y0);
            s += &format!(
                "<line x1=\"{px:.1}\" y1=\"{TOP}\" x2=\"{px:.1}\" y2=\"{bottom}\" stroke=\"#e1e1e1\"/>\n\
<text x=\"{px:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{l}</text>\n",
                bottom + 16.0,
            );
        }
        for (t, l) in axis_ticks(y0, y1, self.log_y) {
            let (_, py) = map(x0, t);
            s += &format!(
                "<line x1=\"{LEFT}\" y1=\"{py:.1}\" x2=\"{right}\" y2=\"{py:.1}\" stroke=\"#e1e1e1\"/>\n\
<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{l}</text>\n",
                LEFT - 6.0,
                py + 4.0,
            );
        }
        s += &format!(
            "<rect x=\"{LEFT}\" y=\"{TOP}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"none\" stroke=\"black\"/>\n\
<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>\n",
            right - LEFT,
            bottom - TOP,
            (LEFT + right) / 2.0,
            HEIGHT as f64 - 8.0,
            xml(&self.x_label)
        );
        for (i, ser) in self.series.iter().enumerate() {
            let col = colour_hex(self.colour(i));
            let pts = self.series_points(ser, &map);
            let dash = if ser.style == Style::Exact {
                " stroke-dasharray=\"6,4\""
            } else {
                ""
            };
            if matches!(ser.style, Style::Line | Style::Exact) {
                let line: Vec<String> = pts.iter().map(|(x, y)| format!("{x:.2},{y:.2}")).collect();
                let width = if ser.style == Style::Markers {
                    1.0
                } else {
                    1.6
                };
                s += &format!(
                    "<polyline fill=\"none\" stroke=\"{col}\" stroke-width=\"{width}\"{dash} points=\"{}\"/>\n",
                    line.join(" ")
                );
            }
            for (label, (x, y)) in self.labelled_points(ser, &map) {
                let tip = label
                    .map(|l| format!("<title>{}</title>", xml(l)))
                    .unwrap_or_default();
                match ser.style {
                    Style::Markers => {
                        s += &format!("<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"3.5\" fill=\"{col}\">{tip}</circle>\n")
                    }
                    Style::Crosses => {
                        s += &format!(
                            "<path d=\"M{:.2},{:.2}L{:.2},{:.2}M{:.2},{:.2}L{:.2},{:.2}\" stroke=\"{col}\" stroke-width=\"2\">{tip}</path>\n",
                            x - 5.0, y - 5.0, x + 5.0, y + 5.0, x - 5.0, y + 5.0, x + 5.0, y - 5.0
                        )
                    }
                    _ => {}
                }
            }
            let (ly, lx) = (TOP + 16.0 + 16.0 * i as f64, self.legend_x());
            s += &match ser.style {
                Style::Markers => format!(
                    "<circle cx=\"{:.1}\" cy=\"{ly:.1}\" r=\"3.5\" fill=\"{col}\"/>\n",
                    lx + 12.0
                ),
                Style::Crosses => format!(
                    "<path d=\"M{:.1},{:.1}L{:.1},{:.1}M{:.1},{:.1}L{:.1},{:.1}\" stroke=\"{col}\" stroke-width=\"2\"/>\n",
                    lx + 7.0, ly - 5.0, lx + 17.0, ly + 5.0, lx + 7.0, ly + 5.0, lx + 17.0, ly - 5.0
                ),
                _ => format!(
                    "<line x1=\"{lx:.1}\" y1=\"{ly:.1}\" x2=\"{:.1}\" y2=\"{ly:.1}\" stroke=\"{col}\" stroke-width=\"2\"{dash}/>\n",
                    lx + 24.0
                ),
            };
            s += &format!(
                "<text x=\"{:.1}\" y=\"{:.1}\">{}</text>\n",
                lx + 30.0,
                ly + 4.0,
                xml(&ser.name)
            );
        }
        s += "</svg>\n";
        s
    }

    /// RGB pixels, row by row: the SVG rendered by resvg, its text in DejaVu Sans.
    pub fn pixels(&self) -> Vec<u8> {
        pixels(&self.svg(), WIDTH as u32, HEIGHT as u32)
    }

    pub fn png(&self) -> Vec<u8> {
        render_png(&self.svg(), WIDTH as u32, HEIGHT as u32)
    }

    /// Writes `dir/name.svg` and `dir/name.png`.
    pub fn write(&self, dir: &Path, name: &str) -> Result<()> {
        let svg = dir.join(format!("{name}.svg"));
        super::file::write_whole(&svg, self.svg().as_bytes())?;
        let png = dir.join(format!("{name}.png"));
        super::file::write_whole(&png, &self.png())
    }
}

use super::file::xml_escape as xml;

/// RGB pixels, row by row, of `svg` (an SVG of our own, `width` x `height`, on an opaque
/// background) rendered by resvg, its text in DejaVu Sans.
pub(crate) fn pixels(svg: &str, width: u32, height: u32) -> Vec<u8> {
    use resvg::{tiny_skia, usvg};
    let tree = usvg::Tree::from_str(svg, fonts()).expect("our own SVG parses");
    let mut pixmap = tiny_skia::Pixmap::new(width, height).expect("a picture has a size");
    resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    // the background is opaque white, so premultiplied RGBA is plain RGBA
    (pixmap.data().chunks_exact(4))
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect()
}

/// `svg` rendered ([`pixels`]) as an RGB PNG.
pub(crate) fn render_png(svg: &str, width: u32, height: u32) -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, width, height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().expect("png header to memory");
        w.write_image_data(&pixels(svg, width, height))
            .expect("png data to memory");
    }
    out
}

/// The SVG renderer's options: DejaVu Sans, embedded, as every family (no system font is
/// read, so a chart looks the same on every machine). Built once.
fn fonts() -> &'static resvg::usvg::Options<'static> {
    static OPTIONS: std::sync::OnceLock<resvg::usvg::Options<'static>> = std::sync::OnceLock::new();
    OPTIONS.get_or_init(|| {
        let mut o = resvg::usvg::Options::default();
        let db = o.fontdb_mut();
        db.load_font_data(dejavu::sans::regular().to_vec());
        db.set_sans_serif_family("DejaVu Sans");
        o.font_family = "DejaVu Sans".into();
        o
    })
}

/// Columns of a `history.csv` by name.
pub struct Table {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl Table {
    /// Reads a history: a header and at least one row, every row as many numbers as the
    /// header has columns; otherwise an error naming the line (a file cut short by a full
    /// disk, or edited).
    pub fn read(path: &Path) -> Result<Table> {
        let text = crate::limits::read_own_text(path).map_err(|source| ImpactError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let bad = |line: usize, message: String| ImpactError::Malformed {
            path: path.to_path_buf(),
            line: Some(line),
            message,
        };
        let mut lines = text.lines().enumerate();
        let columns: Vec<String> = lines
            .next()
            .map_or("", |(_, l)| l)
            .split(',')
            .map(String::from)
            .collect();
        let mut rows = Vec::new();
        for (i, l) in lines.filter(|(_, l)| !l.trim().is_empty()) {
            let row = l
                .split(',')
                .map(|v| v.parse::<f64>().ok())
                .collect::<Option<Vec<f64>>>()
                .ok_or_else(|| bad(i + 1, "the row is not a row of numbers".into()))?;
            if row.len() != columns.len() {
                return Err(bad(
                    i + 1,
                    format!(
                        "the row holds {} values and the header {} columns (was the file cut short or edited?)",
                        row.len(),
                        columns.len()
                    ),
                ));
            }
            rows.push(row);
        }
        // every row is written with its line end: a last line without one was cut short
        if !text.is_empty() && !text.ends_with('\n') {
            return Err(bad(
                text.lines().count(),
                "the last row has no line end: the file was cut short".into(),
            ));
        }
        if rows.is_empty() {
            return Err(ImpactError::Malformed {
                path: path.to_path_buf(),
                line: None,
                message: "the history holds no rows".into(),
            });
        }
        Ok(Table { columns, rows })
    }

    pub fn col(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.columns.iter().position(|c| c == name)?;
        Some(self.rows.iter().map(|r| r[i]).collect())
    }
}

/// A chart of the named columns of `table` against time.
pub fn chart(table: &Table, title: &str, columns: &[String]) -> Chart {
    let t = table.col("time").unwrap_or_default();
    Chart {
        title: title.into(),
        x_label: "time".into(),
        series: columns
            .iter()
            .filter_map(|c| {
                table.col(c).map(|y| Series {
                    name: c.clone(),
                    x: t.clone(),
                    y,
                    style: Style::Line,
                    labels: Vec::new(),
                })
            })
            .collect(),
        log_x: false,
        log_y: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_numbers_inside_the_range() {
        assert_eq!(
            ticks(0.0, 0.4),
            vec![0.0, 0.1, 0.2, 0.30000000000000004, 0.4]
        );
        let t = ticks(-0.013, 0.52);
        assert!(t.len() >= 4 && t.len() <= 8, "{t:?}");
        assert!(t.iter().all(|v| (-0.013..=0.52).contains(v)));
        assert_eq!(label(0.5), "0.5");
        assert_eq!(label(2.5e-6), "2.50e-6");
    }

    /// A log axis within a decade is labelled 1-2-5 by value, each label once; across many
    /// decades, by decades.
    #[test]
    fn log_ticks_are_distinct_values() {
        let labels = |lo: f64, hi: f64| -> Vec<String> {
            log_ticks(lo.log10(), hi.log10())
                .into_iter()
                .map(|t| t.1)
                .collect()
        };
        assert_eq!(labels(1.5e-3, 3e-2), ["0.002", "0.005", "0.01", "0.02"]);
        assert_eq!(labels(1.5e-5, 3e-4), ["2e-5", "5e-5", "1e-4", "2e-4"]);
        assert_eq!(labels(1.0, 9.0), ["1", "2", "5"]);
        assert_eq!(labels(2.5, 4.5), ["3", "4"]);
        assert_eq!(
            labels(1e-6, 1e2),
            ["1e-6", "1e-5", "1e-4", "0.001", "0.01", "0.1", "1", "10", "100"]
        );
        for (lo, hi) in [(1.5e-3, 3e-2), (0.8, 40.0), (1e-9, 1e9), (0.11, 0.19)] {
            let l = labels(lo, hi);
            let mut d = l.clone();
            d.dedup();
            assert_eq!(l, d, "repeated labels {l:?}");
            assert!(l.len() >= 2 && l.len() <= 10, "{l:?}");
        }
    }

    /// Values near 1e308 of both signs draw at finite coordinates.
    #[test]
    fn extreme_values_draw_at_finite_coordinates() {
        let chart = Chart {
            title: "t".into(),
            x_label: "time".into(),
            series: vec![Series {
                name: "a".into(),
                x: vec![0.0, 1.0, 2.0],
                y: vec![-1.7e308, 1e308, 1.7e308],
                style: Style::Line,
                labels: Vec::new(),
            }],
            log_x: false,
            log_y: false,
        };
        let svg = chart.svg();
        assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
    }

    /// A chart's PNG decodes to the right size and holds the series colour (where the line
    /// is drawn, antialiased), dark text and a white background.
    #[test]
    fn png_holds_the_curves() {
        let chart = Chart {
            title: "test".into(),
            x_label: "time".into(),
            series: vec![Series {
                name: "a".into(),
                x: vec![0.0, 1.0, 2.0],
                y: vec![0.0, 1.0, 0.5],
                style: Style::Line,
                labels: Vec::new(),
            }],
            log_x: false,
            log_y: false,
        };
        let px = chart.pixels();
        assert_eq!(px.len(), 3 * WIDTH * HEIGHT);
        let near = |c: [u8; 3], tol: i32| {
            move |p: &[u8]| (0..3).all(|k| (i32::from(p[k]) - i32::from(c[k])).abs() <= tol)
        };
        let count = |f: &dyn Fn(&[u8]) -> bool| px.chunks_exact(3).filter(|p| f(p)).count();
        assert!(count(&near(PALETTE[0], 40)) > 200, "the curve");
        assert!(count(&near(BLACK, 40)) > 200, "text and frame");
        assert!(
            count(&near([255, 255, 255], 0)) > WIDTH * HEIGHT / 2,
            "background"
        );
        let png = chart.png();
        assert_eq!(&png[1..4], b"PNG");
    }
}

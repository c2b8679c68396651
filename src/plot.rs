//! Line plots written as PNG and SVG, whole or not at all (a temporary file, then a
//! rename), with the embedded DejaVu Sans font so that no system font is needed.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Once;

use anyhow::{Context, Result, anyhow};
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;

static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Registers the embedded font as plotters' "sans-serif" (once per process).
fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The font is embedded and known good: failure here is a build defect.
        plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
            .unwrap_or_else(|_| panic!("embedded DejaVu Sans failed to load"));
    });
}

/// One named curve.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend name.
    pub name: String,
    /// Points `(x, y)`; points with a non-finite coordinate, or not positive on a log axis,
    /// are skipped.
    pub points: Vec<(f64, f64)>,
}

/// Linear or logarithmic axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    /// Linear.
    Linear,
    /// Base-10 logarithmic.
    Log,
}

/// A plot of several curves, drawn with lines and point markers.
#[derive(Clone, Debug)]
pub struct Plot {
    /// Title above the chart; one longer than the chart is wide is cut to fit
    /// ([`fit_title`]).
    pub title: String,
    /// Label of the horizontal axis.
    pub x_label: String,
    /// Label of the vertical axis.
    pub y_label: String,
    /// Horizontal scale.
    pub x_scale: Scale,
    /// Vertical scale.
    pub y_scale: Scale,
    /// The curves.
    pub series: Vec<Series>,
    /// Optional fixed vertical range (else fitted to the data).
    pub y_range: Option<(f64, f64)>,
    /// Draw each series as a line through its points (true) or as markers only (false,
    /// for scattered data such as timings).
    pub lines: bool,
}

const SIZE: (u32, u32) = (1000, 700);
/// Margin around the chart [px].
const MARGIN: u32 = 15;
/// Font size of the title [px].
pub const TITLE_SIZE: u32 = 26;
/// The widest title drawn [px]: the image less its margins and some air either side.
pub const TITLE_WIDTH: u32 = SIZE.0 - 2 * MARGIN - 30;

/// The width of `text` in the title's font [px], as the chart lays it out.
pub fn title_width(text: &str) -> Result<u32> {
    register_font();
    let font = ("sans-serif", f64::from(TITLE_SIZE)).into_font();
    let (w, _) = font
        .box_size(text)
        .map_err(|e| anyhow!("measuring the title {text:?}: {e:?}"))?;
    Ok(w)
}

/// `title` cut to at most `max` pixels wide as `width` measures it: whole when it fits, else
/// the longest run of its comma-separated clauses that fits (when that keeps at least half the
/// width), else the longest run of its words, else of its characters, followed by an
/// ellipsis.
pub fn fit_title(
    title: &str,
    max: u32,
    mut width: impl FnMut(&str) -> Result<u32>,
) -> Result<String> {
    let title = title.trim();
    if width(title)? <= max {
        return Ok(title.to_string());
    }
    let cut = |head: &str| {
        let head = head.trim_end_matches(|c: char| c.is_whitespace() || ",;:-(".contains(c));
        format!("{head}\u{2026}")
    };
    // ends of the clauses (before each ", "), of the words, of the characters: longest first
    let clauses: Vec<usize> = title.match_indices(", ").map(|(i, _)| i).collect();
    let words: Vec<usize> = title.match_indices(' ').map(|(i, _)| i).collect();
    let chars: Vec<usize> = title.char_indices().map(|(i, _)| i).skip(1).collect();
    for (ends, least) in [(clauses, max / 2), (words, 0), (chars, 0)] {
        for &end in ends.iter().rev() {
            let t = cut(&title[..end]);
            let w = width(&t)?;
            if w <= max {
                if w >= least {
                    return Ok(t);
                }
                break;
            }
        }
    }
    Ok("\u{2026}".into())
}
const COLOURS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
];

impl Plot {
    fn usable(&self, p: &(f64, f64)) -> bool {
        let in_range = self.y_range.is_none_or(|(a, b)| p.1 >= a && p.1 <= b);
        in_range
            && p.0.is_finite()
            && p.1.is_finite()
            && (self.x_scale == Scale::Linear || p.0 > 0.0)
            && (self.y_scale == Scale::Linear || p.1 > 0.0)
    }

    fn range(&self, pick: impl Fn(&(f64, f64)) -> f64, scale: Scale) -> Range<f64> {
        let vals = self
            .series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|p| self.usable(p))
            .map(pick);
        let (lo, hi) = vals.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
        if !lo.is_finite() {
            return if scale == Scale::Log {
                0.1..10.0
            } else {
                0.0..1.0
            };
        }
        match scale {
            Scale::Log => {
                let (l, h) = (
                    lo.log10().floor(),
                    hi.log10().ceil().max(lo.log10().floor() + 1.0),
                );
                10f64.powf(l)..10f64.powf(h)
            }
            Scale::Linear => {
                let pad = 0.02 * (hi - lo).max(1e-12);
                (lo - pad)..(hi + pad)
            }
        }
    }

    /// Writes `<stem>.png` and `<stem>.svg`; returns their paths.
    pub fn write(&self, stem: &Path) -> Result<Vec<PathBuf>> {
        register_font();
        let png = stem.with_extension("png");
        let svg = stem.with_extension("svg");
        // PNG: drawn to a temporary file with a .png extension (the encoder picks the
        // format from it), then renamed into place.
        let tmp_png = stem.with_extension("part.png");
        {
            let root = BitMapBackend::new(&tmp_png, SIZE).into_drawing_area();
            self.draw(root)
                .with_context(|| format!("drawing {}", png.display()))?;
        }
        std::fs::rename(&tmp_png, &png).with_context(|| format!("writing {}", png.display()))?;
        let mut text = String::new();
        {
            let root = SVGBackend::with_string(&mut text, SIZE).into_drawing_area();
            self.draw(root)
                .with_context(|| format!("drawing {}", svg.display()))?;
        }
        crate::write_atomically(&svg, text.as_bytes())?;
        Ok(vec![png, svg])
    }

    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, plotters::coord::Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        let xr = self.range(|p| p.0, self.x_scale);
        let yr = match self.y_range {
            Some((a, b)) => a..b,
            None => self.range(|p| p.1, self.y_scale),
        };
        match (self.x_scale, self.y_scale) {
            (Scale::Log, Scale::Log) => self.draw_in(root, xr.log_scale(), yr.log_scale()),
            (Scale::Log, Scale::Linear) => self.draw_in(root, xr.log_scale(), yr),
            (Scale::Linear, Scale::Log) => self.draw_in(root, xr, yr.log_scale()),
            (Scale::Linear, Scale::Linear) => self.draw_in(root, xr, yr),
        }
    }

    fn draw_in<DB, X, Y>(
        &self,
        root: DrawingArea<DB, plotters::coord::Shift>,
        x: X,
        y: Y,
    ) -> Result<()>
    where
        DB: DrawingBackend,
        DB::ErrorType: 'static,
        X: AsRangedCoord<Value = f64>,
        Y: AsRangedCoord<Value = f64>,
        X::CoordDescType: ValueFormatter<f64>,
        Y::CoordDescType: ValueFormatter<f64>,
    {
        let err = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("{e:?}");
        let tick = |scale: Scale| {
            move |v: &f64| match scale {
                Scale::Log => format!("{:.0e}", v),
                Scale::Linear => {
                    let s = format!("{v:.3}");
                    s.trim_end_matches('0').trim_end_matches('.').to_string()
                }
            }
        };
        let (xt, yt) = (tick(self.x_scale), tick(self.y_scale));
        root.fill(&WHITE).map_err(err)?;
        let title = fit_title(&self.title, TITLE_WIDTH, title_width)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&title, ("sans-serif", TITLE_SIZE))
            .margin(MARGIN)
            .x_label_area_size(55)
            .y_label_area_size(85)
            .build_cartesian_2d(x, y)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .x_label_formatter(&xt)
            .y_label_formatter(&yt)
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(err)?;
        for (i, s) in self.series.iter().enumerate() {
            let colour = COLOURS[i % COLOURS.len()];
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|p| self.usable(p))
                .collect();
            let legend = move |(x, y): (i32, i32)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3))
            };
            if !self.lines {
                chart
                    .draw_series(pts.iter().map(|p| Circle::new(*p, 2, colour.filled())))
                    .map_err(err)?
                    .label(s.name.as_str())
                    .legend(legend);
                continue;
            }
            chart
                .draw_series(LineSeries::new(pts.iter().copied(), colour.stroke_width(2)))
                .map_err(err)?
                .label(s.name.as_str())
                .legend(legend);
            if pts.len() <= 60 {
                chart
                    .draw_series(pts.iter().map(|p| Circle::new(*p, 3, colour.filled())))
                    .map_err(err)?;
            }
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 16))
            .position(SeriesLabelPosition::LowerRight)
            .draw()
            .map_err(err)?;
        root.present().map_err(err)?;
        Ok(())
    }
}

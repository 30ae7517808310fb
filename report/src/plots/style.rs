//! One look for every figure: a colour, a line pattern and a marker per law (so a curve under
//! another stays visible, also in grey print), compact tick labels, a plain grid, one legend
//! outside the plots, curves decimated without losing their peaks and broken at gaps.
use lander::laws::Law;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::ops::Range;

/// The marker of a law's curve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    Circle,
    Triangle,
    Square,
    Cross,
}

/// How a law is drawn in every figure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Look {
    pub colour: RGBColor,
    /// Dash and gap in pixels; `None` for a solid line.
    pub dashes: Option<(u32, u32)>,
    pub width: u32,
    pub marker: Marker,
    /// Where along a tenth of the axis the markers sit, so that overlapping curves keep
    /// distinct markers.
    pub marker_shift: f64,
}

/// The paper's two laws keep the paper's look: coupled red, solid, circles; decoupled blue,
/// short dashes, triangles.
const COUPLED: Look = Look {
    colour: RGBColor(214, 39, 40),
    dashes: None,
    width: 3,
    marker: Marker::Circle,
    marker_shift: 0.0,
};
const DECOUPLED: Look = Look {
    colour: RGBColor(31, 119, 180),
    dashes: Some((6, 5)),
    width: 2,
    marker: Marker::Triangle,
    marker_shift: 2.0 / 3.0,
};

/// The looks of every other law the GNC FMU offers, one picked by the law's name (the same
/// in every figure, whatever other laws fly beside it).
const OTHERS: [Look; 4] = [
    Look {
        colour: RGBColor(148, 103, 189),
        dashes: Some((3, 4)),
        width: 3,
        marker: Marker::Cross,
        marker_shift: 1.0 / 6.0,
    },
    Look {
        colour: RGBColor(44, 160, 44),
        dashes: Some((14, 6)),
        width: 3,
        marker: Marker::Square,
        marker_shift: 1.0 / 3.0,
    },
    Look {
        colour: RGBColor(255, 127, 14),
        dashes: Some((10, 3)),
        width: 2,
        marker: Marker::Cross,
        marker_shift: 1.0 / 2.0,
    },
    Look {
        colour: RGBColor(140, 86, 75),
        dashes: Some((2, 6)),
        width: 3,
        marker: Marker::Square,
        marker_shift: 5.0 / 6.0,
    },
];

pub fn look(law: Law) -> Look {
    match law {
        Law::COUPLED => COUPLED,
        Law::DECOUPLED => DECOUPLED,
        other => {
            // FNV-1a: stable across runs and platforms, unlike std's hasher.
            let hash = other
                .name()
                .bytes()
                .fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
                    (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
                });
            OTHERS[(hash % OTHERS.len() as u64) as usize]
        }
    }
}

pub fn colour(law: Law) -> RGBColor {
    look(law).colour
}

/// Solid lines are stroked as filled polygons: an unfilled thick line comes out as a double
/// outline with plotters' bitmap backend.
pub fn line(law: Law, width: u32) -> ShapeStyle {
    colour(law).filled().stroke_width(width)
}

/// `laws` in the order they are drawn: the coupled law first, the paper's thin dashed
/// decoupled curve last, on top of the others; the rest by name between them.
pub fn draw_order(laws: impl IntoIterator<Item = Law>) -> Vec<Law> {
    let rank = |law: &Law| match *law {
        Law::COUPLED => 0,
        Law::DECOUPLED => 2,
        _ => 1,
    };
    let mut laws: Vec<Law> = laws.into_iter().collect();
    laws.sort_by(|a, b| rank(a).cmp(&rank(b)).then(a.name().cmp(b.name())));
    laws.dedup();
    laws
}

/// Pattern of a law's line.
pub fn dashes(law: Law) -> Option<(u32, u32)> {
    look(law).dashes
}

pub fn width(law: Law) -> u32 {
    look(law).width
}

/// Draws a law's curve (with its pattern, one polyline per gap-free piece, decimated to the
/// plot's pixel columns keeping every bucket's minimum and maximum) and ten markers evenly
/// spaced in x, shifted per law so that overlapping curves keep distinct markers. No legend
/// entry: a figure draws one legend, outside its plots ([`legend_strip`]).
pub fn draw_law_curve(
    chart: &mut Chart2d<'_>,
    law: Law,
    points: &[(f64, f64)],
) -> anyhow::Result<()> {
    let x_range = chart.x_range();
    let buckets = plot_buckets(chart);
    let pieces: Vec<Vec<(f64, f64)>> = segments(points)
        .into_iter()
        .map(|piece| decimate(&clip_x(&piece, &x_range), buckets))
        .filter(|piece| !piece.is_empty())
        .collect();
    let shift = marker_shift(law);
    let span = x_range.end - x_range.start;
    let markers: Vec<(f64, f64)> = (0..10)
        .filter_map(|k| {
            let x = x_range.start + span * (k as f64 + 0.1 + 0.8 * shift) / 10.0;
            nearest(&pieces, x, 0.02 * span)
        })
        .collect();
    stroke(chart, law, &pieces, &markers)
}

/// Draws a law's path that is sorted in neither coordinate (a ground track, an altitude
/// profile): broken where a value is not finite, decimated keeping its extremes, ten markers
/// spaced along it.
pub fn draw_law_path(
    chart: &mut Chart2d<'_>,
    law: Law,
    points: &[(f64, f64)],
) -> anyhow::Result<()> {
    let chunks = plot_buckets(chart);
    let mut pieces: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
    for &p in points {
        if p.0.is_finite() && p.1.is_finite() {
            pieces.last_mut().expect("a piece").push(p);
        } else if !pieces.last().expect("a piece").is_empty() {
            pieces.push(Vec::new());
        }
    }
    let pieces: Vec<Vec<(f64, f64)>> = pieces
        .into_iter()
        .filter(|p| !p.is_empty())
        .map(|p| decimate_path(&p, chunks, &[|q: &(f64, f64)| q.0, |q: &(f64, f64)| q.1]))
        .collect();
    let all: Vec<(f64, f64)> = pieces.iter().flatten().copied().collect();
    let every = (all.len() / 10).max(1);
    let skip = (marker_shift(law) * every as f64) as usize;
    let markers: Vec<(f64, f64)> = all.iter().copied().skip(skip).step_by(every).collect();
    stroke(chart, law, &pieces, &markers)
}

fn marker_shift(law: Law) -> f64 {
    look(law).marker_shift
}

fn stroke(
    chart: &mut Chart2d<'_>,
    law: Law,
    pieces: &[Vec<(f64, f64)>],
    markers: &[(f64, f64)],
) -> anyhow::Result<()> {
    let style = line(law, width(law));
    for piece in pieces {
        match dashes(law) {
            None => {
                chart.draw_series(LineSeries::new(piece.iter().copied(), style))?;
            }
            Some((dash, gap)) => {
                chart.draw_series(DashedLineSeries::new(
                    piece.iter().copied(),
                    dash,
                    gap,
                    style,
                ))?;
            }
        }
    }
    let c = colour(law);
    let marker = look(law).marker;
    let show = move |on: bool| if on { c.filled() } else { TRANSPARENT.filled() };
    let line = move |on: bool| show(on).stroke_width(2);
    chart.draw_series(markers.iter().map(|&p| {
        EmptyElement::at(p)
            + Circle::new((0, 0), 5, show(marker == Marker::Circle))
            + TriangleMarker::new((0, 0), 7, show(marker == Marker::Triangle))
            + Rectangle::new([(-4, -4), (4, 4)], show(marker == Marker::Square))
            + Cross::new((0, 0), 5, line(marker == Marker::Cross))
    }))?;
    Ok(())
}

/// The point nearest to `x` on `pieces`, if one is within `within` of it.
fn nearest(pieces: &[Vec<(f64, f64)>], x: f64, within: f64) -> Option<(f64, f64)> {
    let best = pieces
        .iter()
        .flatten()
        .min_by(|a, b| (a.0 - x).abs().total_cmp(&(b.0 - x).abs()))?;
    ((best.0 - x).abs() <= within).then_some(*best)
}

/// The points of a piece sorted in x that lie inside `x`, plus one on each side (so that a
/// line leaves the plot at its edge instead of stopping short of it).
pub fn clip_x(points: &[(f64, f64)], x: &Range<f64>) -> Vec<(f64, f64)> {
    let first = points.partition_point(|p| p.0 < x.start).saturating_sub(1);
    let last = (points.partition_point(|p| p.0 <= x.end) + 1).min(points.len());
    if first >= last {
        return Vec::new();
    }
    points[first..last].to_vec()
}

/// Buckets for [`decimate`] on a chart: one per three pixel columns of its plot area (finer
/// buckets turn a sub-pixel chatter into zigzags that a thick line strokes with spikes; the
/// extremes are kept either way).
pub fn plot_buckets(chart: &Chart2d<'_>) -> usize {
    let (w, _) = chart.plotting_area().dim_in_pixel();
    (w as usize / 3).max(2)
}

/// A step longer than this many times the series' typical (median) step is a gap: there is
/// no data between its ends, so no line is drawn across it.
pub const GAP_FACTOR: f64 = 5.0;

/// The gap-free pieces of a series sorted in x: split where x or y is not finite (that point
/// left out) and where x jumps by more than [`GAP_FACTOR`] times the median step.
pub fn segments(points: &[(f64, f64)]) -> Vec<Vec<(f64, f64)>> {
    let mut steps: Vec<f64> = points
        .windows(2)
        .map(|w| w[1].0 - w[0].0)
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    steps.sort_by(f64::total_cmp);
    let limit = steps
        .get(steps.len() / 2)
        .map_or(f64::INFINITY, |median| GAP_FACTOR * median);
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut piece: Vec<(f64, f64)> = Vec::new();
    for &p in points {
        if !(p.0.is_finite() && p.1.is_finite()) {
            if !piece.is_empty() {
                out.push(std::mem::take(&mut piece));
            }
            continue;
        }
        if piece.last().is_some_and(|last| p.0 - last.0 > limit) {
            out.push(std::mem::take(&mut piece));
        }
        piece.push(p);
    }
    if !piece.is_empty() {
        out.push(piece);
    }
    out
}

/// Min/max-preserving decimation of a series sorted in x: the x range is cut into `buckets`
/// equal buckets (a few per pixel column) and of each bucket the first and the last point and
/// those with the smallest and the largest y are kept, in their order. A peak narrower than
/// a bucket keeps its height, so a curve reaches the values the data reach (taking every
/// k-th point cut the coupled law's 28.43 deg/s yaw-rate peak to about 27.5).
pub fn decimate(points: &[(f64, f64)], buckets: usize) -> Vec<(f64, f64)> {
    let buckets = buckets.max(1);
    if points.len() <= 4 * buckets {
        return points.to_vec();
    }
    let (x0, x1) = (points[0].0, points[points.len() - 1].0);
    let scale = if x1 > x0 {
        buckets as f64 / (x1 - x0)
    } else {
        0.0
    };
    let bucket = |_: usize, p: &(f64, f64)| (((p.0 - x0) * scale) as usize).min(buckets - 1);
    extremes_per_bucket(points, bucket, &[|p: &(f64, f64)| p.1])
}

/// Decimation of a path sorted in no coordinate (a ground track, a 3-D trajectory): `chunks`
/// runs of consecutive points, each keeping its first and last point and its extreme points
/// in every coordinate `keys` gives.
pub fn decimate_path<T: Copy>(points: &[T], chunks: usize, keys: &[fn(&T) -> f64]) -> Vec<T> {
    let chunks = chunks.max(1);
    if points.len() <= (2 + 2 * keys.len()) * chunks {
        return points.to_vec();
    }
    let per = points.len().div_ceil(chunks);
    extremes_per_bucket(points, |k, _| k / per, keys)
}

/// Of each run of consecutive points in one bucket: the first, the last, and those with the
/// minimum and the maximum of each key, in their original order.
fn extremes_per_bucket<T: Copy>(
    points: &[T],
    bucket: impl Fn(usize, &T) -> usize,
    keys: &[fn(&T) -> f64],
) -> Vec<T> {
    let mut out = Vec::new();
    let mut start = 0;
    while start < points.len() {
        let b = bucket(start, &points[start]);
        let mut end = start + 1;
        while end < points.len() && bucket(end, &points[end]) == b {
            end += 1;
        }
        let mut keep = vec![start, end - 1];
        for key in keys {
            let by = |a: &usize, b: &usize| key(&points[*a]).total_cmp(&key(&points[*b]));
            keep.extend((start..end).min_by(by));
            keep.extend((start..end).max_by(by));
        }
        keep.sort_unstable();
        keep.dedup();
        out.extend(keep.into_iter().map(|k| points[k]));
        start = end;
    }
    out
}

/// What a legend entry shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Key {
    /// A law's curve: its colour, pattern and marker.
    Curve(Law),
    /// A law's curve drawn in long dashes (a retarget flight with the target only moved).
    Dashed(Law),
    /// A solid line in a law's colour (a re-planned retarget flight).
    Solid(Law),
    /// A shaded band in a law's colour, outlined.
    Band(Law),
    /// A thin line in a law's colour.
    Thin(Law),
    /// Short thin dashes in a law's colour (the range of all runs).
    Range(Law),
}

/// Legend entries, in the order shown: what each shows, and its text.
pub type Legend = Vec<(Key, String)>;

const LEGEND_FONT: u32 = 16;
const LEGEND_ROW: u32 = 26;
const SAMPLE: i32 = 40;
const LEGEND_GAP: i32 = 30;

/// Draws `entries`, in their order, as centred rows across the top of `area` (outside every
/// plot, so that no legend hides a curve) and returns the area below them.
pub fn legend_strip<'a>(
    area: &DrawingArea<BitMapBackend<'a>, Shift>,
    entries: &[(Key, String)],
) -> anyhow::Result<DrawingArea<BitMapBackend<'a>, Shift>> {
    let font = ("sans-serif", LEGEND_FONT).into_font().color(&BLACK);
    let (width, _) = area.dim_in_pixel();
    let widths: Vec<i32> = entries
        .iter()
        .map(|(_, text)| {
            let w = area
                .estimate_text_size(text, &font)
                .map_or(8 * text.len() as i32, |(w, _)| w as i32);
            SAMPLE + 8 + w + LEGEND_GAP
        })
        .collect();
    let mut rows: Vec<Vec<usize>> = vec![Vec::new()];
    let mut used = 0;
    for (k, &w) in widths.iter().enumerate() {
        let row = rows.last_mut().expect("one row");
        if !row.is_empty() && used + w > width as i32 - 20 {
            rows.push(vec![k]);
            used = w;
        } else {
            row.push(k);
            used += w;
        }
    }
    let height = LEGEND_ROW * rows.len() as u32 + 8;
    let (strip, rest) = area.split_vertically(height);
    for (r, row) in rows.iter().enumerate() {
        let total: i32 = row.iter().map(|&k| widths[k]).sum::<i32>() - LEGEND_GAP;
        let mut x = (width as i32 - total) / 2;
        let y = 4 + LEGEND_ROW as i32 * r as i32 + LEGEND_ROW as i32 / 2;
        for &k in row {
            let (key, text) = &entries[k];
            draw_key(&strip, *key, (x, y))?;
            strip.draw(&Text::new(
                text.clone(),
                (x + SAMPLE + 8, y),
                font.clone().pos(Pos::new(HPos::Left, VPos::Center)),
            ))?;
            x += widths[k];
        }
    }
    Ok(rest)
}

fn draw_key(
    area: &DrawingArea<BitMapBackend<'_>, Shift>,
    key: Key,
    (x, y): (i32, i32),
) -> anyhow::Result<()> {
    let dashed = |(dash, gap): (i32, i32), style: ShapeStyle| -> anyhow::Result<()> {
        let mut at = x;
        while at < x + SAMPLE {
            let to = (at + dash).min(x + SAMPLE);
            area.draw(&PathElement::new(vec![(at, y), (to, y)], style))?;
            at = to + gap;
        }
        Ok(())
    };
    let solid =
        |style: ShapeStyle| area.draw(&PathElement::new(vec![(x, y), (x + SAMPLE, y)], style));
    match key {
        Key::Curve(law) => {
            let style = line(law, width(law));
            match dashes(law) {
                None => solid(style)?,
                Some((d, g)) => dashed((d as i32, g as i32), style)?,
            }
            let c = colour(law);
            let (cx, cy) = (x + SAMPLE / 2, y);
            match look(law).marker {
                Marker::Circle => area.draw(&Circle::new((cx, cy), 5, c.filled()))?,
                Marker::Triangle => area.draw(&TriangleMarker::new((cx, cy), 7, c.filled()))?,
                Marker::Square => area.draw(&Rectangle::new(
                    [(cx - 4, cy - 4), (cx + 4, cy + 4)],
                    c.filled(),
                ))?,
                Marker::Cross => area.draw(&Cross::new((cx, cy), 5, c.stroke_width(2)))?,
            }
        }
        Key::Dashed(law) => dashed((8, 6), colour(law).filled().stroke_width(2))?,
        Key::Solid(law) => solid(colour(law).filled().stroke_width(3))?,
        Key::Band(law) => {
            let c = colour(law);
            let corners = [(x, y - 8), (x + SAMPLE, y + 8)];
            area.draw(&Rectangle::new(corners, c.mix(BAND_ALPHA).filled()))?;
            area.draw(&Rectangle::new(corners, c.mix(0.9).stroke_width(1)))?;
        }
        Key::Thin(law) => solid(colour(law).mix(0.9).stroke_width(1))?,
        Key::Range(law) => dashed((3, 3), colour(law).mix(0.7).stroke_width(1))?,
    }
    Ok(())
}

/// Opacity of a shaded band: low enough that overlapping bands of three laws stay apart.
pub const BAND_ALPHA: f64 = 0.2;

/// A vertical dashed line at each `(x, label)` inside the chart's x range, labelled at the
/// top of the plot (left of the line near the right edge).
pub fn phase_markers(chart: &mut Chart2d<'_>, markers: &[(f64, &str)]) -> anyhow::Result<()> {
    let (x, y) = (chart.x_range(), chart.y_range());
    let span = x.end - x.start;
    for &(t, label) in markers {
        if t < x.start || t > x.end + 1e-9 * span.abs() {
            continue;
        }
        chart.draw_series(DashedLineSeries::new(
            [(t, y.start), (t, y.end)],
            6,
            4,
            BLACK.mix(0.55).stroke_width(1),
        ))?;
        let (pos, dx) = if t > x.start + 0.7 * span {
            (Pos::new(HPos::Right, VPos::Top), -4)
        } else {
            (Pos::new(HPos::Left, VPos::Top), 4)
        };
        let font = ("sans-serif", 14)
            .into_font()
            .color(&BLACK.mix(0.8))
            .pos(pos);
        // On a white ground, so that a curve under the label does not hide it.
        let (w, h) = chart
            .plotting_area()
            .estimate_text_size(label, &font)
            .unwrap_or((7 * label.len() as u32, 14));
        let (w, h) = (w as i32, h as i32);
        let x0 = if dx < 0 { dx - w - 2 } else { dx - 2 };
        chart.draw_series(std::iter::once(
            EmptyElement::at((t, y.end))
                + Rectangle::new([(x0, 2), (x0 + w + 4, h + 6)], WHITE.mix(0.85).filled())
                + Text::new(label.to_owned(), (dx, 4), font),
        ))?;
    }
    Ok(())
}

/// A linear 2-D chart on a bitmap.
pub type Chart2d<'a> =
    ChartContext<'a, BitMapBackend<'a>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// [`tick`] on an axis spanning `range`: a tick within a millionth of the span from zero is
/// zero (not 3.4e-21 from the float arithmetic of the tick positions).
pub fn tick_on(range: &Range<f64>) -> impl Fn(&f64) -> String {
    let span = (range.end - range.start).abs();
    move |v: &f64| {
        if v.abs() < 1e-6 * span {
            "0".to_owned()
        } else {
            tick(v)
        }
    }
}

/// A tick label with at most three significant digits and no float noise: 0.009, 2.5,
/// 150, 1e-4.
pub fn tick(value: &f64) -> String {
    let v = *value;
    if v == 0.0 || !v.is_finite() {
        return if v.is_finite() {
            "0".into()
        } else {
            v.to_string()
        };
    }
    let magnitude = v.abs().log10().floor() as i32;
    if !(-3..5).contains(&magnitude) {
        let text = format!("{v:.1e}");
        return text.replace(".0e", "e");
    }
    let decimals = (2 - magnitude).max(0) as usize;
    let text = format!("{v:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_short_and_free_of_float_noise() {
        assert_eq!(tick(&0.009000000000000001), "0.009");
        assert_eq!(tick(&0.1), "0.1");
        assert_eq!(tick(&2.5), "2.5");
        assert_eq!(tick(&150.0), "150");
        assert_eq!(tick(&-45.0), "-45");
        assert_eq!(tick(&800.0000000001), "800");
        assert_eq!(tick(&0.0), "0");
        assert_eq!(tick(&1e-4), "1e-4");
        assert_eq!(tick(&123456.0), "1.2e5");
        assert_eq!(tick(&0.04999999), "0.05");
    }

    #[test]
    fn decimation_keeps_every_peak_and_the_ends() {
        // A one-sample spike between two buckets' worth of noise, as the coupled yaw rate.
        let points: Vec<(f64, f64)> = (0..17_201)
            .map(|k| {
                let t = k as f64 * 0.01;
                let y = if k == 637 {
                    28.434
                } else if k == 9_001 {
                    -20.256
                } else {
                    (t * 7.0).sin()
                };
                (t, y)
            })
            .collect();
        let kept = decimate(&points, 1_000);
        assert!(kept.len() <= 4 * 1_000, "{}", kept.len());
        assert!(kept.len() < points.len() / 4);
        assert_eq!(kept[0], points[0]);
        assert_eq!(kept.last(), points.last());
        assert!(kept.contains(&points[637]) && kept.contains(&points[9_001]));
        assert!(kept.windows(2).all(|w| w[0].0 < w[1].0), "in order");
        assert_eq!(decimate(&points[..10], 100), points[..10].to_vec());
        let path: Vec<[f64; 2]> = points.iter().map(|p| [p.1, p.0]).collect();
        let kept = decimate_path(&path, 300, &[|p: &[f64; 2]| p[0], |p: &[f64; 2]| p[1]]);
        assert!(kept.len() <= 6 * 300 && kept.contains(&path[637]) && kept.contains(&path[9_001]));
    }

    #[test]
    fn gaps_and_non_finite_values_break_a_series() {
        let mut points: Vec<(f64, f64)> = (0..10).map(|k| (k as f64, 1.0)).collect();
        points[4].1 = f64::NAN;
        points.extend((30..35).map(|k| (k as f64, 2.0)));
        let pieces = segments(&points);
        let lengths: Vec<usize> = pieces.iter().map(Vec::len).collect();
        assert_eq!(lengths, vec![4, 5, 5]);
        assert_eq!(pieces[2][0], (30.0, 2.0));
        assert!(segments(&[(0.0, f64::NAN)]).is_empty());
        assert_eq!(segments(&[(0.0, 1.0)]).len(), 1);
    }
}

//! One look for every figure: a colour, a line pattern and a marker per law (so a curve under
//! another stays visible, also in grey print), compact tick labels, a plain grid.
use crate::scenarios::Law;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

pub fn colour(law: Law) -> RGBColor {
    match law {
        Law::Coupled => RGBColor(214, 39, 40),
        Law::Decoupled => RGBColor(31, 119, 180),
        Law::Reduced => RGBColor(44, 160, 44),
    }
}

/// Solid lines are stroked as filled polygons: an unfilled thick line comes out as a double
/// outline with plotters' bitmap backend.
pub fn line(law: Law, width: u32) -> ShapeStyle {
    colour(law).filled().stroke_width(width)
}

/// Laws drawn in this order, so the thin dashed decoupled curve lies on top of the others.
pub const DRAW_ORDER: [Law; 3] = [Law::Coupled, Law::Reduced, Law::Decoupled];

/// Pattern of a law's line: coupled solid, reduced long dashes, decoupled short dashes.
pub fn dashes(law: Law) -> Option<(u32, u32)> {
    match law {
        Law::Coupled => None,
        Law::Reduced => Some((14, 6)),
        Law::Decoupled => Some((6, 5)),
    }
}

pub fn width(law: Law) -> u32 {
    match law {
        Law::Coupled => 3,
        Law::Reduced => 3,
        Law::Decoupled => 2,
    }
}

/// Draws a law's curve (with its pattern) and its markers every `len / 10` points, and
/// registers its legend entry.
pub fn draw_law_curve<'a>(
    chart: &mut Chart2d<'a>,
    law: Law,
    points: &[(f64, f64)],
    label: &str,
) -> anyhow::Result<()> {
    let style = line(law, width(law));
    let points: Vec<(f64, f64)> = thin(points)
        .into_iter()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect();
    match dashes(law) {
        None => {
            chart.draw_series(LineSeries::new(points.iter().copied(), style))?;
        }
        Some((dash, gap)) => {
            chart.draw_series(DashedLineSeries::new(
                points.iter().copied(),
                dash,
                gap,
                style,
            ))?;
        }
    }
    let every = (points.len() / 10).max(1);
    let shift = match law {
        Law::Coupled => 0,
        Law::Reduced => every / 3,
        Law::Decoupled => 2 * every / 3,
    };
    let markers: Vec<(f64, f64)> = points.iter().copied().skip(shift).step_by(every).collect();
    chart
        .draw_series(markers.iter().map(|&p| {
            let c = colour(law);
            let show = |on: bool| if on { c.filled() } else { TRANSPARENT.filled() };
            EmptyElement::at(p)
                + Circle::new((0, 0), 5, show(law == Law::Coupled))
                + TriangleMarker::new((0, 0), 7, show(law == Law::Decoupled))
                + Rectangle::new([(-4, -4), (4, 4)], show(law == Law::Reduced))
        }))?
        .label(label.to_owned())
        .legend(move |(x, y)| {
            let c = colour(law);
            let show = |on: bool| if on { c.filled() } else { TRANSPARENT.filled() };
            EmptyElement::at((x, y))
                + PathElement::new(vec![(-8, 0), (16, 0)], style)
                + Circle::new((4, 0), 5, show(law == Law::Coupled))
                + TriangleMarker::new((4, 0), 7, show(law == Law::Decoupled))
                + Rectangle::new([(0, -4), (8, 4)], show(law == Law::Reduced))
        });
    Ok(())
}

/// At most this many points of a curve are drawn.
pub const MAX_POINTS: usize = 800;

/// Every k-th point (and the last) so at most [`MAX_POINTS`] remain: a figure a few hundred
/// pixels wide shows no more, and plotters strokes a thick line through thousands of short
/// segments with jagged spikes.
pub fn thin<T: Copy>(points: &[T]) -> Vec<T> {
    let every = points.len().div_ceil(MAX_POINTS).max(1);
    let mut out: Vec<T> = points.iter().copied().step_by(every).collect();
    if points.len() > 1 && !(points.len() - 1).is_multiple_of(every) {
        out.push(points[points.len() - 1]);
    }
    out
}

/// Markers: a filled circle (coupled), triangle (decoupled) or square (reduced); each marker
/// holds all three shapes, two transparent, so that every law's marker has one type.
/// A linear 2-D chart on a bitmap.
pub type Chart2d<'a> =
    ChartContext<'a, BitMapBackend<'a>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

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
    fn thinning_keeps_the_ends_and_at_most_the_limit() {
        let points: Vec<usize> = (0..17_201).collect();
        let kept = thin(&points);
        assert!(kept.len() <= MAX_POINTS + 1);
        assert_eq!((kept[0], *kept.last().unwrap()), (0, 17_200));
        assert_eq!(thin(&[1, 2, 3]), vec![1, 2, 3]);
    }
}

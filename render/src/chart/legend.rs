//! The legend column: drawn in its own drawing area to the right of the chart, so it never
//! covers data.

use plotters::coord::Shift;
use plotters::prelude::*;

/// The series colours, in series order.
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

/// Colour of series `i`.
pub fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// How a legend entry is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mark {
    /// A solid line sample.
    Line,
    /// A dashed line sample.
    Dashed,
    /// A filled dot.
    Dot,
}

/// One legend entry.
pub struct Entry<'a> {
    /// Text.
    pub name: &'a str,
    /// Colour index.
    pub color: usize,
    /// Sample.
    pub mark: Mark,
}

/// Width (px) of a legend column for these names.
pub fn width(names: &[&str]) -> u32 {
    let longest = names.iter().map(|n| n.chars().count()).max().unwrap_or(0) as u32;
    (44 + 7 * longest).clamp(110, 260)
}

/// Draw `entries` top-down in `area` (the legend column), starting below `top` px.
pub fn draw(
    area: &DrawingArea<SVGBackend, Shift>,
    entries: &[Entry],
    top: i32,
) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    let style = ("sans-serif", 14).into_font().color(&BLACK);
    for (i, e) in entries.iter().enumerate() {
        let y = top + 20 * i as i32;
        let c = color(e.color);
        match e.mark {
            Mark::Line => area.draw(&PathElement::new(vec![(8, y), (32, y)], c.stroke_width(2)))?,
            Mark::Dashed => {
                for x in [8, 20] {
                    area.draw(&PathElement::new(
                        vec![(x, y), (x + 8, y)],
                        c.stroke_width(2),
                    ))?;
                }
            }
            Mark::Dot => area.draw(&Circle::new((20, y), 4, c.filled()))?,
        }
        area.draw(&Text::new(
            e.name.to_string(),
            (38, y),
            style.clone().pos(plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Left,
                plotters::style::text_anchor::VPos::Center,
            )),
        ))?;
    }
    Ok(())
}

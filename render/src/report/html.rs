//! HTML building blocks of the self-contained reports: escaping, the page with its inline
//! style sheet, sections, tables and figures. No scripts, fonts, images or links to the network.

use std::fmt::Write;

/// `s` with the five HTML special characters escaped (text and attribute values).
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(c),
        }
    }
    out
}

const STYLE: &str = "
body { font-family: sans-serif; margin: 24px auto; max-width: 1180px; color: #222; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { font-size: 1.25em; border-bottom: 1px solid #ccc; padding-bottom: 4px; margin-top: 1.8em; }
h3 { font-size: 1.05em; margin: 1em 0 0.4em; }
p.note { color: #555; font-size: 0.92em; }
table { border-collapse: collapse; margin: 8px 0 16px; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 4px 8px; text-align: right; }
th { background: #f2f2f2; }
td.l, th.l { text-align: left; }
.ok { color: #1a7f37; font-weight: bold; }
.bad { color: #c62828; font-weight: bold; }
.warn { color: #b26a00; font-weight: bold; }
.figs { display: grid; grid-template-columns: repeat(auto-fill, minmax(540px, 1fr)); gap: 10px; }
.fig svg { width: 100%; height: auto; border: 1px solid #eee; }
.fig.wide { grid-column: 1 / -1; max-width: 1000px; }
nav.toc { background: #f7f7f7; padding: 8px 16px; border: 1px solid #ddd; }
nav.toc ol { margin: 4px 0; }
p.bad { color: #c62828; }
p.warn { color: #b26a00; }
pre { background: #f7f7f7; padding: 10px; overflow-x: auto; font-size: 0.85em; }
";

/// A complete page: `title` (escaped) and `body` (HTML).
pub fn page(title: &str, body: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n<h1>{}</h1>\n{body}</body>\n</html>\n",
        escape(title),
        escape(title)
    )
}

/// A section with anchor `id`, heading `heading` (escaped) and HTML `content`.
pub fn section(id: &str, heading: &str, content: &str) -> String {
    format!(
        "<section id=\"{}\">\n<h2>{}</h2>\n{content}</section>\n",
        escape(id),
        escape(heading)
    )
}

/// The table of contents: a link to each `(anchor, heading)` of `entries`, and under the entry
/// whose anchor is `nested_under` a link to each of `nested` (a section's subsections).
pub fn toc(
    entries: &[(String, String)],
    nested_under: &str,
    nested: &[(String, String)],
) -> String {
    let link = |(id, heading): &(String, String)| {
        format!("<a href=\"#{}\">{}</a>", escape(id), escape(heading))
    };
    let mut s = String::from("<nav class=\"toc\">\n<b>Contents</b>\n<ol>\n");
    for e in entries {
        s += &format!("<li>{}", link(e));
        if e.0 == nested_under && !nested.is_empty() {
            let inner: Vec<String> = nested.iter().map(link).collect();
            s += &format!(": {}", inner.join(", "));
        }
        s += "</li>\n";
    }
    s += "</ol>\n</nav>\n";
    s
}

/// A paragraph of escaped text.
pub fn note(text: &str) -> String {
    format!("<p class=\"note\">{}</p>\n", escape(text))
}

/// One table cell: its text (escaped) and an optional CSS class.
pub struct Cell {
    /// Text.
    pub text: String,
    /// CSS class (`l`, `ok`, `bad`, `warn`) or empty.
    pub class: &'static str,
}

impl Cell {
    /// A right-aligned cell.
    pub fn num(text: impl Into<String>) -> Cell {
        Cell {
            text: text.into(),
            class: "",
        }
    }

    /// A left-aligned cell.
    pub fn text(text: impl Into<String>) -> Cell {
        Cell {
            text: text.into(),
            class: "l",
        }
    }
}

/// A table with a header row.
pub fn table(header: &[&str], rows: &[Vec<Cell>]) -> String {
    let mut s = String::from("<table>\n<tr>");
    for (i, h) in header.iter().enumerate() {
        let class = if i == 0 { " class=\"l\"" } else { "" };
        let _ = write!(s, "<th{class}>{}</th>", escape(h));
    }
    s.push_str("</tr>\n");
    for row in rows {
        s.push_str("<tr>");
        for c in row {
            if c.class.is_empty() {
                let _ = write!(s, "<td>{}</td>", escape(&c.text));
            } else {
                let _ = write!(s, "<td class=\"{}\">{}</td>", c.class, escape(&c.text));
            }
        }
        s.push_str("</tr>\n");
    }
    s.push_str("</table>\n");
    s
}

/// Figures wider than this (px) get a row of their own ([`figures`]).
pub const WIDE_FIGURE_PX: u32 = 600;

/// The `width` attribute of an SVG's root element, in px.
fn svg_width(svg: &str) -> Option<u32> {
    let tag = &svg[svg.find("<svg")?..];
    let tag = &tag[..tag.find('>')?];
    let at = tag.find(" width=\"")? + " width=\"".len();
    let end = tag[at..].find('"')? + at;
    tag[at..end].trim_end_matches("px").parse().ok()
}

/// Inline SVG figures in a responsive grid (two columns of at least 540 px). A figure wider than
/// [`WIDE_FIGURE_PX`] (the 900-px RMSE, NEES, NIS and density plots) takes a whole row, so it is
/// never drawn below its own size and its 13–15 px labels stay legible. The SVG text comes from
/// plotters, which escapes its text content.
pub fn figures<'a>(svgs: impl IntoIterator<Item = &'a str>) -> String {
    let mut s = String::from("<div class=\"figs\">\n");
    for svg in svgs {
        let body = svg.find("<svg").map_or(svg, |i| &svg[i..]).trim_end();
        let class = match svg_width(body) {
            Some(w) if w > WIDE_FIGURE_PX => "fig wide",
            _ => "fig",
        };
        let _ = writeln!(s, "<div class=\"{class}\">{body}</div>");
    }
    s.push_str("</div>\n");
    s
}

/// A value with 4 significant digits (engineering exponent outside 1e-3..1e5); `–` for none.
pub fn num(v: Option<f64>) -> String {
    match v {
        Some(x) if !x.is_finite() => x.to_string(),
        Some(x) if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e5) => format!("{x:.3e}"),
        Some(x) => {
            let digits = (3 - x.abs().max(1e-300).log10().floor() as i32).clamp(0, 6) as usize;
            format!("{x:.digits$}")
        }
        None => "–".into(),
    }
}

/// A JSON value pretty-printed, escaped, in a `<pre>` block.
pub fn json_block(v: &serde_json::Value) -> String {
    let text = serde_json::to_string_pretty(v).unwrap_or_else(|e| format!("({e})"));
    format!("<pre>{}</pre>\n", escape(&text))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_markup_in_text() {
        assert_eq!(
            escape("<script>alert('x') & \"y\"</script>"),
            "&lt;script&gt;alert(&#39;x&#39;) &amp; &quot;y&quot;&lt;/script&gt;"
        );
        let t = table(&["a<b"], &[vec![Cell::text("<i>")]]);
        assert!(t.contains("a&lt;b") && t.contains("&lt;i&gt;") && !t.contains("<i>"));
    }

    #[test]
    fn wide_figures_take_a_row_so_their_labels_are_not_shrunk() {
        use crate::chart::{Curve, Frame, line_chart};
        let chart = |size| {
            let frame = Frame {
                title: "mean NEES over runs",
                x_label: "time (s)",
                y_label: "NEES (1)",
                log_y: true,
                size,
            };
            let curve = Curve {
                name: "ekf".into(),
                points: vec![(0.0, 1.0), (10.0, 2.0)],
                dashed: false,
                color: None,
            };
            line_chart(&frame, &[curve]).unwrap().unwrap()
        };
        let (wide, small) = (
            chart(crate::trade_figures::WIDE),
            chart(crate::trade_figures::SMALL),
        );
        assert_eq!(svg_width(&wide), Some(crate::trade_figures::WIDE.0));
        let html = figures([wide.as_str(), small.as_str()]);
        assert_eq!(html.matches("<div class=\"fig wide\">").count(), 1);
        assert_eq!(html.matches("<div class=\"fig\">").count(), 1);
        // The page's column is at most 1180 px: a wide figure in its own row shows at least at
        // 1000/900 of its size; in a grid cell (2 columns of ≥ 540 px) it would shrink to ~0.6.
        assert!(STYLE.contains(".fig.wide { grid-column: 1 / -1;"));
    }

    #[test]
    fn numbers_have_four_significant_digits() {
        assert_eq!(num(Some(1234.5678)), "1235");
        assert_eq!(num(Some(0.012345)), "0.01235");
        assert_eq!(num(Some(3.0000000000000004e-5)), "3.000e-5");
        assert_eq!(num(None), "–");
    }
}

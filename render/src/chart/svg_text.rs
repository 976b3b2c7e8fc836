//! Test support: the `<text>` elements of an SVG produced by plotters, with their position, so
//! tests can check tick labels, axis labels and the legend's place.

/// One text element.
#[derive(Debug, Clone)]
pub struct SvgText {
    /// `x` attribute [px].
    pub x: f64,
    /// `y` attribute [px].
    pub y: f64,
    /// Rotated (the y axis label).
    pub rotated: bool,
    /// `text-anchor`: `start` (legend), `middle` (caption, x ticks, axis labels), `end` (y ticks).
    pub anchor: String,
    /// Content, entities decoded.
    pub text: String,
}

fn attr(tag: &str, name: &str) -> Option<String> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    let end = tag[start..].find('"')? + start;
    Some(tag[start..end].to_string())
}

/// Every `<text>` element of `svg`.
pub fn texts(svg: &str) -> Vec<SvgText> {
    let mut out = Vec::new();
    let mut rest = svg;
    while let Some(i) = rest.find("<text") {
        rest = &rest[i..];
        let Some(close) = rest.find('>') else { break };
        let tag = &rest[..close];
        let Some(end) = rest.find("</text>") else {
            break;
        };
        let text = rest[close + 1..end]
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&quot;", "\"")
            .replace("&#39;", "'")
            .replace("&amp;", "&")
            .trim()
            .to_string();
        out.push(SvgText {
            x: attr(tag, "x")
                .and_then(|v| v.parse().ok())
                .unwrap_or(f64::NAN),
            y: attr(tag, "y")
                .and_then(|v| v.parse().ok())
                .unwrap_or(f64::NAN),
            rotated: tag.contains("rotate("),
            anchor: attr(tag, "text-anchor").unwrap_or_default(),
            text,
        });
        rest = &rest[end..];
    }
    out
}

/// Width of the SVG canvas [px].
pub fn width(svg: &str) -> f64 {
    attr(svg, "width")
        .and_then(|v| v.parse().ok())
        .unwrap_or(f64::NAN)
}

/// Whether `s` reads as a tick label (a number in plain or engineering notation).
pub fn is_number(s: &str) -> bool {
    !s.is_empty() && s.parse::<f64>().is_ok()
}

/// Whether a label shows float noise: six or more repeated 0s or 9s in its digits.
pub fn has_float_noise(s: &str) -> bool {
    s.contains("000000") || s.contains("999999")
}

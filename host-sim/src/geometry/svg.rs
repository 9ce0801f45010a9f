//! SVG drawings of sections: stock circle, finished section, tip traces.

use std::fmt::Write;

/// One drawing in mm, centred on the work axis, scaled to `size` pixels.
pub struct Drawing {
    half_mm: f64,
    size: f64,
    body: String,
}

impl Drawing {
    pub fn new(half_mm: f64, size: f64) -> Drawing {
        Drawing { half_mm, size, body: String::new() }
    }

    fn px(&self, x: f64, y: f64) -> (f64, f64) {
        let s = self.size / (2.0 * self.half_mm);
        (self.size / 2.0 + x * s, self.size / 2.0 - y * s)
    }

    pub fn circle(&mut self, r: f64, style: &str) {
        let (cx, cy) = self.px(0.0, 0.0);
        let rp = r * self.size / (2.0 * self.half_mm);
        let _ = writeln!(self.body, r#"<circle cx="{cx:.2}" cy="{cy:.2}" r="{rp:.2}" {style}/>"#);
    }

    /// A polyline of (x, y) points in mm; `closed` joins the last to the first.
    pub fn path(&mut self, points: &[(f64, f64)], closed: bool, style: &str) {
        let mut d = String::new();
        for (i, &(x, y)) in points.iter().enumerate() {
            let (u, v) = self.px(x, y);
            let _ = write!(d, "{}{u:.2},{v:.2} ", if i == 0 { "M" } else { "L" });
        }
        if closed {
            d.push('Z');
        }
        let _ = writeln!(self.body, r#"<path d="{d}" {style}/>"#);
    }

    /// A line of text at the top left; keep it within `TEXT_CHARS_MAX`
    /// characters for a 560-pixel drawing, or it runs off the edge.
    pub fn text(&mut self, line: usize, text: &str) {
        let y = 18.0 + 16.0 * line as f64;
        let _ = writeln!(self.body, r#"<text x="8" y="{y}" font-family="monospace" font-size="13">{text}</text>"#);
    }

    /// Raw SVG (already in pixels) appended below the section.
    pub fn raw(&mut self, svg: &str) {
        self.body.push_str(svg);
    }

    pub fn finish(&self, height: f64) -> String {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{height}\" viewBox=\"0 0 {w} {height}\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n{}</svg>\n",
            self.body,
            w = self.size
        )
    }
}

/// Points of an envelope as a closed outline.
pub fn outline(env: &super::Envelope) -> Vec<(f64, f64)> {
    (0..env.bins())
        .step_by((env.bins() / 2048).max(1))
        .map(|i| {
            let (t, r) = (env.angle(i), env.radius[i]);
            (r * t.cos(), r * t.sin())
        })
        .collect()
}

/// A monospace character's advance at font-size 13, pixels: 0.6 em in
/// DejaVu Sans Mono and Liberation Mono, rounded up for the other faces.
pub const CHAR_PX: f64 = 0.62 * 13.0;

/// The `<text>` lines of an SVG that run past its width (x + characters x
/// `CHAR_PX`), each with how far: for the tests of every drawing's text.
pub fn text_overflow(svg: &str) -> Vec<String> {
    let attr = |tag: &str, name: &str| -> Option<f64> {
        let at = tag.find(&format!(" {name}=\""))? + name.len() + 3;
        tag[at..].split('"').next()?.parse().ok()
    };
    let Some(width) = svg.split_once("<svg").and_then(|(_, t)| attr(t.split('>').next()?, "width")) else {
        return vec!["no width".into()];
    };
    let mut over = Vec::new();
    for part in svg.split("<text").skip(1) {
        let Some((tag, rest)) = part.split_once('>') else { continue };
        let text = rest.split("</text>").next().unwrap_or("");
        let anchor_end = tag.contains(r#"text-anchor="end""#) || tag.contains(r#"text-anchor="middle""#);
        let right =
            attr(tag, "x").unwrap_or(0.0) + if anchor_end { 0.0 } else { CHAR_PX * text.chars().count() as f64 };
        if right > width {
            over.push(format!("{text:?} ends at {right:.0} px, past the width {width}"));
        }
    }
    over
}

#[cfg(test)]
mod tests {
    #[test]
    fn text_past_the_width_is_found() {
        let line = |n: usize| {
            format!(r#"<svg xmlns="x" width="560" height="9"><text x="8" y="18">{}</text></svg>"#, "a".repeat(n))
        };
        assert!(super::text_overflow(&line(68)).is_empty());
        assert_eq!(super::text_overflow(&line(69)).len(), 1);
    }
}

//! A minimal XML element tree with deterministic, indented output: enough for URDF and MJCF.

/// An XML element with attributes in insertion order and child elements.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Element {
    name: &'static str,
    attributes: Vec<(&'static str, String)>,
    children: Vec<Element>,
}

impl Element {
    pub(crate) fn new(name: &'static str) -> Self {
        Self {
            name,
            attributes: Vec::new(),
            children: Vec::new(),
        }
    }

    /// Adds an attribute (builder style).
    pub(crate) fn attr(mut self, key: &'static str, value: impl Into<String>) -> Self {
        self.attributes.push((key, value.into()));
        self
    }

    /// Adds a child (builder style).
    pub(crate) fn child(mut self, child: Element) -> Self {
        self.children.push(child);
        self
    }

    /// Adds a child in place.
    pub(crate) fn push(&mut self, child: Element) {
        self.children.push(child);
    }

    /// Serialises with an XML declaration and two-space indentation.
    pub(crate) fn to_document(&self) -> String {
        let mut out = String::from("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
        self.write(&mut out, 0);
        out
    }

    fn write(&self, out: &mut String, depth: usize) {
        let indent = "  ".repeat(depth);
        out.push_str(&indent);
        out.push('<');
        out.push_str(self.name);
        for (k, v) in &self.attributes {
            out.push(' ');
            out.push_str(k);
            out.push_str("=\"");
            out.push_str(&escape(v));
            out.push('"');
        }
        if self.children.is_empty() {
            out.push_str("/>\n");
            return;
        }
        out.push_str(">\n");
        for c in &self.children {
            c.write(out, depth + 1);
        }
        out.push_str(&indent);
        out.push_str("</");
        out.push_str(self.name);
        out.push_str(">\n");
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Coordinates below this magnitude are written as 0: transform round-off (1e-14 m, 1e-27 in an
/// axis), not data. Masses and inertias are never snapped: a 1 mm part has an inertia of 1e-13.
const SNAP_TO_ZERO_M: f64 = 1e-12;

/// Formats a number for XML and OBJ: at most 10 significant digits, no exponent, no `-0`.
pub(crate) fn num(x: f64) -> String {
    let rounded: f64 = format!("{x:.9e}").parse().unwrap_or(x);
    if rounded == 0.0 {
        "0".to_owned()
    } else {
        format!("{rounded}")
    }
}

/// Formats a coordinate or direction component: like [`num`], with round-off snapped to 0.
pub(crate) fn coord(x: f64) -> String {
    if x.abs() < SNAP_TO_ZERO_M {
        "0".to_owned()
    } else {
        num(x)
    }
}

/// Space-separated coordinates (see [`coord`]).
pub(crate) fn coords(xs: &[f64]) -> String {
    xs.iter().map(|&x| coord(x)).collect::<Vec<_>>().join(" ")
}

/// A colour as four space-separated numbers, each in its shortest `f32` form (`0.48`, not
/// `0.4799999893`).
pub(crate) fn rgba(c: [f32; 4]) -> String {
    c.map(short_f32).join(" ")
}

/// An `f32` in its shortest form, `0` for either zero.
pub(crate) fn short_f32(v: f32) -> String {
    if v == 0.0 {
        "0".to_owned()
    } else {
        format!("{v}")
    }
}

/// Space-separated numbers.
pub(crate) fn nums(xs: &[f64]) -> String {
    xs.iter().map(|&x| num(x)).collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elements_nest_escape_and_indent() {
        let doc = Element::new("robot")
            .attr("name", "a<b&\"c\"")
            .child(Element::new("link").attr("name", "x"))
            .to_document();
        assert_eq!(
            doc,
            "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<robot name=\"a&lt;b&amp;&quot;c&quot;\">\n  <link name=\"x\"/>\n</robot>\n"
        );
    }

    #[test]
    fn numbers_are_short_and_never_negative_zero() {
        assert_eq!(num(0.1 + 0.2), "0.3");
        assert_eq!(num(-0.0), "0");
        assert_eq!(num(1e-7), "0.0000001");
        assert_eq!(coord(4.2e-27), "0");
        assert_eq!(num(2e-13), "0.0000000000002");
        assert_eq!(coords(&[1e-14, 0.5]), "0 0.5");
        assert_eq!(nums(&[1.0, -2.5]), "1 -2.5");
        assert_eq!(rgba([0.48, 0.26, -0.0, 1.0]), "0.48 0.26 0 1");
    }
}

//! The one range check of scenario validation: a [`Range`] holds its two limits (each inclusive
//! or exclusive, or absent), its unit and a note, checks a value and writes its own message, so
//! what a user reads ("must be > 0 and <= 7200 s") and what is checked cannot disagree.

use super::error::ScenarioError;
use std::fmt::{self, Display};

/// The result of one section's checks: the first error, naming field, value and range.
pub(super) type R = Result<(), ScenarioError>;

/// One end of a [`Range`].
#[derive(Debug, Clone, PartialEq)]
pub struct Limit {
    /// The limit itself.
    pub value: f64,
    /// Whether the limit itself is allowed.
    pub inclusive: bool,
    /// What the limit is when it is not a constant, e.g. `timing.duration_s` or `the surface`.
    pub name: Option<String>,
}

/// A limit that comes from another field or the planet, written `name = value`.
#[derive(Debug, Clone, PartialEq)]
pub struct Named(String, f64);

/// The limit `value`, written `name = value` in messages.
pub fn named(name: impl Into<String>, value: f64) -> Named {
    Named(name.into(), value)
}

/// A limit given as a number or as [`named`].
pub trait IntoLimit {
    /// The limit, inclusive or not.
    fn limit(self, inclusive: bool) -> Limit;
}

impl IntoLimit for f64 {
    fn limit(self, inclusive: bool) -> Limit {
        Limit {
            value: self,
            inclusive,
            name: None,
        }
    }
}

impl IntoLimit for Named {
    fn limit(self, inclusive: bool) -> Limit {
        Limit {
            value: self.1,
            inclusive,
            name: Some(self.0),
        }
    }
}

/// The allowed values of one field: finite, above `lo` and below `hi` (a missing limit only
/// asks for a finite value).
#[derive(Debug, Clone, PartialEq)]
pub struct Range {
    /// Lower limit.
    pub lo: Option<Limit>,
    /// Upper limit.
    pub hi: Option<Limit>,
    /// Unit written after the last number, e.g. `s` or `°` (empty for none).
    pub unit: &'static str,
    /// What the range is about when it is not the field itself, e.g. `a 1σ` or `its norm`.
    pub subject: Option<&'static str>,
    /// A remark written in parentheses after the range, e.g. `a variance`.
    pub note: Option<&'static str>,
}

/// Values a [`Range`] can check: real numbers and counts.
pub trait RangeValue: Copy + Display {
    /// The value as a real number for the comparison.
    fn real(self) -> f64;
}

impl RangeValue for f64 {
    fn real(self) -> f64 {
        self
    }
}

impl RangeValue for usize {
    fn real(self) -> f64 {
        // Exact up to 2^53; every count limit is far below that, and rounding keeps the order.
        self as f64
    }
}

impl Range {
    fn from_lo(lo: Limit) -> Self {
        Range {
            lo: Some(lo),
            hi: None,
            unit: "",
            subject: None,
            note: None,
        }
    }

    /// Values `> lo`.
    pub fn gt(lo: impl IntoLimit) -> Self {
        Self::from_lo(lo.limit(false))
    }

    /// Values `>= lo`.
    pub fn ge(lo: impl IntoLimit) -> Self {
        Self::from_lo(lo.limit(true))
    }

    /// Values from `-bound` to `bound`, both included ("within ±bound").
    pub fn within(bound: f64) -> Self {
        Self::ge(-bound).le(bound)
    }

    /// Values strictly between `-bound` and `bound`.
    pub fn strictly_within(bound: f64) -> Self {
        Self::gt(-bound).lt(bound)
    }

    /// Also `< hi`.
    pub fn lt(mut self, hi: impl IntoLimit) -> Self {
        self.hi = Some(hi.limit(false));
        self
    }

    /// Also `<= hi`.
    pub fn le(mut self, hi: impl IntoLimit) -> Self {
        self.hi = Some(hi.limit(true));
        self
    }

    /// With the unit written after the last number.
    pub fn unit(mut self, unit: &'static str) -> Self {
        self.unit = unit;
        self
    }

    /// About `subject` (e.g. `a 1σ`) rather than the field itself.
    pub fn of(mut self, subject: &'static str) -> Self {
        self.subject = Some(subject);
        self
    }

    /// With a remark in parentheses after the range.
    pub fn note(mut self, note: &'static str) -> Self {
        self.note = Some(note);
        self
    }

    /// Is `v` finite and inside both limits?
    pub fn contains(&self, v: f64) -> bool {
        let above = |l: &Limit| {
            if l.inclusive {
                v >= l.value
            } else {
                v > l.value
            }
        };
        let below = |l: &Limit| {
            if l.inclusive {
                v <= l.value
            } else {
                v < l.value
            }
        };
        v.is_finite() && self.lo.as_ref().is_none_or(above) && self.hi.as_ref().is_none_or(below)
    }

    /// `Ok` when `v` is inside, else [`ScenarioError::OutOfRange`] naming `field`, `v` and this
    /// range in words.
    pub fn check(&self, field: &str, v: impl RangeValue) -> Result<(), ScenarioError> {
        if self.contains(v.real()) {
            Ok(())
        } else {
            Err(ScenarioError::range(field, v, self.to_string()))
        }
    }
}

/// A number as a limit is written: plain, or with an exponent when very large or small.
fn number(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e7).contains(&a) {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}

impl Display for Limit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.name {
            Some(name) => write!(f, "{name} = {}", number(self.value)),
            None => f.write_str(&number(self.value)),
        }
    }
}

/// Writes the range as its messages say it: `must be > 0 and <= 7200 s`.
impl Display for Range {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(s) = self.subject {
            write!(f, "{s} ")?;
        }
        f.write_str("must be")?;
        let mut sep = " ";
        if let Some(lo) = &self.lo {
            write!(f, "{sep}{} {lo}", if lo.inclusive { ">=" } else { ">" })?;
            sep = " and ";
        }
        if let Some(hi) = &self.hi {
            write!(f, "{sep}{} {hi}", if hi.inclusive { "<=" } else { "<" })?;
        }
        if !self.unit.is_empty() {
            let space = if self.unit.starts_with('°') { "" } else { " " };
            write!(f, "{space}{}", self.unit)?;
        }
        if self.lo.is_none() || self.hi.is_none() {
            f.write_str(" and finite")?;
        }
        if let Some(note) = self.note {
            write!(f, " ({note})")?;
        }
        Ok(())
    }
}

/// One range check that validation made: the field, the value it had and the range.
#[derive(Debug, Clone, PartialEq)]
pub struct RangeCheck {
    /// Dotted path of the field, e.g. `filter.p0_diag[3]`.
    pub field: String,
    /// The value checked, as written in a message.
    pub value: String,
    /// The allowed range.
    pub range: Range,
}

/// Applies range checks, and lists them when asked to ([`super::ScenarioConfig::range_checks`]).
#[derive(Debug, Default)]
pub struct Checker {
    seen: Option<Vec<RangeCheck>>,
}

impl Checker {
    /// A checker that only checks.
    pub fn new() -> Self {
        Checker::default()
    }

    /// A checker that also lists every check it makes.
    pub fn listing() -> Self {
        Checker {
            seen: Some(Vec::new()),
        }
    }

    /// The checks made so far (empty unless [`Checker::listing`]).
    pub fn into_checks(self) -> Vec<RangeCheck> {
        self.seen.unwrap_or_default()
    }

    /// Check `v` against `range` for `field`.
    pub fn range(
        &mut self,
        field: impl Into<String>,
        v: impl RangeValue,
        range: Range,
    ) -> Result<(), ScenarioError> {
        let field = field.into();
        range.check(&field, v)?;
        if let Some(seen) = &mut self.seen {
            seen.push(RangeCheck {
                field,
                value: v.to_string(),
                range,
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_say_what_is_checked() {
        let r = Range::gt(0.0).le(7200.0).unit("s");
        assert_eq!(r.to_string(), "must be > 0 and <= 7200 s");
        assert!(r.contains(7200.0) && !r.contains(7200.000000000001));
        assert!(!r.contains(0.0) && r.contains(f64::MIN_POSITIVE));
        assert!(!r.contains(f64::NAN));
        let r = Range::within(180.0).unit("°");
        assert_eq!(r.to_string(), "must be >= -180 and <= 180°");
        assert!(r.contains(-180.0) && r.contains(180.0) && !r.contains(180.00000000000003));
        let r = Range::ge(0.0).of("a 1σ").lt(1e4);
        assert_eq!(r.to_string(), "a 1σ must be >= 0 and < 10000");
        let r = Range::gt(0.0).note("a variance");
        assert_eq!(r.to_string(), "must be > 0 and finite (a variance)");
        assert!(r.contains(1e300) && !r.contains(f64::INFINITY));
        let r = Range::gt(1e9).lt(1e17).unit("m³/s²");
        assert_eq!(r.to_string(), "must be > 1e9 and < 1e17 m³/s²");
        let r = Range::gt(0.0)
            .le(named("timing.duration_s", 300.0))
            .unit("s");
        assert_eq!(
            r.to_string(),
            "must be > 0 and <= timing.duration_s = 300 s"
        );
    }

    #[test]
    fn the_error_names_field_value_and_range() {
        let e = Range::gt(0.0)
            .le(7200.0)
            .unit("s")
            .check("timing.duration_s", 7200.5);
        assert_eq!(
            e.unwrap_err().to_string(),
            "timing.duration_s = 7200.5 is out of range: must be > 0 and <= 7200 s"
        );
        let e = Range::ge(1.0).le(1e6).check("monte_carlo.runs", 0usize);
        assert_eq!(
            e.unwrap_err().to_string(),
            "monte_carlo.runs = 0 is out of range: must be >= 1 and <= 1000000"
        );
    }

    #[test]
    fn a_listing_checker_lists_passed_checks_and_stops_at_a_failure() {
        let mut c = Checker::listing();
        c.range("a", 1.0, Range::gt(0.0)).unwrap();
        assert!(c.range("b", -1.0, Range::gt(0.0)).is_err());
        let seen = c.into_checks();
        assert_eq!(seen.len(), 1);
        assert_eq!((seen[0].field.as_str(), seen[0].value.as_str()), ("a", "1"));
    }
}
